// The wasm lifecycle: one instance per thread (re-created after a wasm abort), the read
// loop that feeds a session, and the raw results that become meshes (mesh.js).
import { StlError, stlError, abortError, checkAbort, fromStatus, MESSAGE_BYTES, FROM_CORE } from './errors.js';
import { DEFAULTS, normalizeOptions, normalizeWriteOptions, normalizeIndexedOptions } from './options.js';
import { toSource } from './sources.js';
import { lazyModule } from './wasm-load.js';
import { Mesh, isPresent, isMeshArray, toValidation, meshArray, liveSession, workerHome, writeInput,
  setIntersectionFinder } from './mesh.js';

const CHUNK = 1 << 20; // bytes handed to the core per feed() call
const YIELD_MS = 16; // longest stretch of feeding without giving the event loop a turn
const PROGRESS_MS = 50; // onProgress at most this often (plus once at the end)

const now = () => (typeof performance !== 'undefined' ? performance.now() : Date.now());

// A macrotask turn, so that abort events, timers and rendering can run.
const yieldToEventLoop = (() => {
  if (typeof setImmediate === 'function') return () => new Promise((r) => setImmediate(r));
  if (typeof MessageChannel === 'function') {
    const ch = new MessageChannel();
    const queue = [];
    ch.port1.onmessage = () => queue.shift()();
    return () => new Promise((r) => { queue.push(r); ch.port2.postMessage(0); });
  }
  return () => new Promise((r) => setTimeout(r, 0));
})();

// Two modules (bindings/CMakeLists.txt): getModule() resolves to the core (stltopo-wasm:
// loads, the report, validate()), getFull() to the full module (stltopo-full: also shells
// and defects, fromIndexed(), writing, EditableMesh). Each is instantiated on first use, so
// a page that only loads files never fetches the full one.
export function createStltopo({ instantiate, instantiateFull, loadWorker = null }) {
  const setup = (entry, m) => {
    entry.heapMax = m._heapMax();
    entry.layout = Object.freeze(m._arrayLayout().map((d) => Object.freeze(d)));
    // The EditableMesh's table (STLTOPO_JS_EDIT_ARRAYS), in the full module only.
    if (m._editArrayLayout) entry.editLayout = Object.freeze(m._editArrayLayout().map((d) => Object.freeze(d)));
  };
  const getModule = lazyModule(instantiate, setup);
  const getFull = lazyModule(instantiateFull, setup);
  // The module a read with these options needs: shells and defects are in the full one.
  const moduleFor = (o) => (o.topology && (o.shells || o.intersections) ? getFull() : getModule());

  // The exact geometry (self-intersections, nesting, solid) of a session loaded with shells,
  // when the options ask for it.
  function intersectIfAsked(session, o) {
    if (!o.topology || !o.intersections) return;
    const st = session.intersect(o.maxPairs);
    if (st) throw fromStatus(st);
  }

  // Turns whatever escaped a call into wasm into an error, and drops a wasm
  // instance that aborted (e.g. operator new failed) so the next call gets a
  // fresh one: the module keeps working after any error.
  function wasmFailure(entry, e) {
    if (e instanceof StlError) return e;
    const isRangeError = e instanceof RangeError && /allocat|memory|length/i.test(String(e.message));
    const wasmDied = entry.dead || (typeof WebAssembly !== 'undefined' && e instanceof WebAssembly.RuntimeError);
    if (wasmDied) {
      entry.dead = true;
      getModule.drop(entry);
      getFull.drop(entry);
      const heap = entry.module && entry.module.HEAPU8 ? entry.module.HEAPU8.length : 0;
      if (heap + (64 << 20) >= entry.heapMax || /memory|OOM|alloc/i.test(entry.lastError)) {
        return stlError('out-of-memory', `the WebAssembly heap is exhausted (${e.message})`);
      }
      return e;
    }
    if (isRangeError) return stlError('out-of-memory', e.message);
    return e;
  }

  // Reads a source into a new session; returns it (finished) or throws.
  async function readSession(entry, source, o) {
    const M = entry.module;
    const session = new M._Session(o.maxTriangles, o.maxBytes, source.total || 0, o.normals);
    const signal = o.signal;
    const onAbort = () => source.cancel(abortError());
    if (signal) signal.addEventListener('abort', onAbort, { once: true });
    try {
      let bytesRead = 0;
      let lastYield = now();
      let lastProgress = lastYield;
      const total = source.total || 0;
      const progress = (final) => {
        if (!o.onProgress) return;
        const t = now();
        if (!final && t - lastProgress < PROGRESS_MS) return;
        lastProgress = t;
        o.onProgress(final ? 1 : total ? Math.min(1, bytesRead / total) : NaN, bytesRead);
      };
      for (;;) {
        checkAbort(signal);
        const chunk = await source.next();
        checkAbort(signal);
        if (chunk === null) break;
        for (let off = 0; off < chunk.length; off += CHUNK) {
          const part = off === 0 && chunk.length <= CHUNK ? chunk : chunk.subarray(off, Math.min(off + CHUNK, chunk.length));
          const buf = session.buffer(part.length);
          if (buf === null) throw stlError('out-of-memory', 'could not allocate the input buffer');
          buf.set(part);
          const st = session.feed(part.length);
          if (st) throw fromStatus(st);
          bytesRead += part.length;
          progress(false);
          if (now() - lastYield > YIELD_MS) {
            await yieldToEventLoop();
            checkAbort(signal);
            lastYield = now();
          }
        }
      }
      // prev and face only where they are read from wasm: views and validate().
      const st = session.finish(o.topology, o.tolerance, o.view || !!o.validate, o.topology && !!o.shells);
      if (st) throw fromStatus(st);
      intersectIfAsked(session, o);
      progress(true);
      return session;
    } catch (e) {
      source.cancel(e);
      if (!entry.dead) {
        if (e instanceof StlError && e[FROM_CORE] && o.keepMessageBytes) e[MESSAGE_BYTES] = session.messageBytes();
        session.delete();
      }
      throw e;
    } finally {
      if (signal) signal.removeEventListener('abort', onAbort);
    }
  }

  // Plain data of a finished session (the worker's result message): every array of the
  // table that exists, as copies (copy) or views. Copies leave out the derived arrays,
  // which the core did not build for them, unless it did (withDerived: worker loads, which
  // validate() in wasm and hand the arrays over).
  function extractRaw(entry, session, copy, { validate = false } = {}) {
    const meta = session.meta();
    const raw = {
      format: meta.format,
      colorConvention: meta.colorConvention,
      nVertices: meta.nVertices,
      nTriangles: meta.nTriangles,
      hasTopology: meta.hasTopology,
      hasNormals: meta.hasNormals,
      hasShells: meta.hasShells,
      hasIntersections: !!meta.hasIntersections,
      shellsJson: meta.hasShells ? session.shellListJson() : 'null',
      indexed: meta.indexed,
      solids: meta.solids,
      warnings: meta.warnings,
      counts: meta.counts,
      statsJson: session.infoJson('', false, false, 0),
      validation: validate && meta.hasTopology ? toValidation(session.validate()) : null,
      layout: entry.layout,
      arrays: {},
    };
    const arrays = raw.arrays;
    for (const d of entry.layout) {
      if (!isPresent(d, raw) || (copy && d.derived && !validate)) continue;
      arrays[d.name] = session.array(d.name, copy || d.copied);
    }
    if (meta.hasTopology) {
      // The origin vertex of every loop half-edge (for mesh.holes), read through a view
      // that no allocation can detach before it is used.
      const vert = session.array('vert', false);
      const list = arrays.loopHalfedges;
      const lv = new Uint32Array(list.length);
      for (let i = 0; i < list.length; ++i) lv[i] = vert[list[i]];
      arrays.loopVertices = lv;
    }
    return raw;
  }

  // Reads into JS-owned copies. { validate: true } also runs validate() on the
  // wasm-side arrays and stores the result in raw.validation (worker threads).
  async function loadRaw(source, o, { validate = false } = {}) {
    const entry = await moduleFor(o);
    let session = null;
    try {
      session = await readSession(entry, source, validate ? { ...o, validate } : o);
      return extractRaw(entry, session, true, { validate });
    } catch (e) {
      throw wasmFailure(entry, e);
    } finally {
      if (session && !entry.dead) session.delete();
    }
  }

  async function loadFromSource(source, o) {
    if (!o.view) return new Mesh(await loadRaw(source, o), { entry: null, getEntry: currentEntry });
    const entry = await moduleFor(o);
    let session = null;
    try {
      session = await readSession(entry, source, o);
      const raw = extractRaw(entry, session, false);
      return new Mesh(raw, { entry, session, getEntry: currentEntry });
    } catch (e) {
      if (session && !entry.dead) session.delete();
      throw wasmFailure(entry, e);
    }
  }

  // A session holding the mesh of fromIndexed(): the caller's arrays uploaded, then built.
  function indexedSession(entry, positions, triangles, o) {
    const M = entry.module;
    const session = new M._Session(0, 0, 0, false);
    try {
      const put = (name, src) => {
        if (!src) return;
        const view = session.upload(name, src.length);
        if (view === null) throw stlError('out-of-memory', `could not allocate ${name}`);
        view.set(src);
      };
      put('positions', positions);
      put('triangles', triangles);
      put('attributes', o.attributes);
      put('colors', o.colors);
      put('colorValid', o.colorValid);
      session.setMeta('none', o.solids);
      const st = session.fromIndexed(o.weldNone, o.topology, o.tolerance, o.view || !!o.validate, o.topology && !!o.shells);
      if (st) throw fromStatus(st);
      intersectIfAsked(session, o);
      return session;
    } catch (e) {
      if (!entry.dead) session.delete();
      throw e;
    }
  }

  const typedInput = (v, Type, name) => {
    if (v instanceof Type) return v;
    if (ArrayBuffer.isView(v) || Array.isArray(v)) return Type.from(v);
    throw stlError('invalid-argument', `${name} must be a ${Type.name} or an array of numbers`);
  };

  // fromIndexed() on this thread: plain data as loadRaw() gives it, or a view mesh.
  async function indexedRaw(positions, triangles, o, { validate = false } = {}) {
    const entry = await getFull();
    let session = null;
    try {
      session = indexedSession(entry, positions, triangles, validate ? { ...o, validate } : o);
      return extractRaw(entry, session, true, { validate });
    } catch (e) {
      throw wasmFailure(entry, e);
    } finally {
      if (session && !entry.dead) session.delete();
    }
  }

  async function fromIndexed(positions, triangles, options) {
    if (options && options.worker && loadWorker) {
      const w = await loadWorker();
      return w.fromIndexed(positions, triangles, { ...options, worker: false });
    }
    const o = normalizeIndexedOptions(options);
    const pos = typedInput(positions, Float32Array, 'positions');
    const tri = typedInput(triangles, Uint32Array, 'triangles');
    if (!o.view) return new Mesh(await indexedRaw(pos, tri, o), { entry: null, getEntry: currentEntry });
    const entry = await getFull();
    let session = null;
    try {
      session = indexedSession(entry, pos, tri, o);
      return new Mesh(extractRaw(entry, session, false), { entry, session, getEntry: currentEntry });
    } catch (e) {
      if (session && !entry.dead) session.delete();
      throw wasmFailure(entry, e);
    }
  }

  // The chunks of the STL file of a session's mesh, each copied out of wasm memory.
  async function* sessionChunks(entry, session, o) {
    const st = session.writeBegin(o.format, o.colors, o.name, o.normals === 'stored', o.chunkBytes);
    if (st) throw fromStatus(st);
    for (;;) {
      let chunk;
      try {
        const r = session.writeNext();
        if (r === null) return;
        if (!ArrayBuffer.isView(r)) throw fromStatus(r);
        chunk = r.slice();
      } catch (e) {
        throw wasmFailure(entry, e);
      }
      yield chunk;
    }
  }

  // Writes a mesh (a Mesh, or writeInput() data from another thread) as STL, chunk by chunk,
  // in this thread: through the mesh's own session for a live view of the full module, else
  // through a session of the full module its arrays are uploaded to.
  async function* writeHere(mesh, o) {
    const entry = await getFull();
    const live = mesh instanceof Mesh ? liveSession.get(mesh) : null;
    if (live && live.entry === entry) {
      yield* sessionChunks(entry, live.session, o);
      return;
    }
    const input = mesh instanceof Mesh ? writeInput(mesh) : mesh;
    const session = new entry.module._Session(0, 0, 0, false);
    try {
      for (const d of entry.layout) {
        const src = isMeshArray(d) && !d.group ? meshArray(input, d) : null;
        if (!src) continue;
        const view = session.upload(d.name, src.length);
        if (view === null) throw stlError('out-of-memory', `could not allocate ${d.name} for writing`);
        view.set(src);
      }
      session.setMeta(input.colorConvention, input.solids);
      yield* sessionChunks(entry, session, o);
    } catch (e) {
      throw wasmFailure(entry, e);
    } finally {
      if (!entry.dead) session.delete();
    }
  }

  /** The STL file of a mesh as an async iterator of Uint8Array chunks. */
  function writeStl(mesh, options) {
    const o = normalizeWriteOptions(options);
    if (!(mesh instanceof Mesh)) throw stlError('invalid-argument', 'writeStl() needs a Mesh of loadStl() or fromIndexed()');
    const home = workerHome.get(mesh) || (o.worker && loadWorker ? loadWorker : null);
    if (home) {
      return (async function* inWorker() {
        const w = await home();
        yield* w.writeStl(mesh, { ...options, worker: false });
      })();
    }
    return writeHere(mesh, o);
  }

  // For the npm CLI's convert: reads a source as the native CLI does (default options, no
  // normals, no topology) and yields the chunks of its STL file (format: the input's unless
  // writeOptions.format says). Throws the StlError of the read or of the write.
  async function* convert(source, writeOptions) {
    const entry = await getFull();
    const o = { ...normalizeOptions({ topology: false }), tolerance: 0 };
    const w = normalizeWriteOptions(writeOptions);
    let session = null;
    try {
      session = await readSession(entry, source, o);
      if (writeOptions.format === undefined) w.format = session.meta().format === 'ascii' ? 'ascii' : 'binary';
      yield* sessionChunks(entry, session, w);
    } catch (e) {
      throw wasmFailure(entry, e);
    } finally {
      if (session && !entry.dead) session.delete();
    }
  }

  // For the npm CLI's split: reads a source as the native CLI does (default options, the
  // report-only topology with shells) and yields { shells: n } once it is read, then per
  // shell k { k, line(file) } followed by the chunks of its STL file (format: the input's
  // unless writeOptions.format says).
  async function* split(source, writeOptions) {
    const entry = await getFull();
    const o = { ...normalizeOptions({ topology: true, shells: true }), tolerance: 0 };
    const w = normalizeWriteOptions(writeOptions);
    let session = null;
    try {
      session = await readSession(entry, source, o);
      if (writeOptions.format === undefined) w.format = session.meta().format === 'ascii' ? 'ascii' : 'binary';
      const n = JSON.parse(session.shellListJson()).length;
      yield { shells: n };
      for (let k = 0; k < n; ++k) {
        const s = session;
        yield { k, line: (file) => s.splitLine(file, k) };
        const st = session.selectShell(k);
        if (st) throw fromStatus(st);
        yield* sessionChunks(entry, session, w);
      }
    } catch (e) {
      throw wasmFailure(entry, e);
    } finally {
      if (session && !entry.dead) session.delete();
    }
  }

  /** All chunks of writeStl(), in order (toStl() makes a Blob or one array of them). */
  async function stlChunks(mesh, options) {
    const chunks = [];
    for await (const c of writeStl(mesh, options)) chunks.push(c);
    return chunks;
  }

  // A module instantiated on this thread (the core, else the full one), for validate() of
  // copies, which is synchronous; null before the first load.
  function currentEntry() {
    for (const current of [getModule.current(), getFull.current()]) {
      if (current && current.module && !current.dead) return current;
    }
    return null;
  }

  async function loadStl(input, options) {
    if (options && options.worker && loadWorker) {
      const w = await loadWorker();
      return w.loadStl(input, { ...options, worker: false });
    }
    const o = normalizeOptions(options);
    checkAbort(o.signal);
    return loadFromSource(toSource(input), o);
  }

  // For the npm CLI: the native CLI's JSON line or text for one input (the text report
  // always lists the first defects of each kind, as the native one does).
  async function report(source, { file, json, topology = DEFAULTS.topology, tolerance = DEFAULTS.tolerance,
    maxTriangles = DEFAULTS.maxTriangles, maxBytes = DEFAULTS.maxBytes, shells = false, defects = false,
    maxDefects = -1, intersections = false, maxPairs = DEFAULTS.maxPairs }) {
    const withDefects = defects || !json;
    const o = { ...normalizeOptions({ topology, maxTriangles, maxBytes, shells: shells || withDefects, intersections,
      maxPairs }), tolerance, keepMessageBytes: !json };
    const entry = await moduleFor(o);
    const max = maxDefects >= 0 ? maxDefects : json ? 1000 : 5;
    let session = null;
    try {
      session = await readSession(entry, source, o);
      return {
        ok: true,
        text: json ? `${session.infoJson(file, shells, withDefects, max)}\n` : session.infoText(file, shells, withDefects, max),
      };
    } catch (e) {
      const err = wasmFailure(entry, e);
      if (!(err instanceof StlError)) throw err;
      if (json) return { ok: false, error: err, text: `${errorJson(entry.dead ? await getModule() : entry, file, err)}\n` };
      const bytes = err[MESSAGE_BYTES];
      if (!bytes) return { ok: false, error: err, text: `${file}: ${err.message}\n` };
      return { ok: false, error: err, text: concatBytes(new TextEncoder().encode(`${file}: `), bytes, new Uint8Array([10])) };
    } finally {
      if (session && !entry.dead) session.delete();
    }
  }

  function errorJson(entry, file, err) {
    const M = entry.module;
    const num = (x) => (x === undefined ? -1 : x);
    return M._errorJson(file, err.code, err.message, num(err.offset), num(err.line), num(err.triangle));
  }

  // Test and diagnostics hooks (not part of the public API).
  const internal = {
    getModule,
    getFull,
    report,
    async errorJson(file, err) { return errorJson(await getModule(), file, err); },
    async heap() {
      const { module: M } = await getModule();
      return { inUse: M._heapInUse(), size: M._heapSize(), max: M._heapMax() };
    },
    loadRaw,
    loadFromSource,
    indexedRaw,
    writeHere,
    convert,
    split,
    normalizeWriteOptions,
    normalizeIndexedOptions,
  };

  // The exact geometry of any mesh (loaded with or without shells): its positions and
  // triangles (through vertexWeld, for a tolerance weld) go through fromIndexed() without a
  // weld, so vertex and triangle ids stay the mesh's.
  async function findIntersections(mesh, options = {}) {
    if (!(mesh instanceof Mesh)) throw stlError('invalid-argument', 'findIntersections() needs a Mesh');
    if (options === null || typeof options !== 'object') throw stlError('invalid-argument', 'options must be an object');
    let triangles = mesh.triangles;
    const weld = mesh.vertexWeld;
    if (weld && mesh.stats.weldedVertices !== undefined) triangles = triangles.map((v) => weld[v]);
    const m = await fromIndexed(mesh.positions, triangles, { weld: 'none', intersections: true,
      maxPairs: options.maxPairs, worker: options.worker, signal: options.signal });
    const keys = ['zeroAreaTriangles', 'duplicateTriangles', 'selfIntersections', 'intersectionKinds',
      'intersectingTriangles', 'intersectionsComplete', 'solid'];
    const stats = Object.fromEntries(keys.map((k) => [k, m.stats[k]]));
    const result = { stats, shells: m.shells, triangleShell: m.triangleShell, intersections: m.intersections };
    return result;
  }
  setIntersectionFinder(findIntersections);

  return { loadStl, loadFromSource, fromIndexed, writeStl, stlChunks, findIntersections, internal };
}

/** The bytes of several Uint8Arrays, joined. */
export function concatBytes(...parts) {
  const out = new Uint8Array(parts.reduce((n, p) => n + p.length, 0));
  let o = 0;
  for (const p of parts) {
    out.set(p, o);
    o += p.length;
  }
  return out;
}
