// The page: choose a mesh and options, upload, follow the job, then view and download the result.

import { ApiError, cancelJob, fetchResult, getMetrics, submitJob, waitForJob } from './api.js';
import { parseMesh, parseObj } from './mesh_formats.js';
import { MeshViewer } from './viewer.js';

const kResultMeshes = [
  ['triangles', 'remesh'],
  ['quads', 'quad remesh'],
  ['hexagons', 'hexagonal dual'],
  ['textured', 'textured input'],
];

const $ = (id) => document.getElementById(id);
const viewer = new MeshViewer($('viewer'));
let chosenFile = null;
let currentJobId = null;

function setStatus(text, isError = false) {
  $('status').textContent = text;
  $('status').classList.toggle('error', isError);
}

function describeError(error) {
  if (error instanceof ApiError) {
    const p = error.problem;
    return `${p.status ?? ''} ${p.title ?? 'error'}${p.detail ? ': ' + p.detail : ''}`.trim();
  }
  return String(error.message ?? error);
}

// ---- choosing a file -------------------------------------------------------------------------

async function chooseFile(file) {
  chosenFile = file;
  $('drop-text').textContent = `${file.name} (${(file.size / 1024).toFixed(0)} KiB)`;
  $('submit').disabled = false;
  $('results').hidden = true;
  try {
    viewer.setInput(parseMesh(await file.arrayBuffer()));
    setStatus('Ready to remesh.');
  } catch (error) {
    // The server decides what it accepts; the preview is only a convenience.
    setStatus(`No preview (${describeError(error)}); the server will check the file.`);
  }
}

$('mesh-file').addEventListener('change', (event) => {
  if (event.target.files.length) chooseFile(event.target.files[0]);
});
const dropZone = $('drop-zone');
dropZone.addEventListener('dragover', (event) => {
  event.preventDefault();
  dropZone.classList.add('dragging');
});
dropZone.addEventListener('dragleave', () => dropZone.classList.remove('dragging'));
dropZone.addEventListener('drop', (event) => {
  event.preventDefault();
  dropZone.classList.remove('dragging');
  if (event.dataTransfer.files.length) chooseFile(event.dataTransfer.files[0]);
});

// ---- options ---------------------------------------------------------------------------------

function readOptions() {
  const options = { rosy: $('rosy').value, sizing: $('sizing').value, placement: $('placement').value };
  const target = document.querySelector('input[name=target]:checked').value;
  const value = $('target-value').value.trim();
  if (value !== '') options[target] = value;
  const featureAngle = $('feature-angle').value.trim();
  if (featureAngle !== '') options.feature_angle = featureAngle;
  const dSing = $('d-sing').value.trim();
  if (dSing !== '') options.d_sing = dSing;
  return options;
}

for (const radio of document.querySelectorAll('input[name=target]')) {
  radio.addEventListener('change', () => {
    $('target-value').placeholder =
      radio.value === 'vertices' ? "default: ¼ of the input's vertices" : 'model units';
  });
}

// ---- the job ---------------------------------------------------------------------------------

function showJob(job) {
  const fraction = typeof job.progress === 'number' ? job.progress : 0;
  $('job-progress').value = job.state === 'succeeded' ? 1 : fraction;
  const parts = [job.state];
  if (job.stage) parts.push(job.stage);
  if (job.state === 'running') parts.push(`${Math.round(100 * fraction)} %`);
  if (job.state === 'queued' && job.queue_position != null) parts.push(`position ${job.queue_position} in queue`);
  setStatus(`Job ${job.id}: ${parts.join(' · ')}`);
}

async function runJob(event) {
  event.preventDefault();
  if (!chosenFile) return;
  const options = readOptions();
  $('submit').disabled = true;
  $('results').hidden = true;
  $('upload-progress').value = 0;
  $('job-progress').value = 0;
  setStatus('Uploading…');
  try {
    const accepted = await submitJob(chosenFile, options, (sent, total) => {
      $('upload-progress').value = total ? sent / total : 0;
    });
    $('upload-progress').value = 1;
    currentJobId = accepted.id;
    $('cancel').hidden = false;
    const job = await waitForJob(accepted.id, showJob);
    $('cancel').hidden = true;
    if (job.state === 'succeeded') {
      await showResults(job, Number(job.options?.rosy ?? options.rosy));
      setStatus(`Job ${job.id}: succeeded.`);
    } else if (job.state === 'failed') {
      setStatus(`Job ${job.id} failed: ${describeError(new ApiError(job.error ?? { title: 'failed' }))}`, true);
    } else {
      setStatus(`Job ${job.id}: ${job.state}.`);
    }
  } catch (error) {
    setStatus(describeError(error), true);
  } finally {
    $('submit').disabled = false;
    $('cancel').hidden = true;
  }
}

$('job-form').addEventListener('submit', runJob);
$('cancel').addEventListener('click', () => {
  if (currentJobId) cancelJob(currentJobId).catch((error) => setStatus(describeError(error), true));
});

// ---- results ---------------------------------------------------------------------------------

/** Leaves of a JSON document as [dotted.path, value] rows; arrays of numbers stay one row. */
function flatten(value, prefix = '', rows = []) {
  if (value !== null && typeof value === 'object' && !(Array.isArray(value) && value.every((x) => typeof x !== 'object'))) {
    for (const [key, child] of Object.entries(value)) flatten(child, prefix ? `${prefix}.${key}` : key, rows);
  } else {
    rows.push([prefix, value]);
  }
  return rows;
}

/** Numbers shown with 4 significant digits (integers in full). */
function formatValue(value) {
  if (typeof value === 'number') return Number.isInteger(value) ? String(value) : value.toPrecision(4);
  if (Array.isArray(value)) return value.map(formatValue).join(', ');
  return String(value);
}

function showMetrics(metrics) {
  const body = $('metrics').tBodies[0];
  body.replaceChildren();
  for (const [key, value] of flatten(metrics)) {
    const row = body.insertRow();
    row.dataset.key = key;
    row.dataset.value = JSON.stringify(value);
    row.insertCell().textContent = key;
    row.insertCell().textContent = formatValue(value);
  }
}

/**
 * The remesh's warnings (what the user may act on: a vertex count missed, a part lost), one
 * item each above the metrics; hidden when there are none.
 */
function showWarnings(warnings) {
  const list = $('warnings');
  list.replaceChildren(...warnings.map((text) => {
    const item = document.createElement('li');
    item.textContent = text;
    return item;
  }));
  list.hidden = warnings.length === 0;
}

/** One row per result mesh with a link per format, from the job's `links.results`. */
function showDownloads(job) {
  const body = $('downloads').tBodies[0];
  body.replaceChildren();
  for (const [mesh, label] of kResultMeshes) {
    const results = (job.links?.results ?? []).filter((r) => r.mesh === mesh);
    if (!results.length) continue;
    const row = body.insertRow();
    row.insertCell().textContent = label;
    const links = row.insertCell();
    for (const result of results) {
      const link = document.createElement('a');
      link.href = result.href;
      link.download = `${job.id}-${mesh}.${result.format}`;
      link.textContent = result.format;
      if (result.bytes != null) link.title = `${(result.bytes / 1024).toFixed(0)} KiB`;
      links.append(link);
    }
  }
}

async function showResults(job, rosy) {
  const { id } = job;
  const text = (buffer) => new TextDecoder().decode(buffer);
  const hasObj = (mesh) => (job.links?.results ?? []).some((r) => r.mesh === mesh && r.format === 'obj');
  const objOf = (mesh) => (hasObj(mesh) ? fetchResult(id, 'obj', mesh) : null);
  // A quad remesh (rosy 4) is shown as its quads.
  const [metrics, triangles, hexagons, textured] = await Promise.all([
    getMetrics(id),
    fetchResult(id, 'obj', hasObj('quads') ? 'quads' : 'triangles'),
    objOf('hexagons'),
    objOf('textured'),
  ]);
  showWarnings(metrics.warnings ?? []);
  showMetrics(metrics);
  showDownloads(job);
  const irregular = viewer.setRemesh(parseObj(text(triangles)), rosy);
  $('count-below').textContent = `valence ≤${rosy - 1}: ${irregular.below.length}`;
  $('count-above').textContent = `valence ≥${rosy + 1}: ${irregular.above.length}`;
  if (hexagons) viewer.setDual(parseObj(text(hexagons)));
  if (textured) viewer.setTextured(parseObj(text(textured)));
  $('results').hidden = false;
  document.body.dataset.jobId = id;
  document.body.dataset.state = 'shown';
}

// ---- viewer controls -------------------------------------------------------------------------

function applyViewOptions() {
  viewer.setOptions({
    mode: $('view-mode').value,
    wireframe: $('show-wireframe').checked,
    singularities: $('show-singularities').checked,
    dual: $('show-dual').checked,
    texture: $('show-texture').checked,
  });
}
for (const id of ['view-mode', 'show-wireframe', 'show-singularities', 'show-dual', 'show-texture']) {
  $(id).addEventListener('change', applyViewOptions);
}
applyViewOptions();
window.addEventListener('resize', () => viewer.resize());
