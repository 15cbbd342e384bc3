// The demo page: loading (samples, file picker, drag and drop, ?url=), the worker-side parse with
// progress and cancel, and the panels. The 3D side lives in viewer.js. This file wires the page's
// controls; the parts are page.js ($, the viewer), load.js (loading), panels.js (stats, verdict,
// loops, shells, defects, progress and errors), edit-panel.js (the edit mode, edit.js) and
// repair-panel.js (the Repair panel: plan, preview, apply, undo; its test hooks are listed there).
//
// Test hooks (kept stable): [data-metric="threads"] is the threads of the last load;
// document.body.dataset.state is "loading" | "ready" | "error";
// every statistic is an element [data-stat="<stltopo info --json key>"] whose text is the value;
// each hole list entry carries data-hole="<hole id>"; each shell entry data-shell="<shell id>"
// (the selected one has class "active" and its figures are [data-shell-stat="<shellList key>"]);
// each defect entry data-defect-kind="<kind>" data-defect-index="<i>" (the framed one is active,
// and body[data-focused-defect] says "<kind>:<i>"); the error code is in [data-error-code].
import { init } from 'stltopo/worker';
import { samples, defaultSampleId } from './samples.js';
import { $, viewer } from './page.js';
import { current, load, loadSample, loadUrl } from './load.js';
import { formatBytes, hideError, resetView } from './panels.js';
import './repair-panel.js'; // wires the Repair panel's controls (load.js hands it each model)

// The threaded modules, served next to the page (vite.config.js, stltopo-threads): loads use
// them when the page is cross-origin isolated, on navigator.hardwareConcurrency threads; the
// Model panel shows the count ([data-metric="threads"]).
init({ threadsUrl: new URL('./stltopo-mt/', location.href) });

// ---------------------------------------------------------------------------------------------
// Wiring

function buildSampleMenu() {
  const select = $('#sample-select');
  const groups = new Map();
  for (const s of samples) {
    if (!groups.has(s.group)) {
      const g = document.createElement('optgroup');
      g.label = s.group;
      groups.set(s.group, g);
      select.append(g);
    }
    const option = new Option(s.label, s.id);
    groups.get(s.group).append(option);
  }
  const custom = new Option('— your file —', '');
  custom.disabled = true;
  select.prepend(custom);
  select.addEventListener('change', () => {
    if (!select.value) return;
    history.replaceState(null, '', `?sample=${encodeURIComponent(select.value)}`);
    loadSample(select.value);
  });
}

function markCustom() {
  $('#sample-select').value = '';
}

function loadFile(file) {
  markCustom();
  history.replaceState(null, '', location.pathname);
  return load(file, { name: file.name, credit: `Your file, ${formatBytes(file.size)}; it stays on this computer.` });
}

$('#open-button').addEventListener('click', () => $('#file-input').click());
$('#file-input').addEventListener('change', (event) => {
  const file = event.target.files?.[0];
  event.target.value = ''; // choosing the same file again still fires "change"
  if (file) loadFile(file);
});

$('#url-form').addEventListener('submit', (event) => {
  event.preventDefault();
  const url = $('#url-input').value.trim();
  if (!url) return;
  markCustom();
  history.replaceState(null, '', `?url=${encodeURIComponent(url)}`);
  loadUrl(url);
});

$('#cancel-button').addEventListener('click', () => {
  if (!current) return;
  current.userCancelled = true;
  current.controller.abort();
});
$('#error-close').addEventListener('click', hideError);
$('#frame-button').addEventListener('click', resetView);

for (const input of document.querySelectorAll('[data-layer]')) {
  input.addEventListener('change', () => viewer.setVisible(input.dataset.layer, input.checked));
}

window.addEventListener('keydown', (event) => {
  if (event.target.closest?.('input, select, textarea') || event.ctrlKey || event.metaKey || event.altKey) return;
  if (event.key === 'f' || event.key === 'F') $('#frame-button').click();
  if (event.key === 'w' || event.key === 'W') $('[data-layer="wireframe"]').click();
  if (event.key === 'Escape' && current) $('#cancel-button').click();
});

// Drag and drop anywhere on the page. dragenter/dragleave fire for every child, so count them.
let dragDepth = 0;
const isFileDrag = (event) => [...(event.dataTransfer?.types ?? [])].some((t) => t === 'Files' || t === 'text/uri-list');
window.addEventListener('dragenter', (event) => {
  if (!isFileDrag(event)) return;
  event.preventDefault();
  dragDepth++;
  $('#drop-overlay').hidden = false;
});
window.addEventListener('dragover', (event) => {
  if (!isFileDrag(event)) return;
  event.preventDefault();
  event.dataTransfer.dropEffect = 'copy';
});
window.addEventListener('dragleave', () => {
  dragDepth = Math.max(0, dragDepth - 1);
  if (dragDepth === 0) $('#drop-overlay').hidden = true;
});
window.addEventListener('drop', (event) => {
  event.preventDefault();
  dragDepth = 0;
  $('#drop-overlay').hidden = true;
  const file = event.dataTransfer?.files?.[0];
  if (file) {
    loadFile(file);
    return;
  }
  const url = event.dataTransfer?.getData('text/uri-list')?.split('\n').find((l) => l && !l.startsWith('#'));
  if (url) {
    markCustom();
    loadUrl(url.trim());
  }
});

buildSampleMenu();
const params = new URLSearchParams(location.search);
if (params.get('url')) {
  markCustom();
  $('#url-input').value = params.get('url');
  loadUrl(params.get('url'));
} else {
  loadSample(params.get('sample') ?? defaultSampleId);
}
