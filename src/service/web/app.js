// The page at / (issue 19): choose a mesh, read the service's check verdict beside a preview,
// design a lattice, follow the fill job, look at the result and download it. Everything goes
// through the same HTTP API a script would use (api.js); nothing is fetched from elsewhere.
import { Api } from './api.js';
import { readMeshFile } from './meshes.js';
import { Viewer } from './viewer.js';

const $ = (id) => document.getElementById(id);
const number = (x, digits = 3) => Number(x).toLocaleString('en', { maximumSignificantDigits: digits });
const escapeHtml = (text) =>
  String(text).replace(/[&<>"']/g, (c) => `&#${c.charCodeAt(0)};`);
// Problems and warnings, one item each ('' for none).
const warningList = (items) =>
  items.length ? `<ul class="problems">${items.map((w) => `<li class="warn">${escapeHtml(w)}</li>`).join('')}</ul>` : '';

// A result larger than this (an STL of 8 million triangles) is offered for download but not
// drawn: a browser tab's memory and a laptop's GPU give out around there.
const kLargestDrawn = 400e6;

const viewer = new Viewer($('viewer'));
let mesh = null;        // the chosen File
let checked = null;     // its check report, once the service has answered
let job = null;         // the running fill job's id
let resultUrl = null;   // the object URL behind the download link
let choices = 0;        // files chosen so far: a check that answers late for an older one is dropped

// The token: from the address's #token=... once (then dropped from the address bar), or typed;
// kept in sessionStorage, this tab only.
function token() {
  const match = /(?:^#|&)token=([^&]+)/.exec(location.hash);
  if (match) {
    sessionStorage.setItem('tpmsfill-token', decodeURIComponent(match[1]));
    history.replaceState(null, '', location.pathname);
  }
  return sessionStorage.getItem('tpmsfill-token') ?? '';
}
$('token').value = token();
$('token').addEventListener('input', () => sessionStorage.setItem('tpmsfill-token', $('token').value));
$('token-form').addEventListener('submit', (e) => e.preventDefault());
const api = () => new Api($('token').value.trim());

function caption(text) {
  $('viewer-caption').textContent =
    text + (viewer.webgl ? ' Drag to turn, scroll to zoom, right-drag to pan.' : ' (This browser has no WebGL: no 3D view.)');
}

// ---- 1. The mesh: a preview read here, the verdict from the service's check.

// The check's report is in mm under the units it was sent with; this turns its lengths into
// mm as fill will read the file with the units and scale chosen now.
const kPerUnit = { mm: 1, cm: 10, m: 1000, in: 25.4, um: 0.001 };
function millimetres(report) {
  return (kPerUnit[$('units').value] / kPerUnit[report.units ?? 'mm']) * (Number($('scale').value) || 1);
}

function showVerdict(report) {
  const mm = millimetres(report);
  const [x, y, z] = report.bbox.max.map((hi, i) => (hi - report.bbox.min[i]) * mm);
  const good = report.valid && report.closed;
  const problems = [...(report.problems ?? []), ...(report.warnings ?? [])];
  $('verdict').innerHTML = `
    <p class="${good ? 'ok' : 'bad'}">${
      good ? 'Closed, 2-manifold and outward: ready to fill.'
           : 'Not a clean solid. Fill can still use it: holes are closed and overlaps resolved by the winding number; repair it first for a watertight copy.'}</p>
    <dl>
      <dt>Triangles</dt><dd>${number(report.triangles, 9)}</dd>
      <dt>Size</dt><dd>${number(x)} × ${number(y)} × ${number(z)} mm</dd>
      <dt>Volume</dt><dd>${report.volume == null ? '—' : number(Math.abs(report.volume) * mm ** 3) + ' mm³'}</dd>
      <dt>Shells</dt><dd>${report.components}</dd>
      <dt>Holes</dt><dd>${report.holes}</dd>
      <dt>Self-intersections</dt><dd>${report.self_intersecting_pairs ?? '—'}</dd>
    </dl>
    ${warningList(problems)}
    ${report.units_hint ? `<p class="warn">${escapeHtml(report.units_hint)}</p>` : ''}`;
  const smallest = Math.min(x, y, z);
  if (smallest < Number($('cell').value))
    $('verdict').insertAdjacentHTML('beforeend',
      `<p class="warn">The part is ${number(smallest)} mm at its thinnest, less than one ${$('cell').value} mm cell: check the units, or choose a smaller cell.</p>`);
}

async function choose(file) {
  const choice = ++choices;
  mesh = file;
  checked = null;
  $('start').disabled = true;
  $('verdict').innerHTML = `<p>Checking <strong>${escapeHtml(file.name)}</strong>…</p>`;
  try {
    if (file.size > kLargestDrawn) throw new Error('too large to draw here');
    const geometry = await readMeshFile(file.name, await file.arrayBuffer());
    if (choice !== choices) return;
    const triangles = viewer.show(geometry, 'input', 0xb8c4d6);
    caption(`${file.name}: ${number(triangles, 9)} triangles (preview).`);
  } catch (e) {
    caption(`${file.name}: no preview (${e.message}); the check below is the verdict.`);
  }
  try {
    const id = await api().submit('check', file, { units: $('units').value });
    const record = await api().follow(id, () => {});
    if (choice !== choices) return;  // another file was chosen meanwhile
    if (record.state !== 'done') throw new Error(record.error ?? `the check was ${record.state}`);
    checked = record.report;
    showVerdict(checked);
    $('start').disabled = job !== null;  // one fill at a time from this page
  } catch (e) {
    if (choice === choices) $('verdict').innerHTML = `<p class="bad">${escapeHtml(e.message)}</p>`;
  }
}

$('mesh-file').addEventListener('change', () => {
  if ($('mesh-file').files.length) choose($('mesh-file').files[0]);
});
const drop = $('drop');
drop.addEventListener('dragover', (e) => {
  e.preventDefault();
  drop.classList.add('over');
});
drop.addEventListener('dragleave', () => drop.classList.remove('over'));
drop.addEventListener('drop', (e) => {
  e.preventDefault();
  drop.classList.remove('over');
  if (e.dataTransfer.files.length) choose(e.dataTransfer.files[0]);
});
for (const id of ['units', 'scale', 'cell'])
  $(id).addEventListener('change', () => checked && showVerdict(checked));

// ---- 2. The design, as the recipe fill reads (docs/recipes.md).

// Fields that apply only to some designs are shown only then.
function fieldsShown() {
  for (const element of document.querySelectorAll('.graded')) element.hidden = !$('grading').value;
  for (const element of document.querySelectorAll('.sheet-only'))
    element.hidden = $('style').value !== 'sheet';
}
$('grading').addEventListener('change', fieldsShown);
$('style').addEventListener('change', fieldsShown);
fieldsShown();

function recipe() {
  const porosity = Number($('porosity').value);
  const r = {
    units: $('units').value,
    scale: Number($('scale').value),
    voxel: Number($('voxel').value),
    skin: Number($('skin').value),
    skin_windows: $('skin-windows').checked,
    lattice: {
      type: $('type').value,
      style: $('style').value,
      cell: Number($('cell').value),
      porosity,
    },
  };
  const thickness = Number($('thickness').value);
  if ($('style').value === 'sheet' && thickness > 0) {
    delete r.lattice.porosity;
    r.lattice.thickness = thickness;
  }
  const along = $('grading').value;
  if (along) {
    const ramp = { what: 'porosity', start: porosity, end: Number($('porosity-end').value) };
    if (along === 'depth') Object.assign(ramp, { ramp: 'depth' });
    else if (along === 'radial') Object.assign(ramp, { ramp: 'radial', axis: [0, 0, 0] });
    else Object.assign(ramp, { ramp: 'linear', axis: { x: [1, 0, 0], y: [0, 1, 0], z: [0, 0, 1] }[along] });
    r.grading = [ramp];
  }
  return r;
}

function showOutcome(record) {
  const r = record.report;
  const warnings = (record.warnings ?? '').split('\n').filter((line) => line);  // one a line
  $('outcome').innerHTML = `
    <p class="ok">Written and checked: closed, 2-manifold, outward, no self-intersections.</p>
    <dl>
      <dt>Triangles</dt><dd>${number(r.output.triangles, 9)}</dd>
      <dt>Porosity</dt><dd>${number(100 * r.porosity)} % ${
        r.lattice.grading ? `(graded: ${escapeHtml(r.lattice.grading)})`
        : r.lattice.porosity_target != null ? `(asked ${number(100 * r.lattice.porosity_target)} %)` : ''}</dd>
      <dt>Lattice volume</dt><dd>${number(r.lattice_volume)} mm³ of ${number(r.model_volume)} mm³</dd>
      <dt>Pieces removed</dt><dd>${r.islands_removed}</dd>
      <dt>Time</dt><dd>${number(r.total_seconds)} s</dd>
    </dl>
    ${warningList(warnings)}`;
}

function running(on) {
  $('start').disabled = on || !checked;
  $('cancel').hidden = !on;
  $('progress-box').hidden = !on;
}

$('design').addEventListener('submit', async (e) => {
  e.preventDefault();
  if (!mesh) return;
  $('outcome').textContent = '';
  $('download').hidden = true;
  if (resultUrl) URL.revokeObjectURL(resultUrl);
  running(true);
  $('progress').value = 0;
  $('stage').textContent = 'queued';
  try {
    performance.mark('fill-sent');
    job = await api().submit('fill', mesh, recipe());
    const record = await api().follow(job, (r) => {
      $('progress').value = r.progress ?? 0;
      $('stage').textContent = r.state === 'running' ? `${r.stage || 'starting'} (${Math.round(100 * (r.progress ?? 0))} %)` : r.state;
    });
    if (record.state === 'cancelled') {
      $('outcome').innerHTML = '<p>Cancelled: nothing was written.</p>';
      return;
    }
    if (record.state !== 'done') throw new Error(record.error ?? `the job ${record.state}`);
    performance.mark('fill-ended');  // marks: what the browser test times
    showOutcome(record);
    $('stage').textContent = 'fetching the result';
    const blob = await api().result(job);
    performance.mark('result-fetched');
    resultUrl = URL.createObjectURL(blob);
    const name = mesh.name.replace(/(\.gz)?$/i, '').replace(/\.[^.]*$/, '') + `-${$('type').value}.stl`;
    Object.assign($('download'), { href: resultUrl, download: name, hidden: false });
    $('download').textContent = `Download ${name} (${number(blob.size / 1e6)} MB)`;
    if (blob.size > kLargestDrawn) {
      caption(`${name}: ${number(record.report.output.triangles, 9)} triangles, more than this page draws; open the download in a viewer.`);
    } else {
      const geometry = await readMeshFile('result.stl', await blob.arrayBuffer());
      performance.mark('result-read');
      const triangles = viewer.show(geometry, 'result', 0xd9a441);
      performance.mark('result-drawn');
      caption(`${name}: ${number(triangles, 9)} triangles.`);
    }
    $('stage').textContent = 'done';
  } catch (error) {
    $('outcome').innerHTML = `<p class="bad">${escapeHtml(error.message)}</p>`;
  } finally {
    job = null;
    running(false);
  }
});

$('cancel').addEventListener('click', async () => {
  if (!job) return;
  $('stage').textContent = 'cancelling';
  try {
    await api().cancel(job);
  } catch (e) {
    $('outcome').innerHTML = `<p class="bad">${escapeHtml(e.message)}</p>`;
  }
});

caption('Nothing to show yet.');
