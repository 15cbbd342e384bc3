// The demo's panels: the stats (every key of `stltopo info --json`), the verdict, the hole and
// seam lists, the shells, the defects, the warnings; the progress and error boxes. A click on a
// list entry frames (or isolates) it in the viewer.
import { DEFECT_KINDS, GEOMETRY_DEFECT_KINDS } from 'stltopo/worker';
import { holeColor, colors } from './viewer.js';
import { $, viewer } from './page.js';

// Stats panel layout: [group, [[JSON key, label], ...]]. Keys the package reports beyond these
// land in "Other", so every key of `stltopo info --json` has its element.
const statGroups = [
  ['File', [['format', 'Format'], ['solids', 'Solids'], ['triangles', 'Triangles'], ['vertices', 'Vertices'],
    ['colors', 'Colours'], ['degenerateTriangles', 'Degenerate triangles'], ['zeroAreaTriangles', 'Zero-area triangles'],
    ['duplicateTriangles', 'Duplicate triangles'], ['normalMismatches', 'Normal mismatches'],
    ['warnings', 'Warnings']]],
  ['Topology', [['watertight', 'Watertight'], ['manifold', 'Manifold'], ['edges', 'Edges'],
    ['boundaryEdges', 'Boundary edges'], ['nonManifoldEdges', 'Non-manifold edges'],
    ['inconsistentEdges', 'Inconsistent edges'], ['nonManifoldVertices', 'Non-manifold vertices'],
    ['holes', 'Holes'], ['seams', 'Seams'], ['holeSizes', 'Hole sizes (edges)'], ['shells', 'Shells'],
    ['eulerCharacteristic', 'Euler characteristic'], ['genus', 'Genus']]],
  ['Geometry', [['solid', 'Solid'], ['selfIntersections', 'Self-intersecting pairs'],
    ['intersectionKinds', 'Crossing / touching / coplanar'], ['intersectingTriangles', 'Intersecting triangles'],
    ['intersectionsComplete', 'Intersection pass complete'], ['bbox', 'Bounding box'], ['area', 'Surface area'],
    ['volume', 'Volume']]],
];
// Counts that mean trouble when they are not zero, and flags that mean trouble when false.
const badWhenNonZero = new Set(['degenerateTriangles', 'normalMismatches', 'boundaryEdges', 'nonManifoldEdges',
  'inconsistentEdges', 'nonManifoldVertices', 'holes', 'seams', 'zeroAreaTriangles', 'duplicateTriangles',
  'selfIntersections', 'intersectingTriangles']);
const badWhenFalse = new Set(['watertight', 'manifold', 'solid', 'intersectionsComplete']);

// A click on a hole entry also selects that hole for the edit mode (edit-panel.js sets this).
let selectHole = () => {};
export function onSelectHole(fn) {
  selectHole = fn;
}

// ---------------------------------------------------------------------------------------------
// Progress and errors

export const formatBytes = (n) => (!Number.isFinite(n) ? '' : n < 1e3 ? `${n} B` : n < 1e6 ? `${(n / 1e3).toFixed(1)} kB` : `${(n / 1e6).toFixed(1)} MB`);

export function showProgress(name, fraction, bytes, note) {
  $('#progress').hidden = false;
  $('#progress-name').textContent = name ?? '';
  const bar = $('#progress-bar');
  if (Number.isFinite(fraction)) bar.value = Math.max(0, Math.min(1, fraction));
  else bar.removeAttribute('value'); // indeterminate
  $('#progress-text').textContent = note ?? [Number.isFinite(fraction) ? `${Math.round(fraction * 100)}%` : '', formatBytes(bytes)].filter(Boolean).join(' · ');
}

export function hideProgress() {
  $('#progress').hidden = true;
}

export function showError(name, error) {
  const code = error?.code ?? error?.name ?? 'error';
  $('#error-file').textContent = name ?? 'the file';
  $('#error-code').textContent = code;
  $('#error-code').dataset.errorCode = code;
  $('#error-message').textContent = error?.message ?? String(error);
  $('#error').hidden = false;
}

export function hideError() {
  $('#error').hidden = true;
}

// ---------------------------------------------------------------------------------------------
// Panels

/** Text of a statistic: exactly the JSON value (numbers as JS prints them, arrays as JSON). */
function statText(value) {
  if (value === null || value === undefined) return 'null';
  if (typeof value === 'object') return JSON.stringify(value);
  return String(value);
}

function friendlyBbox(bbox) {
  const min = bbox?.min ?? (Array.isArray(bbox) ? bbox.slice(0, 3) : null);
  const max = bbox?.max ?? (Array.isArray(bbox) ? bbox.slice(3, 6) : null);
  if (!min || !max || min.length !== 3) return '';
  return `size ${[0, 1, 2].map((i) => +(max[i] - min[i]).toPrecision(4)).join(' × ')}`;
}

function friendlySolids(solids) {
  if (!Array.isArray(solids)) return '';
  const names = solids.map((s) => (s.name ? `“${s.name}”` : 'unnamed')).slice(0, 3).join(', ');
  return `${solids.length} solid${solids.length === 1 ? '' : 's'}: ${names}${solids.length > 3 ? ', …' : ''}`;
}

function renderStats(stats, name) {
  const root = $('#stats');
  root.textContent = '';
  const known = new Set(statGroups.flatMap(([, keys]) => keys.map(([k]) => k)));
  const other = Object.keys(stats).filter((k) => !known.has(k) && k !== 'file').map((k) => [k, k]);
  for (const [title, keys] of [...statGroups, ...(other.length ? [['Other', other]] : [])]) {
    const group = document.createElement('div');
    group.className = 'stats-group';
    group.innerHTML = `<h3>${title}</h3>`;
    const dl = document.createElement('dl');
    for (const [key, label] of keys) {
      if (!(key in stats)) continue;
      const value = stats[key];
      const dt = document.createElement('dt');
      dt.textContent = label;
      const dd = document.createElement('dd');
      const span = document.createElement('span');
      span.dataset.stat = key;
      span.textContent = statText(value);
      dd.append(span);
      if (typeof value === 'object' && value !== null) dd.className = 'long';
      if ((badWhenNonZero.has(key) && value > 0) || (badWhenFalse.has(key) && value === false)) dd.classList.add('bad');
      if (badWhenFalse.has(key) && value === true) dd.classList.add('good');
      const friendly = key === 'bbox' ? friendlyBbox(value) : key === 'solids' ? friendlySolids(value) : '';
      if (friendly) {
        const f = document.createElement('span');
        f.className = 'friendly';
        f.textContent = friendly;
        dd.append(f);
      }
      dl.append(dt, dd);
    }
    group.append(dl);
    root.append(group);
  }
  const file = document.querySelector('[data-stat="file"]');
  file.textContent = name;
}

// Shells: the list (triangles, closed, orientation, volume); a click isolates and frames one,
// and the stats panel shows its figures.
let selectedShell = null;
const shellStatKeys = [['triangles', 'Triangles'], ['vertices', 'Vertices'], ['edges', 'Edges'],
  ['closed', 'Closed'], ['manifold', 'Manifold'], ['consistent', 'Consistent'], ['orientation', 'Orientation'],
  ['boundaryEdges', 'Boundary edges'], ['nonManifoldEdges', 'Non-manifold edges'],
  ['inconsistentEdges', 'Inconsistent edges'], ['nonManifoldVertices', 'Non-manifold vertices'], ['holes', 'Holes'],
  ['seams', 'Seams'], ['eulerCharacteristic', 'Euler characteristic'], ['genus', 'Genus'], ['solid', 'Solid'],
  ['bbox', 'Bounding box'], ['area', 'Surface area'], ['volume', 'Volume']];

function renderShellStats(shell) {
  document.querySelector('#shell-stats')?.remove();
  if (!shell) return;
  const group = document.createElement('div');
  group.className = 'stats-group';
  group.id = 'shell-stats';
  group.innerHTML = `<h3>Shell #${shell.id}</h3>`;
  const dl = document.createElement('dl');
  for (const [key, label] of shellStatKeys) {
    const dt = document.createElement('dt');
    dt.textContent = label;
    const dd = document.createElement('dd');
    const span = document.createElement('span');
    span.dataset.shellStat = key;
    span.textContent = statText(shell[key]);
    dd.append(span);
    if (key === 'bbox') dd.className = 'long';
    if ((['closed', 'manifold', 'consistent'].includes(key) && shell[key] === false) ||
        (key.endsWith('Edges') || key === 'nonManifoldVertices' || key === 'holes' || key === 'seams') && shell[key] > 0) {
      dd.classList.add('bad');
    }
    dl.append(dt, dd);
  }
  group.append(dl);
  $('#stats').prepend(group);
}

function renderShells(mesh) {
  const ol = $('#shell-list');
  ol.textContent = '';
  selectedShell = null;
  const shells = mesh.shells ?? [];
  $('#shells-panel').hidden = shells.length === 0;
  const fragment = document.createDocumentFragment();
  for (const shell of shells.slice(0, 2000)) {
    const li = document.createElement('li');
    li.dataset.shell = String(shell.id);
    li.title = `Isolate shell ${shell.id}`;
    const color = shell.orientation === 'inward' ? colors.inward : colors.front;
    li.innerHTML = `<i class="swatch big" style="--c:${color}"></i><span class="id">#${shell.id}</span>` +
      `<span class="edges">${shell.triangles} tri${shell.triangles === 1 ? '' : 's'}</span>` +
      `<span class="orientation ${shell.orientation}">${shell.closed ? 'closed' : 'not closed'} · ${shell.orientation}` +
      `${shellNesting(shell)} · V ${+shell.volume.toPrecision(3)}</span>`;
    li.addEventListener('click', () => {
      const wasActive = li.classList.contains('active');
      document.querySelectorAll('.loop-list li.active, .defect-kind li.active').forEach((e) => e.classList.remove('active'));
      delete document.body.dataset.focusedDefect;
      selectedShell = wasActive ? null : shell.id;
      if (!wasActive) li.classList.add('active');
      viewer.isolateShell(selectedShell);
      renderShellStats(wasActive ? null : shell);
    });
    fragment.append(li);
  }
  ol.append(fragment);
}

// Defects, grouped by kind; a click frames and highlights one.
// What the nesting says about a shell (with intersections): a cavity, a body inside another,
// an inside-out part, or overlapping bodies.
function shellNesting(shell) {
  if (shell.intersectsShells === undefined) return '';
  if (shell.intersectsShells.length) return ` · <b class="overlap">overlaps #${shell.intersectsShells.join(', #')}</b>`;
  if (shell.depth === null) return shell.selfIntersects ? ' · self-intersecting' : '';
  const odd = shell.depth % 2 === 1;
  const what = shell.orientation === 'inward' ? (odd ? `cavity in #${shell.parent}` : 'inside out')
    : shell.orientation === 'outward' ? (odd ? `body inside #${shell.parent}` : shell.depth ? `island in #${shell.parent}` : '')
      : '';
  return (what ? ` · ${what}` : '') + (shell.selfIntersects ? ' · self-intersecting' : '');
}

const defectLabels = {
  holes: 'Holes', seams: 'Seams', nonManifoldEdges: 'Non-manifold edges', inconsistentEdges: 'Inconsistent edges',
  nonManifoldVertices: 'Non-manifold vertices', degenerateTriangles: 'Degenerate triangles',
  zeroAreaTriangles: 'Zero-area triangles', duplicateTriangles: 'Duplicate triangles',
  selfIntersections: 'Self-intersections',
};
const kMaxDefectItems = 200; // per kind in the list (the counts say how many there are)

function defectText(kind, d) {
  switch (kind) {
    case 'holes':
    case 'seams': return `#${d.id} · ${d.edges} edges · shell ${d.shell}`;
    case 'nonManifoldEdges': return `edge ${d.vertices[0]}–${d.vertices[1]} · ${d.triangles.length} triangles`;
    case 'inconsistentEdges': return `edge ${d.vertices[0]}–${d.vertices[1]} · triangles ${d.triangles[0]}, ${d.triangles[1]}`;
    case 'nonManifoldVertices': return `vertex ${d.vertex} · ${d.cycles} cycles`;
    case 'zeroAreaTriangles': return `triangle ${d.triangle} · collinear corners`;
    case 'duplicateTriangles': return `triangles ${d.triangles.join(', ')} · ${d.orientation}`;
    case 'selfIntersections': return `triangles ${d.triangles[0]} × ${d.triangles[1]} · ${d.kind}`;
    default: return `triangle ${d.triangle} · corners ${d.corners.join(', ')} coincide`;
  }
}

function renderDefects(mesh) {
  const root = $('#defect-list');
  root.textContent = '';
  let any = false;
  for (const kind of [...DEFECT_KINDS, ...GEOMETRY_DEFECT_KINDS]) {
    const geometric = kind === 'zeroAreaTriangles' || kind === 'duplicateTriangles' || kind === 'selfIntersections';
    const n = (geometric ? mesh.intersections : mesh.defects) ? mesh.defectCount(kind) : 0;
    if (!n) continue;
    any = true;
    const details = document.createElement('details');
    details.className = 'defect-kind';
    details.dataset.kind = kind;
    details.open = true;
    details.innerHTML = `<summary>${defectLabels[kind]} <span class="count" data-defect-count="${kind}">${n}</span></summary>`;
    const ol = document.createElement('ol');
    for (let i = 0; i < Math.min(n, kMaxDefectItems); i++) {
      const d = mesh.defect(kind, i);
      const li = document.createElement('li');
      li.dataset.defectKind = kind;
      li.dataset.defectIndex = String(i);
      li.textContent = defectText(kind, d);
      li.addEventListener('click', () => {
        document.querySelectorAll('.loop-list li.active, .defect-kind li.active').forEach((e) => e.classList.remove('active'));
        if (selectedShell !== null) {
          selectedShell = null;
          viewer.isolateShell(null);
          renderShellStats(null);
        }
        li.classList.add('active');
        document.body.dataset.focusedDefect = `${kind}:${i}`;
        viewer.focusDefect(kind, d);
      });
      ol.append(li);
    }
    if (n > kMaxDefectItems) {
      const more = document.createElement('li');
      more.className = 'more';
      more.textContent = `… and ${n - kMaxDefectItems} more`;
      ol.append(more);
    }
    details.append(ol);
    root.append(details);
  }
  $('#defects-panel').hidden = !any;
}

// Loops listed at most (a triangle soup has a hole a triangle; the counts say how many).
const kMaxLoopItems = 2000;

function renderLoops(list, loops, kind, colorOf) {
  const ol = $(list);
  ol.textContent = '';
  const fragment = document.createDocumentFragment();
  for (const loop of loops.slice(0, kMaxLoopItems)) {
    const li = document.createElement('li');
    li.dataset[kind] = String(loop.id);
    li.title = `Frame ${kind} ${loop.id}`;
    li.innerHTML = `<i class="swatch big" style="--c:${colorOf(loop)}"></i><span class="id">#${loop.id}</span>` +
      `<span class="edges" data-edges="${loop.edgeCount}">${loop.edgeCount} edge${loop.edgeCount === 1 ? '' : 's'}</span>` +
      `<span class="perimeter">perimeter ${+loop.perimeter.toPrecision(4)}</span>`;
    li.addEventListener('click', () => {
      if (kind === 'hole') selectHole(loop.id);
      const wasActive = li.classList.contains('active');
      clearSelection();
      if (wasActive) {
        viewer.frameAll();
        return;
      }
      li.classList.add('active');
      viewer.focusLoop(loop, colorOf(loop));
    });
    fragment.append(li);
  }
  if (loops.length > kMaxLoopItems) {
    const more = document.createElement('li');
    more.className = 'more';
    more.textContent = `… and ${loops.length - kMaxLoopItems} more`;
    fragment.append(more);
  }
  ol.append(fragment);
}

function arraysBytes(mesh) {
  let bytes = 0;
  const add = (v) => { if (ArrayBuffer.isView(v)) bytes += v.byteLength; };
  for (const value of Object.values(mesh)) {
    add(value);
    if (value && typeof value === 'object' && !ArrayBuffer.isView(value) && !Array.isArray(value)) Object.values(value).forEach(add);
  }
  for (const loop of [...(mesh.holes ?? []), ...(mesh.seams ?? [])]) Object.values(loop).forEach(add);
  return bytes;
}

function renderVerdict(stats) {
  const el = $('#verdict');
  const problems = [];
  const plural = (n, word) => `${n} ${word}${n === 1 ? '' : 's'}`;
  if (stats.holes) problems.push(plural(stats.holes, 'hole'));
  if (stats.seams) problems.push(plural(stats.seams, 'seam'));
  if (stats.nonManifoldEdges) problems.push(plural(stats.nonManifoldEdges, 'non-manifold edge'));
  if (stats.inconsistentEdges) problems.push(plural(stats.inconsistentEdges, 'flipped-face edge'));
  if (stats.nonManifoldVertices) problems.push(plural(stats.nonManifoldVertices, 'non-manifold vertex').replace('vertexs', 'vertices'));
  if (stats.degenerateTriangles) problems.push(plural(stats.degenerateTriangles, 'degenerate triangle'));
  if (stats.zeroAreaTriangles) problems.push(plural(stats.zeroAreaTriangles, 'zero-area triangle'));
  if (stats.duplicateTriangles) problems.push(plural(stats.duplicateTriangles, 'duplicate triangle'));
  if (stats.selfIntersections) problems.push(plural(stats.selfIntersections, 'self-intersecting pair'));
  const good = stats.watertight && stats.manifold;
  // The solid badge: the mesh bounds a volume without ambiguity (exact geometry).
  const solid = stats.solid === null ? '' : stats.solid ? ' <span class="badge solid">solid</span>'
    : ' <span class="badge not-solid">not solid</span>';
  el.className = `verdict ${good && stats.solid !== false ? 'good' : 'bad'}`;
  el.innerHTML = good
    ? `<span class="label">Watertight and manifold</span>${solid} · ${plural(stats.shells, 'shell')}, genus ${stats.genus}` +
      (problems.length ? ` · ${problems.join(', ')}` : '')
    : `<span class="label">${stats.watertight ? 'Watertight, not manifold' : 'Not watertight'}</span>${solid} · ${problems.join(', ') || 'empty mesh'}`;
}

export function showMesh(mesh, { name, credit, parseMs, sceneMs, totalMs }) {
  const stats = mesh.stats;
  renderStats(stats, name);
  renderVerdict(stats);
  for (const el of document.querySelectorAll('[data-count]')) {
    const n = stats[el.dataset.count];
    el.textContent = n === undefined || n === null ? '' : String(n);
    el.closest('.toggle')?.classList.toggle('problem', n > 0);
  }
  const holes = mesh.holes ?? [];
  const seams = mesh.seams ?? [];
  renderLoops('#hole-list', holes, 'hole', (h) => holeColor(h.id));
  renderLoops('#seam-list', seams, 'seam', () => colors.seams);
  renderShells(mesh);
  renderDefects(mesh);
  const inward = (mesh.shells ?? []).filter((sh) => sh.orientation === 'inward').length;
  const inwardCount = document.querySelector('[data-count="inwardShells"]');
  inwardCount.textContent = String(inward);
  inwardCount.closest('.toggle')?.classList.toggle('problem', inward > 0);
  $('#holes-empty').hidden = holes.length > 0;
  $('#seams-panel').hidden = seams.length === 0;
  const warnings = mesh.warnings ?? [];
  $('#warnings-panel').hidden = warnings.length === 0;
  $('#warning-list').innerHTML = '';
  for (const w of warnings) {
    const li = document.createElement('li');
    li.innerHTML = '<code></code> <span></span>';
    li.firstChild.textContent = w.code;
    li.lastChild.textContent = w.message;
    $('#warning-list').append(li);
  }
  const ms = (x) => (x < 1000 ? `${Math.round(x)} ms` : `${(x / 1000).toFixed(2)} s`);
  $('#load-time').textContent = ms(totalMs);
  $('#load-time').title = `read + parse + topology in the worker: ${ms(parseMs)}; building the 3D view: ${ms(sceneMs)}`;
  $('#memory').textContent = formatBytes(arraysBytes(mesh));
  $('#memory').title = 'Size of the mesh and topology arrays handed over by the worker';
  $('#threads').textContent = String(mesh.threads);
  $('#threads').title = mesh.threads > 1
    ? `read, topology and geometry ran on ${mesh.threads} threads (the threaded WebAssembly module: the page is cross-origin isolated)`
    : crossOriginIsolated ? 'one thread' : 'one thread: the page is not cross-origin isolated (its server sends no COOP/COEP headers), so there is no SharedArrayBuffer for the threaded module';
  $('#credit').textContent = credit;
}

/** The Model panel's note on a mesh too large for the whole view or the geometry pass ('' hides it). */
export function showScaleNote(text) {
  $('#scale-note').textContent = text;
  $('#scale-note').hidden = !text;
}

export function clearPanels() {
  showScaleNote('');
  $('#stats').textContent = '';
  $('#hole-list').textContent = '';
  $('#seam-list').textContent = '';
  $('#seams-panel').hidden = true;
  $('#shell-list').textContent = '';
  $('#shells-panel').hidden = true;
  $('#defect-list').textContent = '';
  $('#defects-panel').hidden = true;
  selectedShell = null;
  delete document.body.dataset.focusedDefect;
  $('#warnings-panel').hidden = true;
  $('#holes-empty').hidden = false;
  $('#verdict').textContent = '';
  $('#verdict').className = 'verdict';
  $('#load-time').textContent = '—';
  $('#memory').textContent = '—';
  $('#credit').textContent = '';
  document.querySelector('[data-stat="file"]').textContent = '';
  for (const el of document.querySelectorAll('[data-count]')) el.textContent = '';
}

/**
 * Drops the active list entry and the focused defect, and un-isolates the selected shell:
 * true when a shell was selected.
 */
function clearSelection() {
  document.querySelectorAll('.loop-list li.active, .defect-kind li.active').forEach((e) => e.classList.remove('active'));
  delete document.body.dataset.focusedDefect;
  if (selectedShell === null) return false;
  selectedShell = null;
  renderShellStats(null);
  viewer.isolateShell(null);
  return true;
}

/** The frame button: drops the active entry; un-isolates the selected shell, else frames all. */
export function resetView() {
  if (clearSelection()) return;
  viewer.frameAll();
}
