// The demo's edit mode: a copy of the loaded mesh as an EditableMesh (main thread). A click on the
// model removes a triangle, flips a face or flips its shell; the selected hole can be filled (fan
// or ear); undo goes back one edit (a snapshot of the triangles, fine for the demo's sizes);
// download writes the edited mesh as binary STL (EditableMesh.toStl: the package's writer).
//
// Test hooks: document.body.dataset.edits is the number of edits done; #edit-status says what the
// last one did (or why it was refused).
import { EditableMesh } from 'stltopo';

const kMaxUndo = 20;

export function createEditor({ viewer, show, status }) {
  let em = null; // the EditableMesh, compacted after every edit so that ids match the view
  let undo = [];
  let edits = 0;
  let selectedHole = null;

  const say = (text) => status(text);
  const refresh = () => {
    em.compact();
    show(em);
    document.body.dataset.edits = String(edits);
  };
  const snapshot = () => ({ positions: em.positions, triangles: em.triangles, attributes: em.attributes,
    colors: em.colors, colorValid: em.colorValid, colorConvention: em.colorConvention, format: em.format });

  async function run(what, edit) {
    if (!em) return false;
    const before = snapshot();
    try {
      const text = edit();
      undo.push(before);
      if (undo.length > kMaxUndo) undo.shift();
      ++edits;
      selectedHole = null;
      refresh();
      say(text ?? what);
      return true;
    } catch (e) {
      if (e.code !== 'edit-refused' && e.code !== 'invalid-argument') throw e;
      say(`${what}: ${e.message}`);
      return false;
    }
  }

  return {
    get mesh() { return em; },
    async start(mesh) {
      this.stop();
      em = await EditableMesh.from(mesh);
      undo = [];
      edits = 0;
      document.body.dataset.edits = '0';
      say('Edit mode: click the model.');
    },
    stop() {
      em?.dispose();
      em = null;
      selectedHole = null;
    },
    selectHole(id) { selectedHole = id; },
    click(triangle, tool) {
      if (triangle === null || triangle === undefined) return false;
      if (tool === 'remove') return run(`remove triangle ${triangle}`, () => { em.removeTriangle(triangle); });
      if (tool === 'flip') return run(`flip triangle ${triangle}`, () => { em.reverseTriangle(triangle); });
      return run(`flip the shell of triangle ${triangle}`, () => { em.reverseShell(triangle); });
    },
    fill(method) {
      const holes = em ? em.holes : [];
      const hole = holes.find((h) => h.id === selectedHole) ?? holes[0];
      if (!hole) {
        say('No hole to fill.');
        return false;
      }
      return run(`fill hole ${hole.id} (${method})`, () => {
        const added = em.fillHole(hole.id, { method });
        return `filled hole ${hole.id} with ${added.length} triangle${added.length === 1 ? '' : 's'} (${method})`;
      });
    },
    async undo() {
      const last = undo.pop();
      if (!last) {
        say('Nothing to undo.');
        return;
      }
      em.dispose();
      em = await EditableMesh.from(last);
      ++edits;
      refresh();
      say('Undone.');
    },
    download(name) {
      if (!em) return null;
      const bytes = em.toStl({ format: 'binary' });
      const url = URL.createObjectURL(new Blob([bytes], { type: 'model/stl' }));
      const a = document.createElement('a');
      a.href = url;
      a.download = `${name.replace(/\.stl$/i, '')}-edited.stl`;
      document.body.append(a);
      a.click();
      a.remove();
      setTimeout(() => URL.revokeObjectURL(url), 10000);
      return bytes;
    },
  };
}
