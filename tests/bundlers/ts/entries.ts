// Every entry point a TypeScript user imports, as a user would use them, and the types
// of loadStl's overloads: topology fields are set by default and with { topology: true },
// null with { topology: false }, either when the options are only known at run time.
import { loadStl, init, StlError, type Mesh, type LoadOptions } from 'stltopo';
import { loadStl as loadInWorker } from 'stltopo/worker';
import { toBufferGeometry } from 'stltopo/three';

init({ wasmUrl: '/assets/stltopo-wasm.wasm', workerUrl: new URL('https://example.com/worker-thread.js') });

export async function load(file: Blob, options: LoadOptions): Promise<number> {
  try {
    const mesh = await loadInWorker(file);
    const { next, vert, face } = mesh.halfedges;
    const explicit = await loadStl(await file.arrayBuffer(), { topology: true, weld: { tolerance: 1e-5 } });
    const lean = await loadStl(file, { topology: false });
    const none: null = lean.halfedges;
    // @ts-expect-error: no topology, no half-edges
    void lean.triangleHalfedge.length;
    const unknown: Mesh = await loadStl(file, options);
    // @ts-expect-error: with options known only at run time the topology may be null
    void unknown.halfedges.next;
    const any: Mesh = explicit;
    return toBufferGeometry(mesh).index!.count + next[0] + vert[0] + face[0] + explicit.loops.offsets.length
      + (none === null ? 0 : 1) + (unknown.halfedges?.next.length ?? 0) + any.nTriangles;
  } catch (e) {
    if (e instanceof StlError) return e.code === 'wasm-load' ? -1 : e.code.length;
    throw e;
  }
}
