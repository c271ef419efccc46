'use strict';
// One machine: live charts by short polling (/live?after=<last sequence>, every second), the
// operations of its role, the model and its figures, history charts for a chosen range.
const id = new URLSearchParams(location.search).get('id') || '';
const base = '/api/machines/' + encodeURIComponent(id);
const palette = ['#1f77b4', '#d62728', '#2ca02c', '#ff7f0e', '#9467bd', '#8c564b', '#e377c2', '#17becf'];
const keepSamples = 300;
// How the compensator treats an axis (the API's axes[].state, docs/server.md).
const modelState = {
  full: 'model', fallback_model: 'fallback model (a sensor lost)', geometric: 'geometric only (no thermal part)',
  disabled: '—', link_lost: 'CNC not read',
};
let lastSeq = 0;
let t0 = null;

function lineChart(canvasId, unit) {
  return new Chart(document.getElementById(canvasId), {
    type: 'line',
    data: { datasets: [] },
    options: {
      animation: false, parsing: false, normalized: true, responsive: false,
      elements: { point: { radius: 0 }, line: { borderWidth: 1.5 } },
      scales: { x: { type: 'linear', title: { display: true, text: 's' } }, y: { title: { display: true, text: unit } } },
    },
  });
}
const liveTemp = lineChart('live-temp', '°C');
const liveCorr = lineChart('live-corr', 'µm');
const histTemp = lineChart('hist-temp', '°C');
const histCorr = lineChart('hist-corr', 'µm');

function ensureDatasets(chart, names) {
  if (chart.data.datasets.length === names.length) return;
  chart.data.datasets = names.map((n, i) => ({ label: n, data: [], borderColor: palette[i % palette.length] }));
}

async function pollLive() {
  let s;
  try {
    s = await TA.api('GET', base + '/live?after=' + lastSeq);
  } catch (e) {
    TA.status('live: ' + e.message, true);
    return;
  }
  ensureDatasets(liveTemp, s.channels);
  ensureDatasets(liveCorr, s.axes);
  for (const x of s.samples) {
    if (t0 === null) t0 = x.t;
    x.temp_c.forEach((v, i) => liveTemp.data.datasets[i].data.push({ x: x.t - t0, y: v }));
    x.correction_um.forEach((v, i) => liveCorr.data.datasets[i].data.push({ x: x.t - t0, y: v }));
  }
  for (const c of [liveTemp, liveCorr])
    for (const d of c.data.datasets) if (d.data.length > keepSamples) d.data.splice(0, d.data.length - keepSamples);
  if (s.samples.length) {
    liveTemp.update('none');
    liveCorr.update('none');
    const newest = s.samples[s.samples.length - 1];
    document.getElementById('live-seq').textContent = newest.seq;
    document.getElementById('live-time').textContent = TA.time(newest.t);
  }
  lastSeq = s.last_seq;
}

async function refreshMachine() {
  const m = await TA.load(base);
  if (!m) return;
  document.getElementById('machine-title').textContent = m.id + ' — ' + m.name;
  document.getElementById('m-connected').textContent = m.connected ? 'connected' : 'lost';
  document.getElementById('m-alarms').textContent = m.alarms.length ? m.alarms.join(', ') : 'none';
  document.getElementById('m-coolant').textContent = m.coolant;
  document.getElementById('m-revision').textContent = m.model.revision || 'none';
  document.getElementById('coolant-override').textContent = m.coolant_override ? 'forced: ' + m.coolant_override : 'no override';

  const values = document.querySelector('#live-values tbody');
  values.replaceChildren(...m.channels.map((c) => TA.el('tr', {},
    TA.el('td', {}, c.name), TA.el('td', { id: 'temp-' + c.name, class: 'mono' }, TA.num(c.temp_c, 2)), TA.el('td', {}, c.health))));

  const axes = document.querySelector('#axes tbody');
  axes.replaceChildren(...m.axes.map((a) => {
    const button = TA.el('button', { id: 'axis-' + a.name + '-toggle', type: 'button' }, a.enabled ? 'Disable' : 'Enable');
    button.addEventListener('click', async () => {
      await TA.operate((a.enabled ? 'disable ' : 'enable ') + a.name, 'POST', base + '/axes/' + encodeURIComponent(a.name), { enabled: !a.enabled });
      refreshMachine();
    });
    return TA.el('tr', {}, TA.el('td', {}, a.name), TA.el('td', { class: 'mono' }, TA.num(a.position_mm, 3)),
      TA.el('td', { id: 'corr-' + a.name, class: 'mono' }, TA.num(a.correction_um, 2)),
      TA.el('td', { id: 'axis-' + a.name + '-state' }, a.enabled ? 'on' : 'off'),
      TA.el('td', { id: 'axis-' + a.name + '-model' }, modelState[a.state] || a.state || ''), TA.el('td', {}, button));
  }));

  document.getElementById('model-revision').textContent = m.model.revision || 'none';
  document.getElementById('model-sha').textContent = m.model.sha256 ? m.model.sha256.slice(0, 16) + '…' : '—';
  document.getElementById('model-label').textContent = m.model.label;
  const revisions = document.querySelector('#revisions tbody');
  revisions.replaceChildren(...m.model.available.map((r) => {
    const button = TA.el('button', { id: 'load-' + r.revision, type: 'button' }, 'Load');
    button.addEventListener('click', async () => {
      await TA.operate('load revision ' + r.revision, 'POST', base + '/model', { revision: r.revision });
      refreshMachine();
    });
    return TA.el('tr', {}, TA.el('td', {}, r.revision), TA.el('td', {}, r.loaded_unix_s ? TA.time(r.loaded_unix_s) : ''),
      TA.el('td', {}, r.label), TA.el('td', {}, button));
  }));
  const figures = document.querySelector('#figures tbody');
  figures.replaceChildren(...m.model.figures.map((f) => TA.el('tr', {}, TA.el('td', {}, f.axis), TA.el('td', {}, f.quantity),
    TA.el('td', { class: 'mono' }, TA.num(f.before_um, 2)), TA.el('td', { class: 'mono' }, TA.num(f.after_um, 2)),
    TA.el('td', {}, f.source))));
}

function utcInput(unix) { return new Date(unix * 1000).toISOString().slice(0, 19); }
function fromInput(id) { return Date.parse(document.getElementById(id).value + 'Z') / 1000; }

function exportLinks() {
  const range = 'from=' + fromInput('hist-from') + '&to=' + fromInput('hist-to');
  document.getElementById('export-csv-temp').href = base + '/export?format=csv&table=temperature&' + range;
  document.getElementById('export-csv-comp').href = base + '/export?format=csv&table=compensation&' + range;
  document.getElementById('export-xlsx').href = base + '/export?format=xlsx&' + range;
}

async function loadHistory() {
  exportLinks();
  const from = fromInput('hist-from'), to = fromInput('hist-to');
  let h;
  try {
    h = await TA.api('GET', base + '/history?from=' + from + '&to=' + to + '&points=600');
  } catch (e) {
    TA.status('history: ' + e.message, true);
    return;
  }
  for (const [chart, traces] of [[histTemp, h.temperatures], [histCorr, h.corrections]]) {
    chart.data.datasets = traces.map((tr, i) => ({
      label: tr.name, borderColor: palette[i % palette.length], data: tr.t.map((t, k) => ({ x: t - from, y: tr.v[k] })),
    }));
    chart.update('none');
  }
}

document.getElementById('coolant-apply').addEventListener('click', async () => {
  const state = document.getElementById('coolant-state').value;
  await TA.operate('coolant override ' + (state || 'cleared'), 'POST', base + '/coolant', { state });
  refreshMachine();
});
document.getElementById('rollback').addEventListener('click', async () => {
  await TA.operate('roll back the model', 'POST', base + '/model/rollback');
  refreshMachine();
});
document.getElementById('hist-load').addEventListener('click', loadHistory);
for (const idIn of ['hist-from', 'hist-to']) document.getElementById(idIn).addEventListener('change', exportLinks);

TA.init('').then(() => {
  const now = Date.now() / 1000;
  document.getElementById('hist-from').value = utcInput(now - 3600);
  document.getElementById('hist-to').value = utcInput(now);
  refreshMachine();
  pollLive();
  loadHistory();
  setInterval(pollLive, 1000);
  setInterval(refreshMachine, 2000);
}).catch((e) => TA.status(e.message, true));
