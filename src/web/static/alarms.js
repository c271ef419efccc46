'use strict';
async function refresh() {
  const list = await TA.load('/api/alarms?limit=500');
  if (!list) return;
  const body = document.querySelector('#alarms tbody');
  body.replaceChildren(...list.alarms.map((a) => {
    let ack = '';
    if (!a.acknowledged) {
      ack = TA.el('button', { type: 'button', class: 'ack', 'data-id': a.id }, 'Acknowledge');
      ack.addEventListener('click', async () => {
        await TA.operate('acknowledge ' + a.id, 'POST', '/api/alarms/' + encodeURIComponent(a.id) + '/ack');
        refresh();
      });
    }
    return TA.el('tr', { class: a.active ? 'alarm' : '' }, TA.el('td', {}, TA.time(a.raised_unix_s)),
      TA.el('td', {}, TA.el('a', { href: '/machine.html?id=' + encodeURIComponent(a.machine_id) }, a.machine_id)),
      TA.el('td', {}, a.name + (a.message ? ' — ' + a.message : '')), TA.el('td', {}, a.active ? 'active' : 'cleared'),
      TA.el('td', {}, a.acknowledged ? a.acknowledged_by + ', ' + TA.time(a.acknowledged_unix_s) : 'no'), TA.el('td', {}, ack));
  }));
}
TA.init('alarms').then(() => { refresh(); setInterval(refresh, 3000); }).catch((e) => TA.status(e.message, true));
