// Type-checked by scripts/test-node.sh (tsc --noEmit): uses the whole public API
// of 'stltopo', 'stltopo/worker' and 'stltopo/three' through the package's
// "exports" (self-reference), so the .d.ts files must match the package.
import {
  loadStl, loadStlFile, StlError, Mesh, kInvalid, EdgeKind, fromIndexed, writeStl, toStl, EditableMesh, planRepair, REPAIR_STEPS,
  planUnion, unionShells, type UnionGroup,
  type IndexedOptions, type WriteOptions, type RepairPlan, type RepairLog, type RepairStep, type RepairOptions,
  type LoadOptions, type StlInput, type Stats, type BoundaryLoop, type HalfedgeNavigation, type ValidateResult, type ErrorCode, type Warning, type Solid,
} from 'stltopo';
import * as worker from 'stltopo/worker';
import { toBufferGeometry, holesToLineSegments, problemEdgesToLineSegments, srgbByteTable, fromBufferGeometry } from 'stltopo/three';
import type { BufferGeometry, LineSegments } from 'three';

export async function useEverything(input: StlInput, blob: Blob, response: Response, stream: ReadableStream<Uint8Array>): Promise<number> {
  const controller = new AbortController();
  const options: LoadOptions = {
    topology: true,
    weld: { tolerance: 1e-4 },
    maxTriangles: 1 << 20,
    maxBytes: 0,
    normals: true,
    signal: controller.signal,
    onProgress: (fraction: number, bytesRead: number) => void [fraction, bytesRead],
    view: false,
    worker: false,
  };
  async function* chunks(): AsyncGenerator<Uint8Array> {
    yield new Uint8Array(84);
  }
  const inputs: StlInput[] = [new ArrayBuffer(84), new Uint8Array(84), new DataView(new ArrayBuffer(84)), blob, response, stream, chunks(), input];
  let total = inputs.length;
  const fromIterable: Mesh = await loadStl(chunks());
  total += fromIterable.nTriangles;

  const mesh: Mesh = await loadStl(new Uint8Array(84), options);
  const exact = await loadStl(blob, { weld: 'exact', view: true });
  exact.dispose();
  const fromDisk: Mesh = await loadStlFile('model.stl');
  const fromUrl: Mesh = await loadStlFile(new URL('file:///model.stl'));
  const inWorker: Mesh = await worker.loadStl(stream, { onProgress: (f) => void f, signal: controller.signal });
  const workerFile: Mesh = await worker.loadStlFile('model.stl');
  total += fromDisk.nTriangles + fromUrl.nVertices + inWorker.nHalfedges + workerFile.nTriangles;

  const format: 'binary' | 'ascii' | 'unknown' = mesh.format;
  const positions: Float32Array = mesh.positions;
  const triangles: Uint32Array = mesh.triangles;
  const attributes: Uint16Array = mesh.attributes;
  const colors: Uint8Array | null = mesh.colors;
  const colorValid: Uint8Array | null = mesh.colorValid;
  const convention: 'none' | 'viscam' | 'magics' = mesh.colorConvention;
  const normals: Float32Array | null = mesh.normals;
  const solids: Solid[] = mesh.solids;
  const warnings: Warning[] = mesh.warnings;
  total += format.length + positions.length + triangles.length + attributes.length + (colors?.length ?? 0) + (colorValid?.length ?? 0);
  total += convention.length + (normals?.length ?? 0) + solids.reduce((n, s) => n + s.firstTriangle + s.triangleCount + s.name.length, 0);
  total += warnings.reduce((n, w) => n + w.code.length + w.message.length + (w.offset ?? 0) + (w.line ?? 0) + (w.triangle ?? 0), 0);

  if (mesh.halfedges && mesh.problems && mesh.loops && mesh.triangleHalfedge && mesh.vertexHalfedge && mesh.loopHalfedge && mesh.vertexWeld) {
    const { next, prev, vert, face } = mesh.halfedges;
    total += next[0] + prev[0] + vert[0] + face[0];
    total += mesh.triangleHalfedge[0] + mesh.vertexHalfedge[0] + mesh.loopHalfedge[0] + mesh.vertexWeld[0];
    total += mesh.loops.offsets[0] + mesh.loops.halfedges[0] + mesh.loops.isSeam[0] + mesh.loops.perimeter[0];
    const kinds: Uint8Array = mesh.problems.pairKind;
    total += kinds[0] === EdgeKind.NonManifold ? 1 : 0;
    total += mesh.problems.triangleDegenerate[0] + mesh.problems.vertexNonManifold[0];
  }
  const loops: BoundaryLoop[] = [...mesh.holes, ...mesh.seams];
  for (const h of loops) total += h.id + h.face + h.halfedges[0] + h.vertices[0] + h.edgeCount + h.perimeter;

  const e = mesh.triangleHalfedge ? mesh.triangleHalfedge[0] : kInvalid;
  if (e !== kInvalid) {
    total += mesh.sym(e) + mesh.twin(e) + mesh.org(e) + mesh.dst(e) + mesh.lFace(e) + mesh.rFace(e) + mesh.lNext(e) + mesh.lPrev(e);
    total += mesh.vnext(e) + mesh.oNext(e) + mesh.oPrev(e) + mesh.dNext(e) + mesh.dPrev(e) + mesh.rNext(e) + mesh.rPrev(e);
    for (const h of mesh.faceHalfedges(e)) total += h;
    for (const h of mesh.outgoingHalfedges(e)) total += h;
  }

  const stats: Stats = mesh.stats;
  total += stats.triangles + stats.vertices + stats.area + stats.volume + (stats.edges ?? 0) + (stats.genus ?? 0);
  const genus: number | null | undefined = stats.genus;
  total += (genus === null ? 1 : 0) + (stats.weldedVertices ?? stats.vertices);
  if (stats.bbox) total += stats.bbox.min[0] + stats.bbox.max[2];

  const v: ValidateResult = mesh.validate();
  if (!v.ok) total += v.message.length + (v.element ?? 0);
  mesh.dispose();
  total += mesh.view ? 1 : 0;

  try {
    await loadStl(new ArrayBuffer(0));
  } catch (err) {
    if (err instanceof StlError) {
      const code: ErrorCode = err.code;
      total += code.length + (err.offset ?? 0) + (err.line ?? 0) + (err.triangle ?? 0) + err.message.length;
      const name: 'StlError' = err.name;
      total += name.length;
    }
  }
  const made = new StlError('aborted', 'aborted: by hand', { offset: 1 });
  total += made instanceof Error ? 1 : 0;
  const w = new worker.StlError('empty', 'empty: x');
  total += w.code.length;

  const geometry: BufferGeometry = toBufferGeometry(mesh, { colors: true, normals: true, defaultColor: [1, 2, 3] });
  const holes: LineSegments = holesToLineSegments(mesh, { color: 0xff0000, seams: true, seamColor: 0x00ff00 });
  const problems = problemEdgesToLineSegments(mesh, { nonManifoldColor: 0xff00ff, inconsistentColor: 0xffa000 });
  total += geometry.attributes.position.count + holes.userData.halfedges.length + holes.userData.loops.length;
  total += problems.userData.kinds.length + problems.userData.halfedges.length;
  const linear: Float32Array = srgbByteTable();
  total += linear[255];

  const io: IndexedOptions = {
    weld: 'none', attributes: new Uint16Array(1), solids: [{ name: 'a', firstTriangle: 0, triangleCount: 1 }], worker: true, view: false,
  };
  const indexed: Mesh = await fromIndexed(new Float32Array(9), new Uint32Array([0, 1, 2]), io);
  const fromArrays: Mesh = await fromIndexed([0, 0, 0, 1, 0, 0, 0, 1, 0], [0, 1, 2], { weld: { tolerance: 1e-3 }, colors: [1, 2, 3] });
  const map: Uint32Array | null = indexed.inputVertexMap;
  const wo: WriteOptions = { format: 'ascii', colors: 'magics', name: 'x', normals: 'computed', chunkBytes: 1 << 16, worker: false };
  for await (const chunk of writeStl(indexed, wo)) total += chunk.length;
  const file: Blob | Uint8Array = await toStl(fromArrays, { format: 'binary', colors: 'as-mesh' });
  const workerFile2: Blob | Uint8Array = await worker.toStl(indexed);
  for await (const chunk of worker.writeStl(indexed)) total += chunk.byteLength;
  const fromThree: Mesh = await fromBufferGeometry(geometry, { weld: 'exact' });
  const fromWorker: Mesh = await worker.fromIndexed(new Float32Array(9), [0, 1, 2]);
  total += (map ? map.length : 0) + (file instanceof Blob ? file.size : file.length) + fromThree.nTriangles + fromWorker.nVertices;
  total += workerFile2 instanceof Blob ? 1 : 0;
  return total;
}

// @ts-expect-error: the write format is binary or ascii
export const badWriteFormat: WriteOptions = { format: 'obj' };

// @ts-expect-error: the format is a closed union
export const badFormat: Mesh['format'] = 'obj';
// @ts-expect-error: weld takes 'exact' or { tolerance }
export const badWeld: LoadOptions = { weld: 'loose' };

// EditableMesh: the edits, attributes and results are typed.
export async function editing(mesh: Mesh): Promise<number> {
  const em: EditableMesh = await EditableMesh.from(mesh, { tolerance: 0 });
  const indexed = await EditableMesh.from({ positions: new Float32Array(9), triangles: new Uint32Array([0, 1, 2]) });
  em.removeTriangle(0);
  em.setPosition(0, 1, 2, 3);
  const filled: Uint32Array = em.fillHole(em.holes[0], { method: 'ear' });
  const v: number = em.splitEdge(0, 0.25) + em.collapseEdge(1) + em.addTriangle(0, 1, 2, { nonManifold: true });
  em.addAttribute('temp', 'vertex', new Float32Array(em.nVertices), { merge: (a, b, t) => [a[0] * (1 - t) + b[0] * t], split: 'average' });
  const maps = em.compact();
  const face: number = em.halfedges.face[0] >= em.nTriangles ? em.halfedges.face[0] - em.nTriangles : 0;
  const loop: BoundaryLoop = em.holes[0];
  const loopFace: number = loop.face + em.loops.offsets[0] + em.problems.pairKind[0] + em.stats.holes;
  const ok = em.validate().ok ? 1 : 0;
  // A Mesh and an EditableMesh navigate the same way (HalfedgeNavigation).
  const walk = (n: HalfedgeNavigation, e: number): number => n.lNext(n.sym(e)) + n.oPrev(e) + [...n.faceHalfedges(e)].length;
  const walked: number = walk(em, 0) + walk(mesh, 0);
  em.dispose();
  indexed.dispose();
  return filled.length + v + maps.triangles.length + face + loopFace + ok + walked + em.stats.triangles;
}

// Stats are typed by what the mesh holds: a default load (topology) has every topology
// count, so arithmetic on them compiles under strict; { topology: false } has none.
export async function statsByTopology(input: StlInput): Promise<number> {
  const mesh = await loadStl(input);
  const holes: number = mesh.stats.holes + 1;
  const watertight: boolean = mesh.stats.watertight;
  const genus: number | null = mesh.stats.genus;
  const bare = await loadStl(input, { topology: false });
  // @ts-expect-error a mesh without topology has no topology counts
  const none = bare.stats.holes;
  const either: Stats = bare.stats;
  return holes + (watertight ? 1 : 0) + (genus ?? 0) + (either.holes ?? 0) + (none === undefined ? 0 : 1);
}

// Repair: the plan, the log and undo are typed; step names are a closed union.
export async function repairing(mesh: Mesh): Promise<number> {
  const plan: RepairPlan = await planRepair(mesh, { steps: ['duplicates', 'fill-holes'], fill: ['refine'], maxHoleEdges: 50 });
  const em = await EditableMesh.from(mesh);
  const again: RepairPlan = em.planRepair({ exclude: [{ step: 'fill-holes', item: 0 }] });
  const log: RepairLog = em.applyRepair(plan);
  const undone: RepairStep | null = em.undo();
  const removed: Uint32Array = log.steps[0].removedTriangles;
  const first: Uint32Array = plan.steps[0].items[0].triangles;
  const solid: boolean | null = log.after.solid;
  const steps: readonly RepairStep[] = REPAIR_STEPS;
  em.dispose();
  return removed.length + first.length + again.steps.length + (solid ? 1 : 0) + (undone ? 1 : 0) + steps.length + em.undoableSteps;
}
// @ts-expect-error: step names are a closed union
export const badStep: RepairOptions = { steps: ['holes'] };
export async function repairingInAWorker(mesh: Mesh): Promise<number> {
  const plan = await worker.planRepair(mesh, { steps: ['orient'] });
  const { mesh: repaired, log } = await worker.applyRepair(mesh, plan, { shells: true });
  return repaired.stats.triangles + log.steps.length;
}
// Step-by-step undo in a worker: the same calls, each a Promise.
export async function undoingInAWorker(mesh: Mesh): Promise<number> {
  const em: worker.WorkerEditableMesh = await worker.WorkerEditableMesh.from(mesh, { tolerance: 0 });
  const plan: RepairPlan = await em.planRepair({ steps: ['orient', 'fill-holes'] });
  const again: RepairPlan = await worker.planRepair(em, { exclude: [{ step: 'orient', item: 0 }] });
  const log: RepairLog = await em.applyRepair(plan);
  const undone: RepairStep | null = await em.undo();
  const n: number = em.undoableSteps;
  const bytes: Uint8Array = await em.toStl({ format: 'ascii' });
  const result: Mesh<true> = await em.toMesh({ shells: true });
  const bare: Mesh<false> = await em.toMesh({ topology: false });
  const watertight: boolean = (await em.stats()).watertight;
  const ok: boolean = (await em.validate()).ok;
  // @ts-expect-error: toMesh() keeps the editable mesh's vertices (no weld option)
  await em.toMesh({ weld: 'exact' });
  await em.dispose();
  const fromIndexedInput = await worker.WorkerEditableMesh.from({ positions: new Float32Array(9), triangles: new Uint32Array([0, 1, 2]) });
  await fromIndexedInput.dispose();
  return log.steps.length + again.steps.length + (undone ? 1 : 0) + n + bytes.length + result.nTriangles + bare.nTriangles
    + (watertight ? 1 : 0) + (ok ? 1 : 0);
}
export async function joining(mesh: Mesh): Promise<number> {
  const em = await EditableMesh.from(mesh);
  em.mergeVertices([1, 2], new Uint32Array([4, 5]), { nonManifold: false });
  em.splitEdgeAt(0, 3);
  em.stitch({ keep: [1], gone: [2], edges: [5], vertices: [6] });
  const { first, count }: { first: number; count: number } = em.splitVertex(0);
  em.dispose();
  return first + count;
}
// Overlapping shells: the groups, and their union through manifold-3d (passed in).
export async function uniting(mesh: Mesh, manifold: unknown): Promise<number> {
  const { groups, complete } = await planUnion(mesh);
  const fit: UnionGroup[] = groups.filter((g) => g.fit);
  const r = await unionShells(mesh, { manifold, groups: fit.map((g) => g.index), load: { shells: true } });
  const w = await worker.unionShells(mesh, { manifold });
  const volume: number = r.groups[0]?.result?.volume ?? 0;
  // @ts-expect-error: manifold-3d is required
  await unionShells(mesh, {});
  return (r.mesh ? r.mesh.nTriangles : 0) + (w.mesh?.nTriangles ?? 0) + volume + (complete ? 1 : 0);
}
