// The wasm lifecycle: one instance per thread (re-created after a wasm abort), the read
// loop that feeds a session, and the raw results that become meshes (mesh.js).
import { StlError, stlError, abortError, checkAbort, fromStatus, MESSAGE_BYTES, FROM_CORE } from './errors.js';
import { normalizeOptions, normalizeWriteOptions, normalizeIndexedOptions } from './options.js';
import { toSource } from './sources.js';
import { lazyModule } from './wasm-load.js';
import { threadsFor } from './threads.js';
import { Mesh, isPresent, isMeshArray, toValidation, NO_ROOM_FOR_PREV_FACE, meshArray, liveSession, workerHome, writeInput,
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

// Which wasm module each call needs: the one table of it (what each module is built from:
// bindings/CMakeLists.txt). 'core' is stltopo-wasm (loads, the report, validate(), the error
// JSON), 'full' is stltopo-full (also shells and defects, the exact geometry, fromIndexed(),
// writing, EditableMesh). A row that is a function decides from the call's options. Each
// module is instantiated on first use, so a page that only loads files never fetches the
// full one.
export const MODULE_OF = Object.freeze({
  load: (o) => (o.topology && (o.shells || o.intersections) ? 'full' : 'core'),
  fromIndexed: 'full',
  write: 'full',
  edit: 'full',
  errorJson: 'core',
  heap: 'core',
});

// The calls whose work splits over threads (the read, the topology, the exact geometry);
// every other call runs in a single-threaded module.
const THREADED_CALLS = new Set(['load', 'fromIndexed']);

/**
 * instantiate(extra), instantiateFull(extra): the single-threaded modules. With
 * instantiateThreaded(kind, pool, extra) ('wasm' or 'full', pool: the workers to preallocate)
 * loads with threads > 1 (threadsFor(o, defaultThreads, cores)) use the threaded modules; when one
 * cannot be loaded (StlError wasm-load: not served, a bundle without it) they fall back to
 * the single-threaded one, for good (internal.threadsError() says why).
 */
export function createStltopo({ instantiate, instantiateFull, loadWorker = null, instantiateThreaded = null,
  defaultThreads = () => 1, cores = undefined }) {
  const setup = (entry, m) => {
    entry.heapMax = m._heapMax();
    entry.layout = Object.freeze(m._arrayLayout().map((d) => Object.freeze(d)));
    // The EditableMesh's table (STLTOPO_JS_EDIT_ARRAYS), in the full module only.
    if (m._editArrayLayout) entry.editLayout = Object.freeze(m._editArrayLayout().map((d) => Object.freeze(d)));
  };
  const getModule = lazyModule(instantiate, setup);
  const getFull = lazyModule(instantiateFull, setup);
  const getters = { core: getModule, full: getFull };
  // The threaded modules' getters, made on the first threaded load of each (its pool size).
  const threaded = { core: null, full: null };
  const threadedError = { core: null, full: null };
  const allGetters = () => [getModule, getFull, threaded.core, threaded.full].filter(Boolean);

  // The threaded entry of kind for t threads, or null when that module cannot be loaded.
  async function threadedEntry(kind, t) {
    if (!threaded[kind]) {
      const pool = t - 1;
      threaded[kind] = lazyModule((extra) => instantiateThreaded(kind === 'core' ? 'wasm' : 'full', pool, extra),
        (entry, m) => {
          setup(entry, m);
          entry.pool = pool;
        });
    }
    let entry;
    try {
      entry = await threaded[kind]();
    } catch (e) {
      if (!(e instanceof StlError) || e.code !== 'wasm-load') throw e;
      threadedError[kind] = e;
      return null;
    }
    entry.module._setThreads(Math.min(t, entry.pool + 1));
    return entry;
  }

  /** The entry (instantiated module) that `call` (a row of MODULE_OF) needs with options o. */
  const moduleFor = async (call, o) => {
    const row = MODULE_OF[call];
    const kind = typeof row === 'function' ? row(o) : row;
    const t = instantiateThreaded && THREADED_CALLS.has(call) ? threadsFor(o, defaultThreads, cores) : 1;
    if (t > 1 && !threadedError[kind]) {
      const entry = await threadedEntry(kind, t);
      if (entry) return entry;
    }
    return getters[kind]();
  };

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
      for (const g of allGetters()) g.drop(entry);
      // The threaded modules' memory can grow on another thread: its byteLength is current,
      // HEAPU8 only after the glue's next heap access on this one.
      const M = entry.module;
      const heap = M && M.wasmMemory ? M.wasmMemory.buffer.byteLength : M && M.HEAPU8 ? M.HEAPU8.length : 0;
      if (heap + (64 << 20) >= entry.heapMax || /memory|OOM|alloc/i.test(entry.lastError)) {
        return stlError('out-of-memory', `the WebAssembly heap is exhausted (${entry.lastError || e.message})`);
      }
      return e;
    }
    if (isRangeError) return stlError('out-of-memory', e.message);
    // A result past the engine's string limit (V8: 2^29 - 24 characters), in Node an Error of
    // its own code (a RangeError in browsers, taken above).
    if (e && e.code === 'ERR_STRING_TOO_LONG') return stlError('out-of-memory', e.message);
    return e;
  }

  // The one shape of a call into wasm: make(M) creates a session (nothing that can fail
  // between), use(session, entry) works on it, an async generator function whose yields
  // are streamed to the caller (the session lives until the caller stops iterating) and
  // whose return value is the result. Whatever escapes becomes wasmFailure(entry, e),
  // handed to fail(err, entry), which throws it (the default) or returns a result. The
  // session is deleted at the end (unless the instance died), or kept when use succeeded
  // and keep is set (a view mesh owns it then).
  async function* sessionCall(entry, make, use, { keep = false, fail = null } = {}) {
    let session = null;
    let kept = false;
    try {
      session = make(entry.module);
      const result = yield* use(session, entry);
      kept = keep;
      return result;
    } catch (e) {
      const err = wasmFailure(entry, e);
      if (!fail) throw err;
      return await fail(err, entry);
    } finally {
      if (session && !kept && !entry.dead) session.delete();
    }
  }

  // sessionCall() for a call with one result (use: an async function); resolves to it.
  async function withSession(entry, make, use, options) {
    const only = async function* once(session, e) { return await use(session, e); };
    return (await sessionCall(entry, make, only, options).next()).value;
  }

  // A session that a source is read into (readInto), and one that arrays are uploaded to.
  const readerOf = (source, o) => (M) => new M._Session(o.maxTriangles, o.maxBytes, source.total || 0, o.normals);
  const blankSession = (M) => new M._Session(0, 0, 0, false);

  // Reads a source into a session (readerOf's) and finishes it, or throws.
  async function readInto(session, entry, source, o) {
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
    } catch (e) {
      source.cancel(e);
      if (!entry.dead && e instanceof StlError && e[FROM_CORE] && o.keepMessageBytes) e[MESSAGE_BYTES] = session.messageBytes();
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
    // prev and face, asked for views and validate(), are not in the heap when it could not
    // hold them with the rest (the bindings then built the topology without them): they are
    // derived in JS on first read, as for copies, and validate() cannot run in wasm.
    const noPrevFace = meta.hasTopology && (copy ? validate : true) &&
      session.array('prev', false).length !== session.array('next', false).length;
    const raw = {
      format: meta.format,
      colorConvention: meta.colorConvention,
      nVertices: meta.nVertices,
      nTriangles: meta.nTriangles,
      hasTopology: meta.hasTopology,
      hasNormals: meta.hasNormals,
      hasShells: meta.hasShells,
      hasIntersections: !!meta.hasIntersections,
      shellTable: meta.hasShells ? session.shellTable() : null, // mesh.shells' columns, built on first read
      indexed: meta.indexed,
      solids: meta.solids,
      warnings: meta.warnings,
      counts: meta.counts,
      statsJson: session.infoJson('', false, false, 0),
      threads: entry.module._threads(),
      validation: noPrevFace ? NO_ROOM_FOR_PREV_FACE : validate && meta.hasTopology ? toValidation(session.validate()) : null,
      layout: entry.layout,
      arrays: {},
    };
    const arrays = raw.arrays;
    for (const d of entry.layout) {
      if (!isPresent(d, raw) || (copy && d.derived && !validate)) continue;
      if (noPrevFace && (d.name === 'prev' || d.name === 'face')) continue;
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
    const ro = validate ? { ...o, validate } : o;
    return withSession(await moduleFor('load', o), readerOf(source, ro), async (session, entry) => {
      await readInto(session, entry, source, ro);
      return extractRaw(entry, session, true, { validate });
    });
  }

  async function loadFromSource(source, o) {
    if (!o.view) return new Mesh(await loadRaw(source, o), { entry: null, getEntry: currentEntry });
    return withSession(await moduleFor('load', o), readerOf(source, o), async (session, entry) => {
      await readInto(session, entry, source, o);
      return new Mesh(extractRaw(entry, session, false), { entry, session, getEntry: currentEntry });
    }, { keep: true });
  }

  // Builds the mesh of fromIndexed() in a blank session: the caller's arrays uploaded, then built.
  function buildIndexed(session, positions, triangles, o) {
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
  }

  const typedInput = (v, Type, name) => {
    if (v instanceof Type) return v;
    if (ArrayBuffer.isView(v) || Array.isArray(v)) return Type.from(v);
    throw stlError('invalid-argument', `${name} must be a ${Type.name} or an array of numbers`);
  };

  // fromIndexed() on this thread: plain data as loadRaw() gives it, or a view mesh.
  async function indexedRaw(positions, triangles, o, { validate = false } = {}) {
    return withSession(await moduleFor('fromIndexed', o), blankSession, async (session, entry) => {
      buildIndexed(session, positions, triangles, validate ? { ...o, validate } : o);
      return extractRaw(entry, session, true, { validate });
    });
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
    return withSession(await moduleFor('fromIndexed', o), blankSession, async (session, entry) => {
      buildIndexed(session, pos, tri, o);
      return new Mesh(extractRaw(entry, session, false), { entry, session, getEntry: currentEntry });
    }, { keep: true });
  }

  // The chunks of the STL file of a session's mesh, each copied out of wasm memory (copy
  // false: views of it, each valid until the next is asked for).
  async function* sessionChunks(entry, session, o, copy = true) {
    const st = session.writeBegin(o.format, o.colors, o.name, o.normals === 'stored', o.chunkBytes);
    if (st) throw fromStatus(st);
    for (;;) {
      let chunk;
      try {
        const r = session.writeNext();
        if (r === null) return;
        if (!ArrayBuffer.isView(r)) throw fromStatus(r);
        chunk = copy ? r.slice() : r;
      } catch (e) {
        throw wasmFailure(entry, e);
      }
      yield chunk;
    }
  }

  // Writes a mesh (a Mesh, or writeInput() data from another thread) as STL, chunk by chunk,
  // in this thread: through the mesh's own session for a live view of the full module, else
  // through a session of the full module its arrays are uploaded to.
  async function* writeHere(mesh, o, copy = true) {
    const entry = await moduleFor('write', o);
    const live = mesh instanceof Mesh ? liveSession.get(mesh) : null;
    if (live && live.entry === entry) {
      yield* sessionChunks(entry, live.session, o, copy);
      return;
    }
    const input = mesh instanceof Mesh ? writeInput(mesh) : mesh;
    yield* sessionCall(entry, blankSession, async function* upload(session) {
      for (const d of entry.layout) {
        const src = isMeshArray(d) && !d.group ? meshArray(input, d) : null;
        if (!src) continue;
        const view = session.upload(d.name, src.length);
        if (view === null) throw stlError('out-of-memory', `could not allocate ${d.name} for writing`);
        view.set(src);
      }
      session.setMeta(input.colorConvention, input.solids);
      yield* sessionChunks(entry, session, o, copy);
    });
  }

  /** The worker that writes this mesh (the one that holds it, or a fresh one when the options
   * ask for a worker), or null when it is written on this thread. */
  function writerHome(mesh, o) {
    return workerHome.get(mesh) || (o.worker && loadWorker ? loadWorker : null);
  }

  /** The STL file of a mesh as an async iterator of Uint8Array chunks. */
  function writeStl(mesh, options) {
    const o = normalizeWriteOptions(options);
    if (!(mesh instanceof Mesh)) throw stlError('invalid-argument', 'writeStl() needs a Mesh of loadStl() or fromIndexed()');
    const home = writerHome(mesh, o);
    if (home) {
      return (async function* inWorker() {
        const w = await home();
        yield* w.writeStl(mesh, { ...options, worker: false });
      })();
    }
    return writeHere(mesh, o);
  }

  /** All chunks of writeStl(), in order (what toStl() joins where it cannot do better). */
  async function stlChunks(mesh, options) {
    const chunks = [];
    for await (const c of writeStl(mesh, options)) chunks.push(c);
    return chunks;
  }

  /** toStl() in Node: the file as one Uint8Array. A binary file's size is known beforehand (84
   * bytes a solid and 50 a triangle), so its chunks go from wasm memory straight into it: one
   * copy where stlChunks() and a join make two, each into fresh memory (the 1M torus: 285-300
   * against 143-155 ms, *Stop 68* in bench/PROFILE.md). */
  async function stlBytes(mesh, options) {
    const o = normalizeWriteOptions(options);
    const here = mesh instanceof Mesh && !writerHome(mesh, o);
    const n = here ? mesh.nTriangles : NaN;  // trusted for the size only when the arrays agree
    const sized = Number.isInteger(n) && n >= 0 && mesh.triangles && mesh.triangles.length === 3 * n;
    if (!sized || o.format !== 'binary') return concatBytes(...(await stlChunks(mesh, options)));
    const out = new Uint8Array(84 * Math.max(1, mesh.solids.length) + 50 * n);
    const rest = [];  // what does not fit: nothing, unless the mesh's figures were changed
    let at = 0;
    for await (const view of writeHere(mesh, o, false)) {
      if (rest.length === 0 && at + view.length <= out.length) {
        out.set(view, at);
        at += view.length;
      } else {
        rest.push(view.slice());
      }
    }
    return rest.length === 0 && at === out.length ? out : concatBytes(out.subarray(0, at), ...rest);
  }

  /** toStl() in browsers: the file as a Blob. Each chunk is copied once, into a Blob of its
   * own (a Blob copies the bytes it is made of), where stlChunks() sliced every chunk first and
   * held the slices, a second copy of the whole file in the page's JS heap, until the Blob was
   * made; the Blob of the chunks' Blobs copies nothing. Chromium, the 1M torus: the same time,
   * the JS heap after it 69 against 164 MiB (*Stop 68* in bench/PROFILE.md). A chunk in shared
   * memory would be sliced still (a Blob takes no view of a SharedArrayBuffer); writes run on
   * the single-threaded full module. */
  async function stlBlob(mesh, options) {
    const o = normalizeWriteOptions(options);
    const type = { type: 'model/stl' };
    const here = mesh instanceof Mesh && !writerHome(mesh, o);
    if (!here) return new Blob(await stlChunks(mesh, options), type);
    const parts = [];
    const big = options && options.chunkBytes !== undefined ? o : { ...o, chunkBytes: BLOB_CHUNK_BYTES };
    for await (const view of writeHere(mesh, big, false)) {
      parts.push(new Blob([view.buffer instanceof ArrayBuffer ? view : view.slice()]));
    }
    return new Blob(parts, type);
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

  function errorJson(entry, file, err) {
    const M = entry.module;
    const num = (x) => (x === undefined ? -1 : x);
    return M._errorJson(file, err.code, err.message, num(err.offset), num(err.line), num(err.triangle));
  }

  // The hooks that are not public API: the tests', the worker thread's (worker-handler.js)
  // and the npm CLI's (bin/cli-wasm.mjs builds its calls on the session helpers).
  const internal = {
    getModule,
    getFull,
    moduleFor,
    /** Why the threaded module of kind ('core', 'full') could not be loaded; null if it could. */
    threadsError: (kind = 'core') => threadedError[kind],
    /** The threads a load with options o would ask for here (before the pool's cap). */
    threadsFor: (o) => (instantiateThreaded ? threadsFor(o, defaultThreads, cores) : 1),
    /** The module EditableMesh needs (its row of MODULE_OF). */
    editModule: () => moduleFor('edit'),
    /** What escaped a call into wasm, as an error; an instance that aborted is dropped. */
    wasmFailure,
    /** The error JSON line of the native CLI for err, written by `entry` when it is alive. */
    async errorJson(file, err, entry = null) {
      return errorJson(entry && !entry.dead ? entry : await moduleFor('errorJson'), file, err);
    },
    async heap() {
      const { module: M } = await moduleFor('heap');
      return { inUse: M._heapInUse(), size: M._heapSize(), max: M._heapMax() };
    },
    sessionCall,
    withSession,
    readerOf,
    readInto,
    sessionChunks,
    loadRaw,
    loadFromSource,
    indexedRaw,
    writeHere,
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

  return { loadStl, loadFromSource, fromIndexed, writeStl, stlBytes, stlBlob, findIntersections, internal };
}

// The chunks of toStl()'s Blob when the caller sets no chunkBytes: few Blobs (each costs
// about as much as copying a MiB into it in Chromium), at 8 MiB of wasm memory.
const BLOB_CHUNK_BYTES = 8 << 20;

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
