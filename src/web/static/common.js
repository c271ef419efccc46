'use strict';
// Shared by every page: the API call (session cookie + CSRF header), the page header, helpers.
// No inline script anywhere (the Content-Security-Policy forbids it); text goes in with textContent.
const TA = {
  session: null,

  async api(method, path, body) {
    const opts = { method, headers: {}, credentials: 'same-origin' };
    if (method !== 'GET') {
      opts.headers['X-CSRF-Token'] = TA.session ? TA.session.csrf : '';
      if (body !== undefined) {
        opts.headers['Content-Type'] = 'application/json';
        opts.body = JSON.stringify(body);
      }
    }
    const r = await fetch(path, opts);
    if (r.status === 401 && path !== '/api/login') {
      location.href = '/login.html';
      throw new Error('not logged in');
    }
    const type = r.headers.get('Content-Type') || '';
    const j = type.startsWith('application/json') ? await r.json() : null;
    if (!r.ok) throw new Error(j && j.error ? j.error : r.status + ' ' + r.statusText);
    return j;
  },

  el(tag, attrs, ...children) {
    const e = document.createElement(tag);
    for (const [k, v] of Object.entries(attrs || {})) {
      if (k === 'class') e.className = v;
      else if (k === 'on') for (const [ev, fn] of Object.entries(v)) e.addEventListener(ev, fn);
      else e.setAttribute(k, v);
    }
    for (const c of children) if (c !== null && c !== undefined) e.append(c instanceof Node ? c : String(c));
    return e;
  },

  num(v, digits) { return v === null || v === undefined ? '—' : Number(v).toFixed(digits); },
  time(unix) { return new Date(unix * 1000).toISOString().replace('T', ' ').slice(0, 19) + ' UTC'; },

  status(text, isError) {
    const s = document.getElementById('status');
    if (!s) return;
    s.textContent = text;
    s.className = isError ? 'status error' : 'status ok';
  },

  // A GET whose failure is reported in the status line (null then).
  async load(path) {
    try {
      return await TA.api('GET', path);
    } catch (e) {
      TA.status(e.message, true);
      return null;
    }
  },

  // Runs an operation and reports its outcome in the status line.
  async operate(what, method, path, body) {
    try {
      await TA.api(method, path, body);
      TA.status(what + ': done', false);
      return true;
    } catch (e) {
      TA.status(what + ': refused — ' + e.message, true);
      return false;
    }
  },

  async init(active) {
    TA.session = await TA.api('GET', '/api/session');
    const nav = document.getElementById('nav');
    const links = [['overview', '/overview.html', 'Shop'], ['alarms', '/alarms.html', 'Alarms'],
                   ['audit', '/audit.html', 'Audit log']];
    for (const [key, href, label] of links)
      nav.append(TA.el('a', { href, class: key === active ? 'active' : '' }, label));
    const logout = TA.el('button', { id: 'logout', type: 'button' }, 'Log out');
    logout.addEventListener('click', async () => {
      try { await TA.api('POST', '/api/logout'); } finally { location.href = '/login.html'; }
    });
    nav.append(TA.el('span', { class: 'who', id: 'who' }, TA.session.user + ' (' + TA.session.role + ')'), logout);
    document.getElementById('backend').textContent = TA.session.backend;
  },
};
