// The demo's "Overlapping shells" part of the Repair panel: the groups of closed shells that
// intersect each other (planUnion on the model on screen, from its exact intersection pass),
// "Unite" (unionShells with manifold-3d, loaded on first use: the model on screen becomes the
// union) and "Undo union" (the model before it, as it was).
//
// Test hooks: body[data-union] is "none" (no group), "ready" (a group can be united),
// "unfit" (groups, none can be united) or "unknown" (loaded without the exact geometry);
// body[data-union-groups] the number of groups, body[data-union-undo] how many unions Undo can
// take back, body[data-union-seq] counts the finished actions (errors included), and each
// group is li[data-union-group] (class "unfit", its reason in .reason).
import { planUnion, unionShells } from 'stltopo/worker';
import { $ } from './page.js';

const body = document.body;
let current = null; // { mesh, name } on screen
let undoStack = []; // the models before each union, last on top
let replaceModel = null; // load.js: puts a mesh on screen as the model
let manifold = null; // the manifold-3d module, once loaded
let busy = false;
let seq = 0;

const say = (text) => { $('#union-status').textContent = text; };

/** load.js hands over how to show a model (a call, so that the two modules do not import each other). */
export function setUnionReplace(f) {
  replaceModel = f;
}

/** The model on screen (load.js): a model loaded anew drops the unions' undo; a union's result keeps it. */
export function setUnionSource(value, { keepUndo = false } = {}) {
  current = value;
  if (!keepUndo) undoStack = [];
  body.dataset.unionUndo = String(undoStack.length);
  render();
}

function render() {
  const list = $('#union-groups');
  list.textContent = '';
  const mesh = current?.mesh;
  // Only the pass's own data (a mesh loaded with intersections): planUnion would run the pass.
  const known = mesh?.shells && mesh.triangleShell && mesh.stats.intersectionsComplete != null;
  if (!mesh || !known) {
    body.dataset.union = 'unknown';
    body.dataset.unionGroups = '0';
    say(mesh ? 'The model was loaded without the exact geometry: no overlap is known.' : '');
    update(false);
    return;
  }
  planUnion(mesh).then((plan) => {
    if (current?.mesh !== mesh) return; // another model meanwhile
    const fit = plan.groups.filter((g) => g.fit).length;
    body.dataset.union = plan.groups.length === 0 ? 'none' : fit ? 'ready' : 'unfit';
    body.dataset.unionGroups = String(plan.groups.length);
    for (const g of plan.groups) {
      const li = document.createElement('li');
      li.dataset.unionGroup = String(g.index);
      li.classList.toggle('unfit', !g.fit);
      li.textContent = `Shells ${g.shells.join(', ')}: ${g.triangles.toLocaleString('en-US')} triangles, volume ${+g.volume.toPrecision(6)}`;
      if (g.reason) {
        const r = document.createElement('span');
        r.className = 'reason';
        r.textContent = ` (${g.reason})`;
        li.append(r);
      }
      list.append(li);
    }
    say(plan.groups.length === 0 ? 'No closed shells overlap.'
      : `${plan.groups.length} group${plan.groups.length === 1 ? '' : 's'} of overlapping shells; ${fit} can be united`
        + ` (a boolean union by manifold-3d: the volume counted once).${plan.complete ? '' : ' The pass stopped at its work limit: there may be more.'}`);
    update(fit > 0);
  }, (error) => {
    say(`planUnion: ${error.message}`);
    update(false);
  });
}

function update(canUnite) {
  $('#union-unite').disabled = busy || !canUnite;
  $('#union-undo').disabled = busy || undoStack.length === 0;
}

async function act(name, f) {
  if (busy || !replaceModel) return;
  busy = true;
  body.dataset.unionBusy = 'true';
  update(false);
  try {
    await f();
  } catch (error) {
    say(`${name}: ${error.code ? `${error.code}: ` : ''}${error.message}`);
  } finally {
    busy = false;
    body.dataset.unionBusy = 'false';
    body.dataset.unionUndo = String(undoStack.length);
    body.dataset.unionSeq = String(++seq);
    update(body.dataset.union === 'ready');
  }
}

async function unite() {
  await act('Unite', async () => {
    const t0 = performance.now();
    const before = current;
    if (!manifold) {
      say('Loading manifold-3d…');
      const { default: Module } = await import('manifold-3d');
      const m = await Module();
      m.setup();
      manifold = m;
    }
    say('Uniting…');
    const r = await unionShells(before.mesh, { manifold });
    if (!r.mesh) {
      say('No group could be united: ' + r.groups.map((g) => g.reason).filter(Boolean).join('; '));
      return;
    }
    const united = r.groups.filter((g) => g.united);
    undoStack.push(before);
    await replaceModel(r.mesh, {
      name: before.name, t0, keepUnionUndo: true,
      credit: `United in the page: ${united.length} group${united.length === 1 ? '' : 's'} of overlapping shells (manifold-3d).`,
    });
  });
}

async function undoUnion() {
  await act('Undo union', async () => {
    const prev = undoStack.pop();
    if (!prev) return;
    await replaceModel(prev.mesh, { name: prev.name, t0: performance.now(), keepUnionUndo: true,
      credit: undoStack.length ? 'United in the page (manifold-3d).' : 'As loaded.' });
  });
}

$('#union-unite').addEventListener('click', unite);
$('#union-undo').addEventListener('click', undoUnion);
body.dataset.unionUndo = '0';
body.dataset.unionSeq = '0';
update(false);
