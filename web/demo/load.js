// The demo's loading: one source (a File, bytes or { url }) parsed in the worker with progress
// and cancel, then shown; the samples (fetched, or generated in a worker); "Download STL".
import { loadStl, toStl } from 'stltopo/worker';
import { samples } from './samples.js';
import { $, viewer } from './page.js';
import { FAT_LINE_SEGMENTS, MAX_RINGS } from './viewer.js';
import { showProgress, hideProgress, showError, hideError, showMesh, clearPanels, showScaleNote } from './panels.js';
import { stopEditing, setLoaded } from './edit-panel.js';
import { setRepairSource, repairedStl } from './repair-panel.js';
import { setUnionSource, setUnionReplace } from './union-panel.js';

/** Files larger than this load without the exact geometry (see load()). */
export const GEOMETRY_MAX_BYTES = 1e9;

// What the page says about a mesh too large for everything: the coarse view (the viewer's
// stride, 1 when it draws every triangle), the plainer overlays (the viewer's `plainer`), the
// skipped geometry pass ('' when none applies).
function scaleNote(mesh, { stride, plainer }, geometry, total) {
  const parts = [];
  const n = mesh.nTriangles;
  if (stride > 1) {
    parts.push(`Large mesh: the view draws 1 triangle in ${stride} (${Math.ceil(n / stride).toLocaleString('en-US')} of ` +
      `${n.toLocaleString('en-US')}), without colours; every figure and defect is of the whole mesh.`);
  }
  if (plainer.length) {
    parts.push(`Many defects: the view draws ${plainer.join(', and ')} (past ${FAT_LINE_SEGMENTS.toLocaleString('en-US')} ` +
      `edges of a kind, or ${MAX_RINGS.toLocaleString('en-US')} small holes); the lists and figures are whole.`);
  }
  if (!geometry) {
    parts.push(`Exact geometry skipped: the file is ${(total / 1e9).toFixed(1)} GB, and self-intersections and nesting ` +
      'would not fit in the 4 GB WebAssembly heap beside the mesh (`stltopo info --intersections` runs them natively).');
  }
  return parts.join(' ');
}

export let current = null; // { seq, controller, name } of the load in flight
let loadSeq = 0;
let hasModel = false;

function setState(state) {
  document.body.dataset.state = state;
}

// ---------------------------------------------------------------------------------------------
// Loading

/**
 * Loads one source and shows it. `source` is a File/Blob, an ArrayBuffer, or { url }.
 * A newer load cancels an older one; errors land in the error box and the page stays usable.
 */
export async function load(source, { name, credit = '' } = {}) {
  current?.controller.abort();
  const seq = ++loadSeq;
  const controller = new AbortController();
  current = { seq, controller, name, userCancelled: false };
  setState('loading');
  document.body.dataset.loadCount = String(seq);
  hideError();
  showProgress(name, NaN, 0);
  const t0 = performance.now();
  try {
    let input = source;
    let total = source.size ?? source.byteLength;
    if (source.url) {
      const response = await fetch(source.url, { signal: controller.signal });
      if (!response.ok) {
        throw Object.assign(new Error(`the server answered ${response.status} ${response.statusText} for ${source.url}`), { code: 'http' });
      }
      total = Number(response.headers.get('content-length')) || NaN;
      input = response;
    }
    // The exact geometry costs some 40 bytes per triangle more in the worker's 4 GB heap: a
    // file over GEOMETRY_MAX_BYTES (some 20M binary triangles) loads without it, and says so.
    const geometry = !(total > GEOMETRY_MAX_BYTES);
    const mesh = await loadStl(input, {
      topology: true,
      shells: true,
      intersections: geometry, // exact self-intersections, nesting and the solid badge (issue 21)
      signal: controller.signal,
      onProgress: (fraction, bytesRead) => {
        if (seq === loadSeq) showProgress(name, Number.isFinite(fraction) ? fraction : bytesRead / total, bytesRead);
      },
    });
    if (seq !== loadSeq) return;
    const tParsed = performance.now();
    showProgress(name, 1, total, 'building the view…');
    await nextFrame();
    if (seq !== loadSeq) return;
    await stopEditing();
    const sceneMs = present(mesh, name);
    hasModel = true;
    $('#download').hidden = false;
    showMesh(mesh, { name, credit, parseMs: tParsed - t0, sceneMs, totalMs: performance.now() - t0 });
    showScaleNote(scaleNote(mesh, viewer, geometry, total));
    hideProgress();
    current = null;
    setState('ready');
  } catch (error) {
    if (seq !== loadSeq) return;
    hideProgress();
    const cancelled = current?.userCancelled;
    current = null;
    if (cancelled && hasModel) {
      setState('ready'); // the previous model is still on screen
      return;
    }
    showError(name, error);
    viewer.clear();
    clearPanels();
    hasModel = false;
    shown = null;
    setRepairSource(null);
    setUnionSource(null);
    $('#download').hidden = true;
    setState('error');
  }
}

// `mesh` as the model on screen: drawn, and handed to the download, edit, repair and union
// panels. The time the view took.
function present(mesh, name, { keepView = false, keepUnionUndo = false } = {}) {
  const sceneMs = viewer.setMesh(mesh, { keepView });
  shown = { mesh, name };
  setLoaded({ mesh, name });
  setRepairSource({ mesh, name });
  setUnionSource({ mesh, name }, { keepUndo: keepUnionUndo });
  return sceneMs;
}

// The union panel's result (or its undo) as the model on screen, as a loaded model is; the
// view stays where it is.
async function replaceModel(mesh, { name, credit, t0, keepUnionUndo }) {
  await stopEditing();
  const sceneMs = present(mesh, name, { keepView: true, keepUnionUndo });
  showMesh(mesh, { name, credit, parseMs: performance.now() - t0 - sceneMs, sceneMs, totalMs: performance.now() - t0 });
  showScaleNote(scaleNote(mesh, viewer, true, 0));
}
setUnionReplace(replaceModel);

// The mesh on screen, for "Download STL": written as STL in the worker (the mesh came from
// one), then handed to the browser as a download. While a repair is applied (repair-panel.js),
// the repaired mesh instead (EditableMesh.toStl on this thread).
let shown = null;
$('#download-button').addEventListener('click', async () => {
  if (!shown) return;
  const button = $('#download-button');
  const format = $('#download-format').value;
  button.disabled = true;
  try {
    const repaired = repairedStl(format);
    const blob = repaired ? new Blob([repaired], { type: 'model/stl' }) : await toStl(shown.mesh, { format });
    const a = document.createElement('a');
    a.href = URL.createObjectURL(blob);
    a.download = `${shown.name.replace(/\.stl$/i, '')}${repaired ? '-repaired' : ''}${format === 'ascii' ? '-ascii' : ''}.stl`;
    document.body.append(a);
    a.click();
    a.remove();
    setTimeout(() => URL.revokeObjectURL(a.href), 60_000);
  } catch (error) {
    showError(shown.name, error);
  } finally {
    button.disabled = false;
  }
});

/** Lets the page paint (progress text) before a long step; does not hang in a hidden tab. */
function nextFrame() {
  return new Promise((resolve) => {
    requestAnimationFrame(() => resolve());
    setTimeout(resolve, 100);
  });
}

export async function loadSample(id) {
  const sample = samples.find((s) => s.id === id) ?? samples[0];
  $('#sample-select').value = sample.id;
  if (sample.generate) {
    setState('loading');
    showProgress(sample.label, NaN, 0, 'generating…');
    const seq = loadSeq;
    let buffer;
    try {
      buffer = await generate(sample.generate);
    } catch (error) {
      if (seq === loadSeq) {
        hideProgress();
        showError(sample.label, error);
        setState('error');
      }
      return undefined;
    }
    if (seq !== loadSeq) return undefined; // another load started meanwhile
    const name = `${sample.id}.stl`;
    return load(new File([buffer], name), { name, credit: 'Generated in the page by web/demo/generate.js.' });
  }
  return load({ url: new URL(`samples/${sample.file}`, document.baseURI).href },
    { name: sample.file, credit: `Sample from ${sample.credit}.` });
}

/** Runs a generator of generate.js in a worker (the 1M-triangle one takes a while). */
function generate(name) {
  return new Promise((resolve, reject) => {
    const worker = new Worker(new URL('./generate-worker.js', import.meta.url), { type: 'module' });
    worker.onmessage = ({ data }) => {
      worker.terminate();
      if (data.error) reject(new Error(data.error));
      else resolve(data.buffer);
    };
    worker.onerror = (event) => {
      worker.terminate();
      reject(new Error(`generator worker: ${event.message}`));
    };
    worker.postMessage({ name });
  });
}

export function loadUrl(url) {
  let name = url;
  try {
    name = decodeURIComponent(new URL(url, document.baseURI).pathname.split('/').pop()) || url;
  } catch { /* keep the raw text as the name */ }
  return load({ url }, { name, credit: `Loaded from ${url}` });
}
