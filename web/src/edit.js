// EditableMesh: local edits on a mesh held in wasm memory (see docs/EDITING.md for the
// contracts). The arrays and figures read from it are copies, made when first read after an
// edit; the mesh itself lives in wasm until dispose(). Its array properties follow the
// bindings' table (entry.editLayout: STLTOPO_JS_EDIT_ARRAYS in bindings/edit_arrays.h), one
// getter per row, as a Mesh's follow STLTOPO_JS_ARRAYS.
import { stlError, invalid, fromStatus } from './errors.js';
import { Mesh, kInvalid, buildLoops, trackSession, untrackSession } from './mesh.js';
import { normalizeWriteOptions, normalizeRepairOptions } from './options.js';

const ELEMENTS = { vertex: 0, triangle: 1, edge: 2 };
const RULES = { keepFirst: 0, average: 1, fail: 2 };
const TYPES = [Uint8Array, Int8Array, Uint16Array, Int16Array, Uint32Array, Int32Array, Float32Array, Float64Array];

function check(r) {
  if (r !== null && typeof r === 'object' && typeof r.code === 'string' && typeof r.message === 'string') throw fromStatus(r);
  return r;
}
// A JS rule runs inside a wasm call: an exception must not unwind through it, so the wrapper
// catches it, refuses the edit (null) and keeps it for #edit to throw.
let ruleError = null;
function rule(r, what) {
  if (typeof r === 'function') {
    return [3, (a, b, t) => {
      try {
        return r(a, b, t);
      } catch (e) {
        ruleError = e;
        return null;
      }
    }];
  }
  if (r === undefined) return [0, null];
  if (!(r in RULES)) throw invalid(`unknown ${what} rule ${String(r)} (keepFirst, average, fail or a function)`);
  return [RULES[r], null];
}
function id(x, what) {
  if (!Number.isInteger(x) || x < 0 || x > 0xfffffffe) throw invalid(`${what} must be an id, not ${String(x)}`);
  return x;
}
function idList(x, what) {
  const list = typeof x === 'number' ? [x] : Array.isArray(x) || ArrayBuffer.isView(x) ? Array.from(x) : null;
  if (!list) throw invalid(`${what} must be an id or a list of ids`);
  return list.map((v) => id(v, what));
}

// The id lists of a plan's items and a log's steps, as Uint32Arrays (compact, and
// transferable from a worker).
const ITEM_LISTS = ['triangles', 'vertices', 'loops'];
const LOG_LISTS = ['removedTriangles', 'changedTriangles', 'removedVertices', 'changedVertices'];
/** The plan's or log's JSON text, as the CLI prints it (bin/stltopo.mjs). */
export const RAW_JSON = Symbol('stltopo.rawJson');
function repairPlanFrom(json, options) {
  const p = JSON.parse(json);
  Object.defineProperty(p, RAW_JSON, { value: json });
  for (const s of p.steps) for (const it of s.items) for (const k of ITEM_LISTS) it[k] = Uint32Array.from(it[k]);
  p.options = options;
  return p;
}
function repairLogFrom(json) {
  const l = JSON.parse(json);
  Object.defineProperty(l, RAW_JSON, { value: json });
  for (const s of l.steps) for (const k of LOG_LISTS) s[k] = Uint32Array.from(s[k]);
  return l;
}

/**
 * planRepair(mesh, options) of an entry: a Mesh is planned from its arrays, as the
 * EditableMesh made from it would plan (EditableMesh.planRepairOf).
 */
export function createPlanRepair(EditableMesh) {
  return async function planRepair(mesh, options = {}) {
    if (mesh instanceof EditableMesh) return mesh.planRepair(options);
    return EditableMesh.planRepairOf(mesh, options);
  };
}

/**
 * The session `s` of module entry `entry`, its methods guarded: what escapes a call into wasm
 * becomes failure(entry, e) (wasm.js wasmFailure). An instance that aborted (its heap
 * exhausted: a repair plan of millions of items) is dropped by it, so the next EditableMesh
 * gets a fresh one, and the editable meshes it held say so on their next call.
 */
function guard(entry, s, failure) {
  return new Proxy(s, {
    get(target, key) {
      const v = target[key];
      if (typeof v !== 'function') return v;
      return (...args) => {
        if (entry.dead && key !== 'delete' && key !== 'isDeleted') {
          throw stlError('invalid-argument', 'the editable mesh is lost: its WebAssembly instance aborted');
        }
        try {
          return v.apply(target, args);
        } catch (e) {
          throw failure(entry, e);
        }
      };
    },
  });
}

/**
 * A new session of module entry `entry` with the arrays of `source` (a Mesh, or { positions, triangles,
 * ... }) staged, before its init() or planRepairStaged(). Deleted again when staging fails.
 */
function stage(entry, source, failure) {
  let s;
  try {
    s = guard(entry, new entry.module._EditableMesh(), failure);
  } catch (e) {
    throw failure(entry, e);
  }
  try {
    const up = (name, arr) => {
      if (!arr) return;
      const v = s.upload(name, arr.length);
      if (v === null) throw stlError('out-of-memory', `could not allocate ${name}`);
      v.set(arr);
    };
    up('positions', source.positions);
    up('triangles', source.triangles);
    up('attributes', source.attributes);
    const colors = source.colorConvention && source.colorConvention !== 'none';
    if (colors && source.colors && source.colorValid) {
      up('colors', source.colors);
      up('colorValid', source.colorValid);
    }
    up('normals', source.normals);
    s.setFormat(source.format || 'unknown', colors ? source.colorConvention : 'none');
    for (const so of source.solids || []) s.addSolid(so.name || '', so.firstTriangle, so.triangleCount);
  } catch (e) {
    s.delete();
    throw e;
  }
  return s;
}

/**
 * Creates the EditableMesh class on a module getter (async () => entry with .module), as
 * index.js and node.js make it for their module.
 */
export function createEditableMesh(getModule, failure = (entry, e) => e) {
  class EditableMesh {
    #m;
    #session;
    #cache = new Map();
    #disposed = false;

    constructor(entry, session, source) {
      this.#m = entry;
      this.#session = session;
      /** As the source mesh's (solids and warnings describe the file it came from). */
      this.format = source.format || 'unknown';
      this.colorConvention = source.colors && source.colorValid ? source.colorConvention || 'none' : 'none';
      this.warnings = source.warnings ? [...source.warnings] : [];
      // One getter per row of the array table; a group is an object of getters.
      for (const d of entry.editLayout) {
        let obj = this;
        if (d.group) {
          if (!Object.hasOwn(this, d.group)) Object.defineProperty(this, d.group, { value: {}, enumerable: true });
          obj = this[d.group];
        }
        Object.defineProperty(obj, d.key, { enumerable: true, get: () => this.#get(d.name) });
      }
      trackSession(this, entry, session);
    }

    /**
     * An editable copy of a Mesh (from loadStl) or of an indexed mesh
     * { positions: Float32Array, triangles: Uint32Array, attributes?, colors?, colorValid?,
     *   solids? }. options.tolerance welds for the topology as loadStl does. Resolves when
     * the arrays are checked (a bad id rejects here). With a tolerance the topology is built
     * before it resolves; without one, at the first call that reads or edits the mesh (whose
     * error, such as out of memory, then comes from that call). planRepair() and
     * applyRepair() as the first calls never build the editor of the input: applyRepair
     * takes the repaired mesh the plan made.
     */
    static async from(source, options = {}) {
      if (!source || !source.positions || !source.triangles) throw invalid('EditableMesh.from() needs a Mesh or { positions, triangles }');
      const entry = await getModule();
      const s = stage(entry, source, failure);
      try {
        // Without a tolerance the editor is built at the first call that needs it (#live):
        // from() + planRepair() + applyRepair() then never builds the editor of the input
        // (applyRepair takes the plan's result). The arrays are checked here either way.
        check(options.tolerance ? s.init(options.tolerance) : s.defer());
      } catch (e) {
        s.delete();
        throw e;
      }
      return new EditableMesh(entry, s, source);
    }

    /**
     * planRepair() of a Mesh: the plan of EditableMesh.from(source).planRepair(options),
     * made from the source's arrays without building that EditableMesh first.
     */
    static async planRepairOf(source, options = {}) {
      if (!source || !source.positions || !source.triangles) throw invalid('planRepair() needs a Mesh or an EditableMesh');
      const o = normalizeRepairOptions(options);
      const entry = await getModule();
      const s = stage(entry, source, failure);
      try {
        return repairPlanFrom(check(s.planRepairStaged(o, false)), o);
      } finally {
        s.delete();
      }
    }

    #deferred() {
      if (this.#disposed) throw invalid('the editable mesh was disposed');
      return this.#session.deferred();
    }
    #live() {
      // A deferred from(): the editor now (an error, such as out of memory, leaves it deferred).
      if (this.#deferred()) check(this.#session.init(0));
      return this.#session;
    }
    #edit(r) {
      this.#cache.clear();
      if (ruleError !== null) {
        const e = ruleError;
        ruleError = null;
        throw e;
      }
      return check(r);
    }
    #get(name) {
      let a = this.#cache.get(name);
      if (a === undefined) {
        a = name === 'counts' ? this.#live().counts()
          : name === 'stats' ? (() => { const st = JSON.parse(this.#live().infoJson('')); delete st.file; return st; })()
          : this.#live().array(name, true);
        this.#cache.set(name, a);
      }
      return a;
    }

    /** Slot counts: array lengths, dead slots included. */
    get nVertices() { return this.#get('counts').nVertices; }
    get nTriangles() { return this.#get('counts').nTriangles; }
    get nHalfedges() { return this.#get('counts').nHalfedges; }
    get nLiveTriangles() { return this.#get('counts').nLiveTriangles; }
    get nLiveVertices() { return this.#get('counts').nLiveVertices; }
    /** The triangle attributes the file brought, as a Mesh has them (null when absent). */
    get attributes() { return this.#attr('attribute'); }
    get colors() { return this.colorConvention === 'none' ? null : this.#attr('color'); }
    get colorValid() { return this.colorConvention === 'none' ? null : this.#attr('colorValid'); }
    get normals() { return this.#attr('normal'); }
    #attr(name) {
      const key = `attr:${name}`;
      if (!this.#cache.has(key)) this.#cache.set(key, this.#live().attribute(name, true));
      return this.#cache.get(key);
    }
    /** The figures of `info --json` for the compacted mesh (computed when read after an edit). */
    get stats() { return this.#get('stats'); }
    #loops() {
      let l = this.#cache.get('loopList');
      if (!l) {
        const arrays = {};
        for (const n of ['loopOffsets', 'loopHalfedges', 'loopIsSeam', 'loopPerimeter', 'vert']) arrays[n] = this.#get(n);
        l = buildLoops(arrays, this.nTriangles);
        this.#cache.set('loopList', l);
      }
      return l;
    }
    /** Boundary loops without cut sides, numbered as a fresh load of the compacted mesh numbers them. */
    get holes() { return this.#loops().holes; }
    get seams() { return this.#loops().seams; }

    triangleAlive(t) { return t < this.nTriangles && this.triangles[3 * t] !== kInvalid; }
    halfedgeAlive(e) { return e < this.nHalfedges && this.halfedges.vert[e] !== kInvalid; }

    /** { ok: true } or { ok: false, code, message, element }. */
    validate() {
      const r = this.#live().validate();
      return r === null ? { ok: true } : { ok: false, ...r };
    }

    /** Room for more vertices and triangles, so that no later edit reallocates the arrays. */
    reserve(vertices, triangles) { check(this.#live().reserve(id(vertices, 'vertices'), id(triangles, 'triangles'))); }
    /** Moves vertex v (geometry only: triangles, topology, ids and attributes stay). */
    setPosition(v, x, y, z) { this.#edit(this.#live().setPosition(id(v, 'vertex'), x, y, z)); }
    removeTriangle(t) { this.#edit(this.#live().removeTriangle(id(t, 'triangle'))); }
    addVertex(x, y, z) { return this.#edit(this.#live().addVertex(x, y, z)); }
    /** Returns the new triangle id. options.nonManifold allows non-manifold and inconsistent edges. */
    addTriangle(a, b, c, options = {}) {
      return this.#edit(this.#live().addTriangle(id(a, 'a'), id(b, 'b'), id(c, 'c'), !!options.nonManifold));
    }
    flipEdge(e) { this.#edit(this.#live().flipEdge(id(e, 'half-edge'))); }
    /** Returns the new vertex. */
    splitEdge(e, t = 0.5) { return this.#edit(this.#live().splitEdge(id(e, 'half-edge'), t)); }
    /** Returns the vertex that remains (the origin of e). */
    collapseEdge(e, t = 0.5) { return this.#edit(this.#live().collapseEdge(id(e, 'half-edge'), t)); }
    /**
     * Merges vertex gone[i] into keep[i] for every i, in one edit (keep stays where it is).
     * Numbers or arrays of ids. options.nonManifold allows more non-manifold vertices.
     */
    mergeVertices(keep, gone, options = {}) {
      const k = idList(keep, 'keep'), g = idList(gone, 'gone');
      if (k.length !== g.length) throw invalid('mergeVertices() needs as many gone vertices as keep vertices');
      this.#edit(this.#live().mergeVertices(k, g, !!options.nonManifold));
    }
    /** Closes a T-junction: splits boundary half-edge e's edge at the existing vertex v. */
    splitEdgeAt(e, v, options = {}) {
      this.#edit(this.#live().splitEdgeAt(id(e, 'half-edge'), id(v, 'vertex'), !!options.nonManifold));
    }
    /** splitEdgeAt for each (edges[i], vertices[i]), then mergeVertices(keep, gone), as one edit. */
    stitch({ keep = [], gone = [], edges = [], vertices = [] } = {}, options = {}) {
      const k = idList(keep, 'keep'), g = idList(gone, 'gone'), e = idList(edges, 'edges'), v = idList(vertices, 'vertices');
      if (k.length !== g.length || e.length !== v.length) throw invalid('stitch() needs keep/gone and edges/vertices of equal lengths');
      this.#edit(this.#live().stitch(k, g, e, v, !!options.nonManifold));
    }
    /** Splits vertex v into one vertex per fan: { first, count } of the new vertices. */
    splitVertex(v) { return this.#edit(this.#live().splitVertex(id(v, 'vertex'))); }
    reverseTriangle(t) { this.#edit(this.#live().reverseTriangle(id(t, 'triangle'))); }
    /** Reverses the shell of triangle t. */
    reverseShell(t) { this.#edit(this.#live().reverseShell(id(t, 'triangle'))); }
    /**
     * Fills a loop: h is a loop id (holes[i].id) or a hole object; returns the new triangle
     * ids (Uint32Array). options.method: 'fan' (default) or 'ear'.
     */
    fillHole(h, options = {}) {
      const method = options.method || 'fan';
      if (method !== 'fan' && method !== 'ear') throw invalid(`unknown fill method ${String(method)} (fan or ear)`);
      const byLoop = typeof h === 'number';
      const target = byLoop ? id(h, 'loop') : h && h.halfedges ? h.halfedges[0] : undefined;
      if (target === undefined) throw invalid('fillHole() needs a loop id or a hole');
      return this.#edit(this.#live().fill(target, byLoop, method === 'ear'));
    }
    /**
     * The STL file of the mesh (as compact() would renumber it), as bytes: options as
     * writeStl's ({ format, colors, normals, name }). Colours and attribute words are the
     * triangles' attributes.
     */
    toStl(options = {}) {
      const o = normalizeWriteOptions(options);
      return check(this.#live().toStl(o.format, o.colors, o.normals, o.name === undefined || o.name === null ? null : o.name));
    }
    /** Renumbers densely; returns the old -> new maps { vertices, triangles, halfedges }. */
    compact() { return this.#edit(this.#live().compact()); }

    /**
     * Adds attribute `name` per 'vertex', 'triangle' or 'edge' (per half-edge pair). values:
     * a typed array of (slot count) x components, which sets the type. merge/split:
     * 'keepFirst' (default), 'average', 'fail' or a function (a, b, t) => array | null.
     */
    addAttribute(name, element, values, { components = 1, merge, split } = {}) {
      if (!(element in ELEMENTS)) throw invalid(`unknown element ${String(element)} (vertex, triangle or edge)`);
      const type = TYPES.findIndex((T) => values instanceof T);
      if (type < 0) throw invalid('attribute values must be a typed array');
      const [mr, mf] = rule(merge, 'merge');
      const [sr, sf] = rule(split, 'split');
      const s = this.#live();
      const count = element === 'vertex' ? this.nVertices : element === 'triangle' ? this.nTriangles : this.nHalfedges / 2;
      if (values.length !== count * components) throw invalid(`${name} needs ${count * components} values (${count} x ${components}), not ${values.length}`);
      this.#edit(s.addAttribute(String(name), ELEMENTS[element], type, components, mr, sr, mf, sf));
      s.attribute(String(name), false).set(values);
    }
    /** A copy of the attribute's values (slot order), or null. */
    attribute(name) { return this.#live().attribute(String(name), true); }
    attributeNames() { return this.#live().attributeNames(); }

    /**
     * Plans a repair of this mesh (docs/REPAIR.md): changes nothing. options: { steps,
     * removeWalls, stitchTolerance, maxHoleEdges, maxHoleArea, maxHolePerimeter, fill,
     * minShellTriangles, minShellVolume, intersections, maxPairs, exclude }.
     */
    planRepair(options = {}) {
      const o = normalizeRepairOptions(options);
      // A deferred editor plans on its staged arrays (the same plan, and applyRepair below
      // then takes the plan's result without building the editor of the input).
      const r = this.#deferred() ? this.#session.planRepairStaged(o, true) : this.#live().planRepair(o);
      return repairPlanFrom(check(r), o);
    }
    /**
     * Carries out a plan made for this mesh (by planRepair() on it, or on the Mesh it was
     * made from) and returns the change log. The log's steps can be undone with undo().
     */
    applyRepair(plan) {
      if (!plan || typeof plan !== 'object' || !plan.options || typeof plan.fingerprint !== 'string') {
        throw invalid('applyRepair() needs a plan from planRepair()');
      }
      const r = this.#deferred()
        ? this.#session.applyRepairStaged(plan.options, plan.fingerprint)
        : this.#live().applyRepair(plan.options, plan.fingerprint);
      return repairLogFrom(this.#edit(r));
    }
    /** Undoes the last repair step still applied: its name, or null when there is none. */
    undo() { return this.#deferred() ? null : this.#edit(this.#live().undoRepairStep()); }
    /** How many repair steps undo() can still take back. */
    get undoableSteps() { return this.#deferred() ? 0 : this.#live().undoableRepairSteps(); }

    /** Frees the wasm memory; the object is unusable afterwards. */
    dispose() {
      if (this.#disposed) return;
      this.#disposed = true;
      this.#cache.clear();
      untrackSession(this);
      if (!this.#m.dead) this.#session.delete();
    }
  }
  // The navigation of a Mesh, on the same half-edge arrays.
  for (const k of ['sym', 'twin', 'org', 'dst', 'lFace', 'rFace', 'lNext', 'lPrev', 'vnext', 'oPrev', 'oNext', 'rPrev',
    'rNext', 'dNext', 'dPrev', 'faceHalfedges', 'outgoingHalfedges']) {
    const d = Object.getOwnPropertyDescriptor(Mesh.prototype, k);
    if (d) Object.defineProperty(EditableMesh.prototype, k, d);
  }
  return EditableMesh;
}
