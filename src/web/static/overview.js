'use strict';
// The shop overview: sorted, filtered and paged on the server, refreshed every 2 s.
const state = { sort: 'id', order: 'asc', offset: 0, limit: 100 };

async function refresh() {
  const q = new URLSearchParams({
    sort: state.sort, order: state.order, offset: state.offset, limit: state.limit,
    filter: document.getElementById('filter').value,
    alarms: document.getElementById('alarms-only').checked ? '1' : '0',
    disconnected: document.getElementById('disconnected-only').checked ? '1' : '0',
  });
  const page = await TA.load('/api/machines?' + q);
  if (!page) return;
  const body = document.querySelector('#machines tbody');
  body.replaceChildren();
  for (const m of page.machines) {
    const temps = m.channels.map((c) => c.name + ' ' + TA.num(c.temp_c, 2) + (c.health !== 'ok' ? ' (' + c.health + ')' : '')).join('  ');
    const corr = m.axes.map((a) => a.name + ' ' + (a.enabled ? '' : 'off ') + TA.num(a.correction_um, 1)).join('  ');
    body.append(TA.el('tr', { class: m.alarms.length ? 'alarm' : '' },
      TA.el('td', {}, TA.el('a', { href: '/machine.html?id=' + encodeURIComponent(m.id) }, m.id)),
      TA.el('td', {}, m.name),
      TA.el('td', { class: m.connected ? 'ok' : 'bad' }, m.connected ? 'connected' : 'lost'),
      TA.el('td', {}, m.alarms.join(', ')),
      TA.el('td', {}, m.model.revision),
      TA.el('td', {}, m.coolant),
      TA.el('td', { class: 'mono' }, temps),
      TA.el('td', { class: 'mono' }, corr)));
  }
  const last = Math.min(page.offset + page.machines.length, page.matched);
  document.getElementById('page-info').textContent =
    ' ' + (page.matched ? page.offset + 1 : 0) + '–' + last + ' of ' + page.matched + ' (shop: ' + page.total + ') ';
  state.matched = page.matched;
}

for (const th of document.querySelectorAll('th[data-sort]')) {
  th.addEventListener('click', () => {
    const key = th.getAttribute('data-sort');
    state.order = state.sort === key && state.order === 'asc' ? 'desc' : 'asc';
    state.sort = key;
    for (const h of document.querySelectorAll('th[data-sort]')) h.classList.remove('asc', 'desc');
    th.classList.add(state.order);
    refresh();
  });
}
for (const id of ['filter', 'alarms-only', 'disconnected-only'])
  document.getElementById(id).addEventListener('input', () => { state.offset = 0; refresh(); });
document.getElementById('prev').addEventListener('click', () => { state.offset = Math.max(0, state.offset - state.limit); refresh(); });
document.getElementById('next').addEventListener('click', () => {
  if (state.offset + state.limit < (state.matched || 0)) state.offset += state.limit;
  refresh();
});

TA.init('overview').then(() => { refresh(); setInterval(refresh, 2000); }).catch((e) => TA.status(e.message, true));
