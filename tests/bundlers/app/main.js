// The consumer app every bundler in the matrix builds (tests/bundlers/run.mjs):
// what a web developer writes, nothing more. It loads the STL named by ?stl=
// on the main thread and through the worker, and leaves what it saw in
// window.__result for the test to compare with the native CLI. Then it uses what
// only the full module has (stltopo-full: writing, editing, shells), which the
// bundle must fetch on first use.
import { loadStl, toStl, EditableMesh, StlError } from 'stltopo';
import { loadStl as loadInWorker } from 'stltopo/worker';

const url = new URLSearchParams(location.search).get('stl');
const describe = (e) => ({ error: `${e && e.name}: ${e && e.message}`, code: e && e.code });

async function load(loader) {
  try {
    const mesh = await loader(await fetch(url));
    return { stats: mesh.stats, valid: mesh.validate().ok };
  } catch (e) {
    return describe(e);
  }
}

async function run() {
  const main = await load(loadStl);
  const worker = await load(loadInWorker);
  let errorCode = null;
  try {
    await loadStl(new Uint8Array(0));
  } catch (e) {
    errorCode = e instanceof StlError ? e.code : String(e);
  }
  let full;
  try {
    const mesh = await loadStl(await fetch(url));
    const written = await loadStl(await toStl(mesh));
    const em = await EditableMesh.from(mesh);
    em.removeTriangle(0);
    const shells = await loadInWorker(await fetch(url), { shells: true });
    full = {
      // The same mesh read back (the format and solids may differ: it is written binary).
      sameWritten: ['triangles', 'vertices', 'edges', 'holes', 'shells', 'volume'].every((k) => written.stats[k] === mesh.stats[k]),
      edited: em.stats.triangles === mesh.nTriangles - 1,
      shells: shells.shells.length === mesh.stats.shells,
    };
    em.dispose();
  } catch (e) {
    full = describe(e);
  }
  return { main, worker, errorCode, full };
}

run().then((r) => { window.__result = r; }, (e) => { window.__result = describe(e); });
