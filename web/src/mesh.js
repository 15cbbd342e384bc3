// The Mesh that loadStl() resolves to, built from a raw result: plain data made by
// wasm.js (extractRaw) on this thread or received from a worker thread. Its array
// properties follow the bindings' array table (raw.layout: STLTOPO_JS_ARRAYS in
// bindings/arrays.h), one row per array: { name, group, key, element, width, when,
// copied, derived, type, doc }.
//
// Copies (the default): every array is a plain property holding a JS-owned typed array,
// except the `derived` ones that raw.arrays lacks (prev, face, vert of inline loads), which
// are rebuilt in JS on first read (deriveArray) and then kept.
// Views ({ view: true }): a getter per array that re-creates its view into wasm memory when
// memory growth detached it; `copied` arrays are plain copies even then.
import { stlError } from './errors.js';

export const kInvalid = 0xffffffff;

/** Edge classes per half-edge pair k = e >> 1 (mesh.problems.pairKind). */
export const EdgeKind = Object.freeze({ Interior: 0, Boundary: 1, Inconsistent: 2, NonManifold: 3 });

/** Whether the array of table row d exists for a raw result. */
export function isPresent(d, raw) {
  switch (d.when) {
    case 'mesh': return true;
    case 'normals': return raw.hasNormals;
    case 'colors': return raw.colorConvention !== 'none';
    case 'topology': return raw.hasTopology;
    case 'shells': return !!raw.hasShells;
    case 'intersections': return !!raw.hasIntersections;
    case 'indexed': return !!raw.indexed;
    default: throw new Error(`stltopo: array ${d.name} has an unknown condition '${d.when}'`);
  }
}

/** The arrays that make the mesh itself (what a writer reads), as opposed to its topology. */
export const isMeshArray = (d) => d.when === 'mesh' || d.when === 'normals' || d.when === 'colors';

// Where a mesh's data lives besides its JS arrays: the wasm session of a { view: true } mesh
// ({ entry, session }), and the worker loader of a mesh a worker made (its writes run in a
// worker too).
export const liveSession = new WeakMap();
export const workerHome = new WeakMap();
const layouts = new WeakMap(); // mesh -> the array table it was made with

// Makes obj[key] a plain property holding value (where a first-read getter was).
const settle = (obj, key, value) =>
  Object.defineProperty(obj, key, { value, enumerable: true, writable: true, configurable: true });

// findIntersections() of the instance that made the API (wasm.js): the full module.
let intersectionFinder = null;
export function setIntersectionFinder(f) {
  if (!intersectionFinder) intersectionFinder = f;
}

// The one finalizer of the package (a { view: true } Mesh and an EditableMesh: their wasm
// sessions; a WorkerEditableMesh: its mesh in a worker): an owner dropped without dispose()
// still frees what it holds, eventually.
const registry = typeof FinalizationRegistry === 'function'
  ? new FinalizationRegistry((held) => {
    if (held.release) held.release();
    else if (!held.entry.dead && !held.session.isDeleted()) held.session.delete();
  })
  : null;
/** Frees `session` when `owner` is garbage-collected, unless untrackSession(owner) ran first. */
export function trackSession(owner, entry, session) {
  if (registry) registry.register(owner, { entry, session }, owner);
}
/**
 * Calls release() when `owner` is garbage-collected, unless untrackSession(owner) ran first.
 * release must not hold `owner` (the registry would keep it alive).
 */
export function trackRelease(owner, release) {
  if (registry) registry.register(owner, { release }, owner);
}
export function untrackSession(owner) {
  if (registry) registry.unregister(owner);
}

const ORIENTATIONS = ['inconsistent', 'open', 'outward', 'inward', 'flat']; // Orientation's order
const kMixedSolid = kInvalid - 1;

/**
 * mesh.shells from the bindings' columns (FullSession::shellTable): each shell's object with
 * the keys, in order, and the values of its JSON in `info --json --shells` (the bounding box
 * as float32 values).
 */
function buildShells(t) {
  const { names, counts, reals, box } = t;
  const k = names.length + 3;
  const n = reals.length / 4;
  const nest = t.parent ? t : null;
  const shells = new Array(n);
  for (let i = 0; i < n; ++i) {
    const c = i * k;
    const s = { id: i };
    for (let j = 0; j < names.length; ++j) s[names[j]] = counts[c + j];
    const solid = counts[c + k - 3];
    const flags = counts[c + k - 1];
    s.eulerCharacteristic = reals[4 * i];
    s.genus = flags & 8 ? reals[4 * i + 1] : null;
    s.closed = (flags & 1) !== 0;
    s.manifold = (flags & 2) !== 0;
    s.consistent = (flags & 4) !== 0;
    s.orientation = ORIENTATIONS[counts[c + k - 2]];
    s.solid = solid === kMixedSolid ? 'mixed' : solid === kInvalid ? null : solid;
    s.bbox = { min: [box[6 * i], box[6 * i + 1], box[6 * i + 2]], max: [box[6 * i + 3], box[6 * i + 4], box[6 * i + 5]] };
    s.area = reals[4 * i + 2];
    s.volume = reals[4 * i + 3];
    if (nest) {
      s.selfIntersects = nest.selfIntersects[i] !== 0;
      s.intersectsShells = Array.from(nest.intersectsShells.subarray(nest.intersectsOffsets[i], nest.intersectsOffsets[i + 1]));
      s.parent = nest.parent[i] === kInvalid ? null : nest.parent[i];
      s.depth = nest.depth[i] === kInvalid ? null : nest.depth[i];
    }
    shells[i] = s;
  }
  return shells;
}

/**
 * The boundary loops as { holes, seams }, for Mesh and EditableMesh alike: loop h is
 * { id: h, face: nTriangles + h, halfedges, vertices, edgeCount, perimeter }. arrays holds
 * loopOffsets, loopHalfedges, loopIsSeam, loopPerimeter and either loopVertices (the origin
 * of every loop half-edge, an array of the loops' own: each loop's vertices are a view of
 * it) or vert. Both meshes build the lists on first read of `holes` or `seams`: a triangle
 * soup has a loop per triangle, and its millions of objects (some 300 bytes of JS heap
 * each) once made a load of an 11M-triangle soup end Node with a fatal out-of-memory.
 */
export function buildLoops(arrays, nTriangles) {
  const holes = [];
  const seams = [];
  const off = arrays.loopOffsets;
  if (!off) return { holes, seams };
  const list = arrays.loopHalfedges;
  const lv = arrays.loopVertices;
  const vert = arrays.vert;
  for (let h = 0; h + 1 < off.length; ++h) {
    const halfedges = list.subarray(off[h], off[h + 1]);
    const vertices = lv ? lv.subarray(off[h], off[h + 1]) : halfedges.map((e) => vert[e]);
    const loop = { id: h, face: nTriangles + h, halfedges, vertices, edgeCount: halfedges.length, perimeter: arrays.loopPerimeter[h] };
    (arrays.loopIsSeam[h] ? seams : holes).push(loop);
  }
  return { holes, seams };
}

// The arrays of the table marked `derived`, rebuilt from the arrays a copy holds. Every
// triangle half-edge is reached from triangleHalfedge through next; every loop half-edge
// e is listed in its loop, and its origin is the destination of its twin (a triangle
// half-edge), which is the origin of next[e ^ 1].
//
// The derived half-edge arrays (kDerived rows: prev, face, vert) of a mesh whose arrays were
// copied out of wasm: the core did not build prev and face for it (8 fewer bytes per half-edge
// at its peak), nor copied vert. The first read of any of them builds all three in one pass
// over the triangles and the loops, 12 bytes per half-edge (1M-triangle torus, Node 20, medians
// of 21: 35 ms in grid order, where three passes took 46 and a plain copy of three such arrays
// 29; on a shuffled file one pass or three cost the same, 120-150 ms, the random writes).
export const DERIVED_HALFEDGE_ARRAYS = Object.freeze(['prev', 'face', 'vert']);
function deriveHalfedges(arrays, nTriangles) {
  const next = arrays.next;
  const th = arrays.triangleHalfedge;
  const list = arrays.loopHalfedges;
  const off = arrays.loopOffsets;
  const tri = arrays.triangles;
  const weld = arrays.vertexWeld;
  const n = next.length;
  const prev = new Uint32Array(n);
  const face = new Uint32Array(n);
  const vert = new Uint32Array(n);
  // The exact weld maps every vertex to itself: then skip the lookup, a random read per
  // corner on a shuffled file.
  let identity = true;
  for (let v = 0; v < weld.length && identity; ++v) identity = weld[v] === v;
  for (let t = 0; t < nTriangles; ++t) {
    const h0 = th[t];
    if (h0 === kInvalid) continue;
    const h1 = next[h0];
    const h2 = next[h1];
    prev[h1] = h0;
    prev[h2] = h1;
    prev[h0] = h2;
    face[h0] = t;
    face[h1] = t;
    face[h2] = t;
    const a = tri[3 * t], b = tri[3 * t + 1], c = tri[3 * t + 2];
    vert[h0] = identity ? a : weld[a];
    vert[h1] = identity ? b : weld[b];
    vert[h2] = identity ? c : weld[c];
  }
  // A loop half-edge starts where its twin (a triangle's) ends.
  for (let h = 0; h + 1 < off.length; ++h) {
    for (let i = off[h]; i < off[h + 1]; ++i) {
      const e = list[i];
      face[e] = nTriangles + h;
      prev[next[e]] = e;
      vert[e] = vert[next[(e ^ 1) >>> 0]];
    }
  }
  return { prev, face, vert };
}

const disposedError = () => stlError('invalid-argument', 'the mesh was disposed');

export class Mesh {
  #entry;
  #session;
  #getEntry;
  #counts;
  #validation;
  #layout;
  #disposed = false;

  constructor(raw, { entry = null, session = null, getEntry = () => null } = {}) {
    this.#entry = entry;
    this.#session = session;
    this.#getEntry = getEntry;
    this.#counts = raw.counts;
    this.#validation = raw.validation || null;
    this.#layout = raw.layout;
    layouts.set(this, raw.layout);
    const live = session !== null;
    /** true when the arrays are borrowed views into wasm memory (dispose() frees them). */
    this.view = live;
    this.format = raw.format;
    this.nVertices = raw.nVertices;
    this.nTriangles = raw.nTriangles;
    this.colorConvention = raw.colorConvention;
    this.solids = raw.solids;
    this.warnings = raw.warnings;
    /** The threads the load ran on (1: the single-threaded module; see the `threads` option). */
    this.threads = raw.threads || 1;
    const arrays = raw.arrays;
    this.nHalfedges = raw.hasTopology ? arrays.next.length : 0;
    const cache = live ? { ...arrays } : arrays;
    let derived = null; // deriveHalfedges() of a copy, on the first read of prev, face or vert
    // A view's array `name`, re-created when memory growth detached it.
    const current = (name) => {
      let a = cache[name];
      if (a.buffer.byteLength === 0) cache[name] = a = session.array(name, false);
      return a;
    };
    // The arrays deriveHalfedges reads, for a view.
    const liveArrays = () => Object.fromEntries(
      ['next', 'triangleHalfedge', 'loopHalfedges', 'loopOffsets', 'triangles', 'vertexWeld'].map((n) => [n, current(n)]));
    const groups = new Map(); // group name -> its object, or null when none of its arrays exists
    for (const d of raw.layout) {
      let obj = this;
      if (d.group) {
        if (!groups.has(d.group)) {
          groups.set(d.group, isPresent(d, raw) ? {} : null);
          this[d.group] = groups.get(d.group);
        }
        obj = groups.get(d.group);
        if (obj === null) continue;
      }
      if (!isPresent(d, raw)) {
        obj[d.key] = null;
      } else if (arrays[d.name] === undefined && d.derived) {
        if (!DERIVED_HALFEDGE_ARRAYS.includes(d.name)) throw new Error(`stltopo: no JS rebuild for the derived array ${d.name}`);
        // (a view whose heap could not hold prev and face: derived from its views, and read
        // through this getter, which answers the disposed error as the views' getters do)
        Object.defineProperty(obj, d.key, {
          enumerable: true,
          configurable: true,
          get: () => {
            if (this.#disposed) throw disposedError();
            derived ??= deriveHalfedges(live ? liveArrays() : arrays, raw.nTriangles);
            const a = derived[d.name];
            if (!live) settle(obj, d.key, a);
            return a;
          },
        });
      } else if (!live || d.copied) {
        obj[d.key] = arrays[d.name];
      } else {
        Object.defineProperty(obj, d.key, {
          enumerable: true,
          get: () => {
            if (this.#disposed) throw disposedError();
            return current(d.name);
          },
        });
      }
    }
    // A table without the geometry rows (the core module's) still gives the property.
    if (this.intersections === undefined) this.intersections = null;
    // holes and seams: built together on the first read of either (buildLoops), then plain
    // properties; one the caller set first keeps its value.
    for (const key of ['holes', 'seams']) {
      Object.defineProperty(this, key, {
        enumerable: true,
        configurable: true,
        get: () => { // (the loop arrays are copies, also in a view: readable after dispose())
          const loops = buildLoops(arrays, raw.nTriangles);
          for (const k of ['holes', 'seams']) if (Object.getOwnPropertyDescriptor(this, k).get) settle(this, k, loops[k]);
          return loops[key];
        },
        set: (v) => settle(this, key, v),
      });
    }
    /** The report of each shell (the fields of `info --json --shells`), with { shells: true }. */
    if (!raw.hasShells) {
      this.shells = null;
    } else {
      // Built on first read, then a plain property (one the caller set first stays): a soup
      // has a shell a triangle, some 430 bytes of JS heap each (2M shells: 0.86 GiB).
      Object.defineProperty(this, 'shells', {
        enumerable: true,
        configurable: true,
        get: () => {
          const shells = buildShells(raw.shellTable);
          settle(this, 'shells', shells);
          return shells;
        },
        set: (v) => settle(this, 'shells', v),
      });
    }
    const stats = JSON.parse(raw.statsJson);
    delete stats.file;
    this.stats = stats;
    if (live) trackSession(this, entry, session);
    if (live) liveSession.set(this, { entry, session });
  }

  // Navigation (face[e] is the left face of e). Same names as the C++ header.
  sym(e) { return (e ^ 1) >>> 0; }
  twin(e) { return (e ^ 1) >>> 0; }
  org(e) { return this.halfedges.vert[e]; }
  dst(e) { return this.halfedges.vert[(e ^ 1) >>> 0]; }
  lFace(e) { return this.halfedges.face[e]; }
  rFace(e) { return this.halfedges.face[(e ^ 1) >>> 0]; }
  lNext(e) { return this.halfedges.next[e]; }
  lPrev(e) { return this.halfedges.prev[e]; }
  vnext(e) { return this.halfedges.next[(e ^ 1) >>> 0]; }
  oPrev(e) { return this.halfedges.next[(e ^ 1) >>> 0]; }
  oNext(e) { return (this.halfedges.prev[e] ^ 1) >>> 0; }
  rPrev(e) { return this.oNext((e ^ 1) >>> 0); }
  rNext(e) { return (this.oPrev(e) ^ 1) >>> 0; }
  dNext(e) { return (this.rPrev(e) ^ 1) >>> 0; }
  dPrev(e) { return (this.halfedges.next[e] ^ 1) >>> 0; }

  /** The half-edges of the face (triangle or boundary loop) left of e0, in next order. */
  *faceHalfedges(e0) {
    const next = this.halfedges.next;
    let e = e0;
    for (let i = 0; i < next.length; ++i) {
      yield e;
      e = next[e];
      if (e === e0) return;
    }
  }

  /** The outgoing half-edges of org(e0), following vnext (the cycle that contains e0). */
  *outgoingHalfedges(e0) {
    const next = this.halfedges.next;
    let e = e0;
    for (let i = 0; i < next.length; ++i) {
      yield e;
      e = next[(e ^ 1) >>> 0];
      if (e === e0) return;
    }
  }

  /**
   * The exact geometry of this mesh, whatever it was loaded with: { stats (the intersection
   * keys of info --json --intersections), shells (with nesting), triangleShell,
   * intersections (the arrays of mesh.intersections) }. Options: { maxPairs, worker, signal }.
   */
  findIntersections(options) {
    if (this.#disposed) return Promise.reject(disposedError());
    if (!intersectionFinder) return Promise.reject(stlError('invalid-argument', 'no stltopo instance to run findIntersections()'));
    return intersectionFinder(this, options);
  }

  /** The number of defects of a kind (DEFECT_KINDS); needs { shells: true }. */
  defectCount(kind) {
    return defectCount(this, kind);
  }

  /**
   * Defect i of a kind as an object, in the shape of `info --json --defects` items (no
   * list cut); needs { shells: true }.
   */
  defect(kind, i) {
    return defectItem(this, kind, i);
  }

  /** Checks every topology invariant: { ok: true } or the first violation. */
  validate() {
    if (this.#disposed) throw disposedError();
    if (this.#validation) return { ...this.#validation };
    if (this.#session) return toValidation(this.#session.validate());
    if (!this.halfedges) {
      return { ok: false, code: 'invalid-argument', message: 'invalid-argument: the mesh has no topology (loaded with topology: false)' };
    }
    const entry = this.#getEntry();
    if (!entry) throw new Error('stltopo: validate() needs the wasm module on this thread; call loadStl() here first');
    return validateArrays(entry.module, this, this.#layout, this.#counts);
  }

  /** Frees the wasm memory of a { view: true } mesh; a no-op for copies. */
  dispose() {
    if (this.#disposed || !this.#session) return;
    this.#disposed = true;
    liveSession.delete(this);
    untrackSession(this);
    if (!this.#entry.dead) this.#session.delete();
    this.#session = null;
  }
}

/** The array of table row d on a mesh (null when it does not exist). */
export function meshArray(mesh, d) {
  const obj = d.group ? mesh[d.group] : mesh;
  return obj ? obj[d.key] : null;
}

/** validate()'s result for a mesh whose prev and face did not fit in the wasm heap. */
export const NO_ROOM_FOR_PREV_FACE = Object.freeze({
  ok: false,
  code: 'out-of-memory',
  message: 'out-of-memory: validate() needs prev and face in the wasm heap, which could not hold them with this mesh ' +
    '(they were derived in JS)',
});

/** validate()'s result from a status object of the bindings (null = ok). */
export function toValidation(st) {
  if (!st) return { ok: true };
  const r = { ok: false, code: st.code, message: st.message };
  if (st.element !== undefined) r.element = st.element;
  return r;
}

// validate() of a copy: uploads its arrays into a fresh wasm session and checks them there.
function validateArrays(M, mesh, layout, counts) {
  const s = new M._Session(0, 0, 0, false);
  try {
    for (const d of layout) {
      const src = meshArray(mesh, d);
      if (!src) continue;
      const view = s.upload(d.name, src.length);
      if (view === null) throw stlError('out-of-memory', `could not allocate ${d.name} for validate()`);
      view.set(src);
    }
    s.setCounts(counts);
    return toValidation(s.validate());
  } finally {
    s.delete();
  }
}


/** The kinds of defect, in the order of the report. */
export const DEFECT_KINDS = Object.freeze(['holes', 'seams', 'nonManifoldEdges', 'inconsistentEdges',
  'nonManifoldVertices', 'degenerateTriangles']);
/** The geometric kinds (after DEFECT_KINDS in the report), with { intersections: true }. */
export const GEOMETRY_DEFECT_KINDS = Object.freeze(['zeroAreaTriangles', 'duplicateTriangles', 'selfIntersections']);
const GEOMETRY_KINDS = GEOMETRY_DEFECT_KINDS;
const DUPLICATE_ORIENTATIONS = ['same', 'opposite', 'mixed'];
/** The kind of an intersecting pair (mesh.intersections.kinds). */
export const INTERSECTION_KINDS = Object.freeze(['crossing', 'touching', 'coplanar']);

function intersectionsOf(mesh) {
  if (!mesh.intersections) {
    throw stlError('invalid-argument', 'the mesh has no intersection lists (load it with { intersections: true })');
  }
  return mesh.intersections;
}

function defectsOf(mesh) {
  if (!mesh.defects) throw stlError('invalid-argument', 'the mesh has no defect lists (load it with { shells: true })');
  return mesh.defects;
}

function defectCount(mesh, kind) {
  if (GEOMETRY_KINDS.includes(kind)) {
    const x = intersectionsOf(mesh);
    if (kind === 'zeroAreaTriangles') return x.zeroAreaTriangles.length;
    if (kind === 'duplicateTriangles') return x.duplicateOffsets.length - 1;
    return x.kinds.length;
  }
  const d = defectsOf(mesh);
  switch (kind) {
    case 'holes': return mesh.holes.length;
    case 'seams': return mesh.seams.length;
    case 'nonManifoldEdges': return d.nonManifoldEdgeVertices.length / 2;
    case 'inconsistentEdges': return d.inconsistentEdgeVertices.length / 2;
    case 'nonManifoldVertices': return d.nonManifoldVertices.length;
    case 'degenerateTriangles': return d.degenerateTriangles.length;
    default: throw stlError('invalid-argument', `unknown defect kind '${kind}' (one of ${DEFECT_KINDS.join(', ')})`);
  }
}

function position(mesh, v) {
  const p = mesh.positions;
  return [p[3 * v], p[3 * v + 1], p[3 * v + 2]];
}

function box(mesh, vertices) {
  const min = position(mesh, vertices[0]);
  const max = min.slice();
  for (const v of vertices) {
    const q = position(mesh, v);
    for (let k = 0; k < 3; ++k) {
      if (q[k] < min[k]) min[k] = q[k];
      if (q[k] > max[k]) max[k] = q[k];
    }
  }
  return { min, max };
}

const CORNERS = { 1: [0, 1], 2: [1, 2], 4: [0, 2], 7: [0, 1, 2] };

function defectItem(mesh, kind, i) {
  const n = defectCount(mesh, kind);
  if (!Number.isInteger(i) || i < 0 || i >= n) throw stlError('invalid-argument', `no ${kind} item ${i} (there are ${n})`);
  const d = mesh.defects;
  const x = mesh.intersections;
  switch (kind) {
    case 'zeroAreaTriangles': return { triangle: x.zeroAreaTriangles[i] };
    case 'duplicateTriangles':
      return { triangles: Array.from(x.duplicateTriangles.subarray(x.duplicateOffsets[i], x.duplicateOffsets[i + 1])),
        orientation: DUPLICATE_ORIENTATIONS[x.duplicateOrientation[i]] };
    case 'selfIntersections':
      return { triangles: [x.pairs[2 * i], x.pairs[2 * i + 1]], kind: INTERSECTION_KINDS[x.kinds[i]],
        point: [x.points[3 * i], x.points[3 * i + 1], x.points[3 * i + 2]] };
    case 'holes':
    case 'seams': {
      const loop = mesh[kind][i];
      const vertices = Array.from(loop.vertices);
      const item = { id: loop.id, edges: loop.edgeCount, perimeter: loop.perimeter, vertices, bbox: box(mesh, vertices),
        shell: d.loopShell[loop.id] };
      if (kind === 'seams') {
        const pairKind = mesh.problems.pairKind;
        item.cutEdges = [];
        for (let k = 0; k < loop.halfedges.length; ++k) {
          const e = loop.halfedges[k];
          if (pairKind[e >>> 1] !== EdgeKind.Boundary) {
            item.cutEdges.push([vertices[k], vertices[(k + 1) % vertices.length]]);
          }
        }
      }
      return item;
    }
    case 'nonManifoldEdges': {
      const a = d.nonManifoldEdgeVertices[2 * i], b = d.nonManifoldEdgeVertices[2 * i + 1];
      const tris = d.nonManifoldEdgeTriangles.subarray(d.nonManifoldEdgeOffsets[i], d.nonManifoldEdgeOffsets[i + 1]);
      return { vertices: [a, b], positions: [position(mesh, a), position(mesh, b)], triangles: Array.from(tris) };
    }
    case 'inconsistentEdges':
      return { vertices: [d.inconsistentEdgeVertices[2 * i], d.inconsistentEdgeVertices[2 * i + 1]],
        triangles: [d.inconsistentEdgeTriangles[2 * i], d.inconsistentEdgeTriangles[2 * i + 1]] };
    case 'nonManifoldVertices': {
      const v = d.nonManifoldVertices[i];
      return { vertex: v, position: position(mesh, v), cycles: d.nonManifoldVertexCycles[i] };
    }
    default:
      return { triangle: d.degenerateTriangles[i], corners: CORNERS[d.degenerateCorners[i]].slice() };
  }
}

/** The plain data a writer needs from a mesh: cloneable, for a worker thread. */
export function writeInput(mesh) {
  const layout = layouts.get(mesh);
  if (!layout) throw stlError('invalid-argument', 'writeStl() needs a Mesh of loadStl() or fromIndexed()');
  const input = { colorConvention: mesh.colorConvention, solids: mesh.solids.map((s) => ({ ...s })) };
  for (const d of layout) if (isMeshArray(d) && !d.group) input[d.key] = meshArray(mesh, d);
  return input;
}
