'use strict';
async function refresh() {
  const log = await TA.load('/api/audit?limit=500');
  if (!log) return;
  document.querySelector('#audit tbody').replaceChildren(...log.entries.map((e) => TA.el('tr', {},
    TA.el('td', {}, e.time_utc), TA.el('td', {}, e.user), TA.el('td', {}, e.role), TA.el('td', {}, e.remote),
    TA.el('td', {}, e.action), TA.el('td', {}, e.target), TA.el('td', { class: 'mono' }, e.detail), TA.el('td', {}, e.outcome))));
}
TA.init('audit').then(refresh).catch((e) => TA.status(e.message, true));
