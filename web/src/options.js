// Load options: the defaults (shared with the npm CLI, bin/stltopo.mjs) and their checks.
import { invalid } from './errors.js';

/** The defaults of loadStl() and of `stltopo info`. */
export const DEFAULTS = Object.freeze({
  topology: true,
  tolerance: 0, // weld: 'exact'
  maxTriangles: 2 ** 28,
  maxBytes: 0, // unlimited
  normals: false,
  view: false,
  shells: false, // triangleShell, mesh.shells and mesh.defects (4 bytes more per triangle)
  intersections: false, // mesh.intersections, the intersection keys of mesh.stats (implies shells)
  maxPairs: 4000000, // the intersection pass's work limit (--max-pairs)
});

/**
 * The checked, complete options of a load. Throws invalid-argument on a bad value.
 * maxTriangles is in [1, 2^32), as for both CLIs' --max-triangles.
 */
export function normalizeOptions(options) {
  if (options == null) options = {};
  if (typeof options !== 'object') throw invalid('options must be an object');
  const o = {
    topology: options.topology === undefined ? DEFAULTS.topology : !!options.topology,
    tolerance: DEFAULTS.tolerance,
    maxTriangles: DEFAULTS.maxTriangles,
    maxBytes: DEFAULTS.maxBytes,
    normals: !!options.normals,
    signal: options.signal || null,
    onProgress: options.onProgress || null,
    view: !!options.view,
    shells: !!options.shells || !!options.intersections,
    intersections: !!options.intersections,
    maxPairs: DEFAULTS.maxPairs,
    threads: null, // the environment's default (web/src/threads.js)
  };
  if (options.threads !== undefined && options.threads !== null) {
    const n = options.threads;
    if (!Number.isInteger(n) || n < 0 || n > 1024) throw invalid('threads must be an integer in [0, 1024] (0: the machine\'s cores)');
    o.threads = n;
  }
  if (options.maxPairs !== undefined) {
    const n = options.maxPairs;
    if (!Number.isInteger(n) || n < 1 || n > 2 ** 40) throw invalid('maxPairs must be an integer in [1, 2^40]');
    o.maxPairs = n;
  }
  const weld = options.weld;
  if (weld !== undefined && weld !== 'exact') {
    if (!weld || typeof weld !== 'object' || typeof weld.tolerance !== 'number' || !(weld.tolerance >= 0) ||
        !Number.isFinite(weld.tolerance)) {
      throw invalid("weld must be 'exact' or { tolerance: number >= 0 }");
    }
    o.tolerance = weld.tolerance;
  }
  if (options.maxTriangles !== undefined) {
    const n = options.maxTriangles;
    if (!Number.isInteger(n) || n < 1 || n > 0xffffffff) throw invalid('maxTriangles must be an integer in [1, 2^32)');
    o.maxTriangles = n;
  }
  if (options.maxBytes !== undefined) {
    const n = options.maxBytes;
    if (!Number.isInteger(n) || n < 0) throw invalid('maxBytes must be a non-negative integer (0 = unlimited)');
    o.maxBytes = n;
  }
  if (o.onProgress !== null && typeof o.onProgress !== 'function') throw invalid('onProgress must be a function');
  if (o.signal !== null && typeof o.signal.aborted !== 'boolean') throw invalid('signal must be an AbortSignal');
  return o;
}

/** The plain, cloneable form of normalized options (what a worker thread gets). */
export function plainOptions(o) {
  return {
    topology: o.topology,
    weld: o.tolerance > 0 ? { tolerance: o.tolerance } : 'exact',
    maxTriangles: o.maxTriangles,
    maxBytes: o.maxBytes,
    normals: o.normals,
    shells: o.shells,
    intersections: o.intersections,
    maxPairs: o.maxPairs,
    threads: o.threads,
  };
}

/** The defaults of writeStl() / toStl() and of `stltopo convert`. */
export const WRITE_DEFAULTS = Object.freeze({
  format: 'binary',
  colors: 'as-mesh',
  name: null, // each solid's own name
  normals: 'stored', // the stored normals when the mesh kept them, else from the winding
  chunkBytes: 1 << 20,
});

/** The checked, complete options of a write. Throws invalid-argument on a bad value. */
export function normalizeWriteOptions(options) {
  if (options == null) options = {};
  if (typeof options !== 'object') throw invalid('options must be an object');
  const o = { ...WRITE_DEFAULTS, worker: !!options.worker };
  const pick = (key, allowed) => {
    const v = options[key];
    if (v === undefined) return;
    if (!allowed.includes(v)) throw invalid(`${key} must be ${allowed.map((a) => `'${a}'`).join(', ')}`);
    o[key] = v;
  };
  pick('format', ['binary', 'ascii']);
  pick('colors', ['as-mesh', 'none', 'viscam', 'magics']);
  pick('normals', ['stored', 'computed']);
  if (options.name !== undefined && options.name !== null) {
    if (typeof options.name !== 'string') throw invalid('name must be a string');
    o.name = options.name;
  }
  if (options.chunkBytes !== undefined) {
    const n = options.chunkBytes;
    if (!Number.isInteger(n) || n < 1) throw invalid('chunkBytes must be a positive integer');
    o.chunkBytes = n;
  }
  return o;
}

/** The options of fromIndexed(): those of a load (weld also 'none'), plus the optional arrays. */
export function normalizeIndexedOptions(options) {
  if (options == null) options = {};
  if (typeof options !== 'object') throw invalid('options must be an object');
  const none = options.weld === 'none';
  const o = normalizeOptions(none ? { ...options, weld: 'exact' } : options);
  o.weldNone = none;
  const typed = (key, Type) => {
    const v = options[key];
    if (v === undefined || v === null) return null;
    if (v instanceof Type) return v;
    if (ArrayBuffer.isView(v) || Array.isArray(v)) return Type.from(v);
    throw invalid(`${key} must be a ${Type.name} or an array of numbers`);
  };
  o.attributes = typed('attributes', Uint16Array);
  o.colors = typed('colors', Uint8Array);
  o.colorValid = typed('colorValid', Uint8Array);
  const solids = options.solids ?? [];
  if (!Array.isArray(solids)) throw invalid('solids must be an array of { name, firstTriangle, triangleCount }');
  o.solids = solids.map((s, i) => {
    if (!s || !Number.isInteger(s.firstTriangle) || !Number.isInteger(s.triangleCount) || s.firstTriangle < 0 || s.triangleCount < 0) {
      throw invalid(`solids[${i}] needs integer firstTriangle and triangleCount >= 0`);
    }
    return { name: s.name === undefined ? '' : String(s.name), firstTriangle: s.firstTriangle, triangleCount: s.triangleCount };
  });
  return o;
}

/** The repair steps, in the order they run (include/stltopo/repair.h). */
export const REPAIR_STEPS = Object.freeze(['duplicates', 'zero-area', 'stitch', 'orient', 'split-nonmanifold', 'fill-holes',
  'small-shells']);
/** The defaults of planRepair() and of `stltopo repair` (RepairOptions). */
export const REPAIR_DEFAULTS = Object.freeze({
  steps: Object.freeze(['duplicates', 'zero-area', 'stitch', 'orient', 'fill-holes']),
  removeWalls: false,
  stitchTolerance: 0,
  maxHoleEdges: 1000,
  maxHoleArea: 0, // no limit
  maxHolePerimeter: 0, // no limit
  fill: Object.freeze([]), // 'refine', 'fair'
  minShellTriangles: 10,
  minShellVolume: 0,
  intersections: true,
  maxPairs: 4000000,
});

/**
 * The checked, complete options of planRepair(), in the form the bindings read
 * (EditSession::repairOptions). Throws invalid-argument on a bad value.
 */
export function normalizeRepairOptions(options) {
  if (options == null) options = {};
  if (typeof options !== 'object') throw invalid('repair options must be an object');
  const d = REPAIR_DEFAULTS;
  const pick = (k) => (options[k] === undefined ? d[k] : options[k]);
  const num = (k, integer, max) => {
    const v = pick(k);
    if (typeof v !== 'number' || !(v >= 0) || v > max || (integer && !Number.isInteger(v))) {
      throw invalid(`${k} must be ${integer ? 'an integer' : 'a number'} in [0, ${max}]`);
    }
    return v;
  };
  const steps = pick('steps');
  if (!Array.isArray(steps)) throw invalid(`steps must be an array of step names (${REPAIR_STEPS.join(', ')})`);
  for (const s of steps) if (!REPAIR_STEPS.includes(s)) throw invalid(`unknown repair step ${String(s)} (${REPAIR_STEPS.join(', ')})`);
  const fill = pick('fill');
  if (!Array.isArray(fill) || fill.some((f) => f !== 'refine' && f !== 'fair')) throw invalid("fill must be an array of 'refine', 'fair'");
  const exclude = options.exclude === undefined ? [] : options.exclude;
  if (!Array.isArray(exclude)) throw invalid('exclude must be an array of { step, item }');
  const maxPairs = pick('maxPairs');
  if (!Number.isInteger(maxPairs) || maxPairs < 1 || maxPairs > 2 ** 40) throw invalid('maxPairs must be an integer in [1, 2^40]');
  return {
    steps: REPAIR_STEPS.filter((s) => steps.includes(s)),
    removeOppositeDuplicates: !!pick('removeWalls'),
    stitchTolerance: num('stitchTolerance', false, Number.MAX_VALUE),
    maxHoleEdges: num('maxHoleEdges', true, 0xffffffff),
    maxHoleArea: num('maxHoleArea', false, Number.MAX_VALUE),
    maxHolePerimeter: num('maxHolePerimeter', false, Number.MAX_VALUE),
    fillRefine: fill.includes('refine'),
    fillFair: fill.includes('fair'),
    minShellTriangles: num('minShellTriangles', true, 0xffffffff),
    minShellVolume: num('minShellVolume', false, Number.MAX_VALUE),
    intersections: !!pick('intersections'),
    maxPairs,
    exclude: exclude.map((x) => {
      if (!x || !REPAIR_STEPS.includes(x.step) || !Number.isInteger(x.item) || x.item < 0 || x.item > 0xffffffff) {
        throw invalid('exclude items must be { step: a step name, item: an item index }');
      }
      return { step: x.step, item: x.item };
    }),
  };
}
