// The demo's edit-mode controls: the toggle, the tools, clicks on the model, fill, undo and
// download, around the editor of edit.js.
import { createEditor } from './edit.js';
import { $, viewer } from './page.js';
import { showMesh, onSelectHole } from './panels.js';

let loaded = null; // { mesh, name } on screen (the edit mode starts from it)

/** The mesh that load.js put on screen: the edit mode starts from it. */
export function setLoaded(value) {
  loaded = value;
}

const editor = createEditor({
  viewer,
  show(em) {
    viewer.setMesh(em, { keepView: true });
    showMesh(em, { name: loaded?.name ?? '', credit: '', parseMs: 0, sceneMs: 0, totalMs: 0 });
  },
  status(text) { $('#edit-status').textContent = text; },
});
onSelectHole((id) => editor.selectHole(id));
const tool = () => document.querySelector('input[name="edit-tool"]:checked').value;

export async function stopEditing() {
  if (!editor.mesh) return;
  editor.stop();
  $('#edit-mode').checked = false;
  $('#edit-tools').hidden = true;
  document.body.dataset.editing = 'false';
}

$('#edit-mode').addEventListener('change', async (event) => {
  if (!event.target.checked) {
    await stopEditing();
    if (loaded) {
      viewer.setMesh(loaded.mesh, { keepView: true });
      showMesh(loaded.mesh, { name: loaded.name, credit: '', parseMs: 0, sceneMs: 0, totalMs: 0 });
    }
    return;
  }
  if (!loaded) {
    event.target.checked = false;
    return;
  }
  await editor.start(loaded.mesh);
  $('#edit-tools').hidden = false;
  document.body.dataset.editing = 'true';
});
// A click (not a drag of the view) on the model edits it.
let down = null;
$('#viewport').addEventListener('pointerdown', (e) => { down = { x: e.clientX, y: e.clientY }; });
$('#viewport').addEventListener('pointerup', (e) => {
  if (!editor.mesh || !down || Math.hypot(e.clientX - down.x, e.clientY - down.y) > 4) return;
  if (e.target !== viewer.renderer.domElement) return;
  editor.click(viewer.pick(e.clientX, e.clientY), tool());
});
$('#fill-fan').addEventListener('click', () => editor.fill('fan'));
$('#fill-ear').addEventListener('click', () => editor.fill('ear'));
$('#undo-button').addEventListener('click', () => editor.undo());
$('#edit-download').addEventListener('click', () => editor.download(loaded?.name ?? 'mesh'));
