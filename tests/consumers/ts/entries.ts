// Every entry point a TypeScript user imports, as a user would use them.
import { loadStl, StlError, type Mesh } from 'stltopo';
import { loadStl as loadInWorker } from 'stltopo/worker';
import { toBufferGeometry } from 'stltopo/three';

export async function load(file: Blob): Promise<number> {
  try {
    const mesh: Mesh = await loadInWorker(file);
    const again = await loadStl(await file.arrayBuffer());
    return toBufferGeometry(mesh).getIndex()!.count + again.nTriangles;
  } catch (e) {
    if (e instanceof StlError) return e.code.length;
    throw e;
  }
}
