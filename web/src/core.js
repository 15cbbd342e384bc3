// stltopo's JavaScript layer, shared by the browser entry (index.js), the Node
// entry (node.js) and the worker threads. It drives the raw Embind API of
// bindings/bindings.cpp (`_Session` and friends) and turns it into loadStl().
//
// Memory: by default every array is copied out of wasm memory in the same
// expression that views it (view + slice), and the wasm-side session is deleted
// before loadStl resolves: nothing to dispose, nothing detaches (prev, face and vert
// are not copied but rebuilt in JS on first read: see DERIVED_ARRAYS). With
// { view: true } the arrays are borrowed views into wasm memory, valid until
// mesh.dispose(). A view *you keep in a variable* detaches (length 0) when the
// wasm memory grows (emscripten#6747); the mesh's own properties re-create it.

export const kInvalid = 0xffffffff;

/** Edge classes per half-edge pair k = e >> 1 (mesh.problems.pairKind). */
export const EdgeKind = Object.freeze({ Interior: 0, Boundary: 1, Inconsistent: 2, NonManifold: 3 });

export class StlError extends Error {
  constructor(code, message, location) {
    super(message);
    this.name = 'StlError';
    this.code = code;
    if (location) {
      if (location.offset !== undefined) this.offset = location.offset;
      if (location.line !== undefined) this.line = location.line;
      if (location.triangle !== undefined) this.triangle = location.triangle;
    }
  }
}

const CHUNK = 1 << 20; // bytes handed to the core per feed() call
const YIELD_MS = 16; // longest stretch of feeding without giving the event loop a turn
const PROGRESS_MS = 50; // onProgress at most this often (plus once at the end)

const TOPOLOGY_ARRAYS = [
  'next', 'prev', 'vert', 'face', 'pairKind', 'triangleHalfedge', 'vertexHalfedge', 'vertexWeld',
  'loopHalfedge', 'loopOffsets', 'loopHalfedges', 'loopIsSeam', 'loopPerimeter', 'triangleDegenerate',
  'vertexNonManifold',
];
// Small per-loop arrays: always copied, so holes/seams never dangle.
const LOOP_ARRAYS = ['loopOffsets', 'loopHalfedges', 'loopIsSeam', 'loopPerimeter'];
// Half-edge arrays that copies (and worker results) do not take from wasm: they follow
// from next, triangleHalfedge, triangles, vertexWeld and the loops, and are rebuilt in JS
// on first use, which costs about as much as copying them (3 x 4 bytes per half-edge)
// would. For copies the core does not even build prev and face (prevAndFace: false).
const DERIVED_ARRAYS = ['prev', 'face', 'vert'];

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

function abortError() {
  return new StlError('aborted', 'aborted: the load was cancelled (AbortSignal)');
}
function checkAbort(signal) {
  if (signal && signal.aborted) throw abortError();
}
function invalid(message) {
  return new StlError('invalid-argument', `invalid-argument: ${message}`);
}
// The CLI prints core messages as raw bytes, like the native CLI.
const MESSAGE_BYTES = Symbol('stltopo.messageBytes');
const FROM_CORE = Symbol('stltopo.fromCore');

function fromStatus(st) {
  const e = new StlError(st.code, st.message, st);
  e[FROM_CORE] = true;
  return e;
}

// ---------------------------------------------------------------------------
// Options

export function normalizeOptions(options) {
  if (options == null) options = {};
  if (typeof options !== 'object') throw invalid('options must be an object');
  const o = {
    topology: options.topology === undefined ? true : !!options.topology,
    tolerance: 0,
    maxTriangles: 2 ** 28,
    maxBytes: 0,
    normals: !!options.normals,
    signal: options.signal || null,
    onProgress: options.onProgress || null,
    view: !!options.view,
  };
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
    if (!Number.isInteger(n) || n < 0 || n > 0xffffffff) throw invalid('maxTriangles must be an integer in [0, 2^32)');
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

// ---------------------------------------------------------------------------
// Inputs. A source is { total, next(): Promise<Uint8Array|null>, cancel() }.

function toBytes(chunk) {
  if (chunk instanceof Uint8Array) return chunk;
  if (ArrayBuffer.isView(chunk)) return new Uint8Array(chunk.buffer, chunk.byteOffset, chunk.byteLength);
  if (chunk instanceof ArrayBuffer) return new Uint8Array(chunk);
  throw invalid('stream chunks must be Uint8Array (or ArrayBuffer)');
}

export function bufferSource(bytes) {
  let done = false;
  return {
    total: bytes.byteLength,
    async next() {
      if (done) return null;
      done = true;
      return bytes;
    },
    cancel() {},
  };
}

export function streamSource(stream, total) {
  let reader;
  try {
    reader = stream.getReader();
  } catch (e) {
    throw invalid(`cannot read the stream (${e.message})`);
  }
  let finished = false;
  return {
    total,
    async next() {
      if (finished) return null;
      const { done, value } = await reader.read();
      if (done) {
        finished = true;
        return null;
      }
      return toBytes(value);
    },
    cancel(reason) {
      if (finished) return;
      finished = true;
      reader.cancel(reason).catch(() => {});
    },
  };
}

export function iteratorSource(iterable, total) {
  const it = iterable[Symbol.asyncIterator]();
  let finished = false;
  return {
    total,
    async next() {
      if (finished) return null;
      const { done, value } = await it.next();
      if (done) {
        finished = true;
        return null;
      }
      return toBytes(value);
    },
    cancel() {
      if (finished) return;
      finished = true;
      if (typeof it.return === 'function') Promise.resolve(it.return()).catch(() => {});
    },
  };
}

function isResponse(x) {
  return (typeof Response !== 'undefined' && x instanceof Response) ||
    (typeof x.arrayBuffer === 'function' && 'body' in x && 'status' in x && x.headers && typeof x.headers.get === 'function');
}

function contentLength(response) {
  const enc = response.headers.get('content-encoding');
  if (enc && enc !== 'identity') return 0; // the length counts compressed bytes
  const n = Number(response.headers.get('content-length'));
  return Number.isFinite(n) && n > 0 ? n : 0;
}

export function toSource(input) {
  if (input == null) throw invalid('no input');
  if (input instanceof ArrayBuffer) return bufferSource(new Uint8Array(input));
  if (typeof SharedArrayBuffer !== 'undefined' && input instanceof SharedArrayBuffer) {
    return bufferSource(new Uint8Array(input));
  }
  if (ArrayBuffer.isView(input)) return bufferSource(new Uint8Array(input.buffer, input.byteOffset, input.byteLength));
  if (typeof input.getReader === 'function') return streamSource(input, 0);
  if (typeof input.stream === 'function' && typeof input.size === 'number') return streamSource(input.stream(), input.size);
  if (typeof input === 'object' && isResponse(input)) {
    if (!input.ok && input.status !== 0) throw invalid(`HTTP response status ${input.status}`);
    if (input.bodyUsed) throw invalid('the Response body was already used');
    if (!input.body) return bufferSource(new Uint8Array(0));
    return streamSource(input.body, contentLength(input));
  }
  if (typeof input[Symbol.asyncIterator] === 'function') return iteratorSource(input, 0);
  throw invalid('input must be an ArrayBuffer, a typed array, a Blob/File, a Response or a ReadableStream');
}

// ---------------------------------------------------------------------------
// The module (one wasm instance per thread, re-created after a wasm abort).

export function createStltopo({ instantiate, loadWorker = null }) {
  let current = null;

  function getModule() {
    if (!current || current.dead) {
      const entry = { module: null, dead: false, heapMax: 0, lastError: '' };
      entry.promise = instantiate({
        onAbort(what) { entry.dead = true; entry.lastError = String(what || ''); },
        printErr(text) { entry.lastError = String(text); },
        print() {},
      }).then(
        (m) => {
          entry.module = m;
          entry.heapMax = m._heapMax();
          return entry;
        },
        (e) => {
          if (current === entry) current = null;
          throw e;
        },
      );
      current = entry;
    }
    return current.promise;
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
      if (current === entry) current = null;
      const heap = entry.module && entry.module.HEAPU8 ? entry.module.HEAPU8.length : 0;
      if (heap + (64 << 20) >= entry.heapMax || /memory|OOM|alloc/i.test(entry.lastError)) {
        return new StlError('out-of-memory', `out-of-memory: the WebAssembly heap is exhausted (${e.message})`);
      }
      return e;
    }
    if (isRangeError) return new StlError('out-of-memory', `out-of-memory: ${e.message}`);
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
          if (buf === null) throw new StlError('out-of-memory', 'out-of-memory: could not allocate the input buffer');
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
      const st = session.finish(o.topology, o.tolerance, o.view || !!o.validate);
      if (st) throw fromStatus(st);
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

  // Plain data of a finished session: the worker message format.
  function extractRaw(session, copy, validate = false) {
    const meta = session.meta();
    const arrays = {};
    const get = (name) => session.array(name, copy);
    arrays.positions = get('positions');
    arrays.triangles = get('triangles');
    arrays.attributes = get('attributes');
    if (meta.hasNormals) arrays.normals = get('normals');
    if (meta.colorConvention !== 'none') {
      arrays.colors = get('colors');
      arrays.colorValid = get('colorValid');
    }
    if (meta.hasTopology) {
      for (const n of TOPOLOGY_ARRAYS) {
        if (copy && DERIVED_ARRAYS.includes(n)) continue; // rebuilt in JS on first use (deriveHalfedgeArrays)
        arrays[n] = LOOP_ARRAYS.includes(n) ? session.array(n, true) : get(n);
      }
      // The origin vertex of every loop half-edge (for mesh.holes), read through a view
      // that no allocation can detach before it is used.
      const vert = session.array('vert', false);
      const list = arrays.loopHalfedges;
      const lv = new Uint32Array(list.length);
      for (let i = 0; i < list.length; ++i) lv[i] = vert[list[i]];
      arrays.loopVertices = lv;
    }
    return {
      format: meta.format,
      colorConvention: meta.colorConvention,
      nVertices: meta.nVertices,
      nTriangles: meta.nTriangles,
      hasTopology: meta.hasTopology,
      solids: meta.solids,
      warnings: meta.warnings,
      counts: meta.counts,
      statsJson: session.infoJson(''),
      validation: validate && meta.hasTopology ? toValidation(session.validate()) : null,
      arrays,
    };
  }

  // Reads into JS-owned copies. { validate: true } also runs validate() on the
  // wasm-side arrays and stores the result in raw.validation (worker threads).
  async function loadRaw(source, o, { validate = false } = {}) {
    const entry = await getModule();
    let session = null;
    try {
      session = await readSession(entry, source, validate ? { ...o, validate } : o);
      return extractRaw(session, true, validate);
    } catch (e) {
      throw wasmFailure(entry, e);
    } finally {
      if (session && !entry.dead) session.delete();
    }
  }

  async function loadFromSource(source, o) {
    if (!o.view) return new Mesh(await loadRaw(source, o), { entry: null, getEntry: currentEntry });
    const entry = await getModule();
    let session = null;
    try {
      session = await readSession(entry, source, o);
      const raw = extractRaw(session, false);
      return new Mesh(raw, { entry, session, getEntry: currentEntry });
    } catch (e) {
      if (session && !entry.dead) session.delete();
      throw wasmFailure(entry, e);
    }
  }

  function currentEntry() {
    return current && current.module && !current.dead ? current : null;
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

  // For the npm CLI: the native CLI's JSON line or text for one input.
  async function report(source, { file, json, topology = true, tolerance = 0, maxTriangles = 2 ** 28, maxBytes = 0 }) {
    const entry = await getModule();
    const o = { ...normalizeOptions({ topology, maxTriangles, maxBytes }), tolerance, keepMessageBytes: !json };
    let session = null;
    try {
      session = await readSession(entry, source, o);
      return { ok: true, text: json ? `${session.infoJson(file)}\n` : session.infoText(file) };
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
    report,
    async errorJson(file, err) { return errorJson(await getModule(), file, err); },
    async heap() {
      const { module: M } = await getModule();
      return { inUse: M._heapInUse(), size: M._heapSize(), max: M._heapMax() };
    },
    loadRaw,
    loadFromSource,
  };

  return { loadStl, loadFromSource, internal };
}

function concatBytes(...parts) {
  const out = new Uint8Array(parts.reduce((n, p) => n + p.length, 0));
  let o = 0;
  for (const p of parts) {
    out.set(p, o);
    o += p.length;
  }
  return out;
}

// ---------------------------------------------------------------------------
// The mesh object.

const registry = typeof FinalizationRegistry === 'function'
  ? new FinalizationRegistry(({ entry, session }) => {
    if (!entry.dead && !session.isDeleted()) session.delete();
  })
  : null;

function buildLoops(arrays, nTriangles) {
  const holes = [];
  const seams = [];
  const off = arrays.loopOffsets;
  if (!off) return { holes, seams };
  const list = arrays.loopHalfedges;
  const lv = arrays.loopVertices;
  for (let h = 0; h + 1 < off.length; ++h) {
    const halfedges = list.subarray(off[h], off[h + 1]);
    const vertices = lv.slice(off[h], off[h + 1]);
    const loop = { id: h, face: nTriangles + h, halfedges, vertices, edgeCount: halfedges.length, perimeter: arrays.loopPerimeter[h] };
    (arrays.loopIsSeam[h] ? seams : holes).push(loop);
  }
  return { holes, seams };
}

// prev, face and vert of a copied mesh, from the arrays it holds (see DERIVED_ARRAYS).
// Every triangle half-edge is reached from triangleHalfedge through next; every loop
// half-edge e is listed in its loop, and its origin is the destination of its twin
// (a triangle half-edge), which is the origin of next[e ^ 1].
function deriveHalfedgeArrays(arrays, nTriangles, which) {
  const next = arrays.next;
  const n = next.length;
  if (which === 'prev') {
    const prev = new Uint32Array(n);
    for (let e = 0; e < n; ++e) prev[next[e]] = e;
    return prev;
  }
  const th = arrays.triangleHalfedge;
  const list = arrays.loopHalfedges;
  const off = arrays.loopOffsets;
  if (which === 'face') {
    const face = new Uint32Array(n);
    for (let t = 0; t < nTriangles; ++t) {
      const h0 = th[t];
      if (h0 === kInvalid) continue;
      const h1 = next[h0];
      face[h0] = t;
      face[h1] = t;
      face[next[h1]] = t;
    }
    for (let h = 0; h + 1 < off.length; ++h) for (let i = off[h]; i < off[h + 1]; ++i) face[list[i]] = nTriangles + h;
    return face;
  }
  const vert = new Uint32Array(n);
  const tri = arrays.triangles;
  const weld = arrays.vertexWeld;
  // The exact weld maps every vertex to itself: then skip the lookup, a random read per
  // corner on a shuffled file.
  let identity = true;
  for (let v = 0; v < weld.length && identity; ++v) identity = weld[v] === v;
  for (let t = 0; t < nTriangles; ++t) {
    const h0 = th[t];
    if (h0 === kInvalid) continue;
    const h1 = next[h0];
    const a = tri[3 * t], b = tri[3 * t + 1], c = tri[3 * t + 2];
    vert[h0] = identity ? a : weld[a];
    vert[h1] = identity ? b : weld[b];
    vert[next[h1]] = identity ? c : weld[c];
  }
  for (let i = 0; i < list.length; ++i) {
    const e = list[i];
    vert[e] = vert[next[(e ^ 1) >>> 0]];
  }
  return vert;
}

export class Mesh {
  #entry;
  #session;
  #getEntry;
  #counts;
  #validation;
  #disposed = false;

  constructor(raw, { entry = null, session = null, getEntry = () => null } = {}) {
    this.#entry = entry;
    this.#session = session;
    this.#getEntry = getEntry;
    this.#counts = raw.counts;
    this.#validation = raw.validation || null;
    const live = session !== null;
    /** true when the arrays are borrowed views into wasm memory (dispose() frees them). */
    this.view = live;
    this.format = raw.format;
    this.nVertices = raw.nVertices;
    this.nTriangles = raw.nTriangles;
    const arrays = raw.arrays;
    const cache = live ? { ...arrays } : arrays;
    // Each array property: a plain value for copies; for views, a getter that
    // re-creates the view when memory growth detached it.
    const def = (obj, key, name) => {
      if (!live && arrays[name] === undefined && DERIVED_ARRAYS.includes(name)) {
        // Rebuilt on first read, then a plain property.
        Object.defineProperty(obj, key, {
          enumerable: true,
          configurable: true,
          get: () => {
            const a = deriveHalfedgeArrays(arrays, raw.nTriangles, name);
            Object.defineProperty(obj, key, { value: a, enumerable: true, writable: true, configurable: true });
            return a;
          },
        });
        return;
      }
      if (!live || LOOP_ARRAYS.includes(name)) {
        obj[key] = arrays[name];
        return;
      }
      Object.defineProperty(obj, key, {
        enumerable: true,
        get: () => {
          if (this.#disposed) throw new StlError('invalid-argument', 'invalid-argument: the mesh was disposed');
          let a = cache[name];
          if (a.buffer.byteLength === 0) cache[name] = a = session.array(name, false);
          return a;
        },
      });
    };
    def(this, 'positions', 'positions');
    def(this, 'triangles', 'triangles');
    def(this, 'attributes', 'attributes');
    this.colorConvention = raw.colorConvention;
    if (arrays.colors) {
      def(this, 'colors', 'colors');
      def(this, 'colorValid', 'colorValid');
    } else {
      this.colors = null;
      this.colorValid = null;
    }
    if (arrays.normals) def(this, 'normals', 'normals');
    else this.normals = null;
    this.solids = raw.solids;
    this.warnings = raw.warnings;
    if (raw.hasTopology) {
      this.nHalfedges = arrays.next.length;
      this.halfedges = {};
      for (const n of ['next', 'prev', 'vert', 'face']) def(this.halfedges, n, n);
      def(this, 'triangleHalfedge', 'triangleHalfedge');
      def(this, 'vertexHalfedge', 'vertexHalfedge');
      def(this, 'loopHalfedge', 'loopHalfedge');
      def(this, 'vertexWeld', 'vertexWeld');
      this.loops = {
        offsets: arrays.loopOffsets,
        halfedges: arrays.loopHalfedges,
        isSeam: arrays.loopIsSeam,
        perimeter: arrays.loopPerimeter,
      };
      const { holes, seams } = buildLoops(arrays, raw.nTriangles);
      this.holes = holes;
      this.seams = seams;
      this.problems = {};
      def(this.problems, 'pairKind', 'pairKind');
      def(this.problems, 'triangleDegenerate', 'triangleDegenerate');
      def(this.problems, 'vertexNonManifold', 'vertexNonManifold');
    } else {
      this.nHalfedges = 0;
      this.halfedges = null;
      this.triangleHalfedge = null;
      this.vertexHalfedge = null;
      this.loopHalfedge = null;
      this.vertexWeld = null;
      this.loops = null;
      this.holes = [];
      this.seams = [];
      this.problems = null;
    }
    const stats = JSON.parse(raw.statsJson);
    delete stats.file;
    this.stats = stats;
    if (live && registry) registry.register(this, { entry, session }, this);
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

  /** Checks every topology invariant: { ok: true } or the first violation. */
  validate() {
    if (this.#disposed) throw new StlError('invalid-argument', 'invalid-argument: the mesh was disposed');
    if (this.#session) return toValidation(this.#session.validate());
    if (this.#validation) return { ...this.#validation };
    if (!this.halfedges) {
      return { ok: false, code: 'invalid-argument', message: 'invalid-argument: the mesh has no topology (loaded with topology: false)' };
    }
    const entry = this.#getEntry();
    if (!entry) throw new Error('stltopo: validate() needs the wasm module on this thread; call loadStl() here first');
    return validateArrays(entry.module, this, this.#counts);
  }

  /** Frees the wasm memory of a { view: true } mesh; a no-op for copies. */
  dispose() {
    if (this.#disposed || !this.#session) return;
    this.#disposed = true;
    if (registry) registry.unregister(this);
    if (!this.#entry.dead) this.#session.delete();
    this.#session = null;
  }
}

function toValidation(st) {
  if (!st) return { ok: true };
  const r = { ok: false, code: st.code, message: st.message };
  if (st.element !== undefined) r.element = st.element;
  return r;
}

function validateArrays(M, mesh, counts) {
  const s = new M._Session(0, 0, 0, false);
  try {
    const up = (name, src) => {
      const view = s.upload(name, src.length);
      if (view === null) throw new StlError('out-of-memory', `out-of-memory: could not allocate ${name} for validate()`);
      view.set(src);
    };
    up('positions', mesh.positions);
    up('triangles', mesh.triangles);
    const h = mesh.halfedges;
    up('next', h.next);
    up('prev', h.prev);
    up('vert', h.vert);
    up('face', h.face);
    up('pairKind', mesh.problems.pairKind);
    up('triangleDegenerate', mesh.problems.triangleDegenerate);
    up('vertexNonManifold', mesh.problems.vertexNonManifold);
    up('triangleHalfedge', mesh.triangleHalfedge);
    up('vertexHalfedge', mesh.vertexHalfedge);
    up('vertexWeld', mesh.vertexWeld);
    up('loopHalfedge', mesh.loopHalfedge);
    up('loopOffsets', mesh.loops.offsets);
    up('loopHalfedges', mesh.loops.halfedges);
    up('loopIsSeam', mesh.loops.isSeam);
    up('loopPerimeter', mesh.loops.perimeter);
    s.setCounts(counts.nHoles, counts.nSeams, counts.nUsedVertices);
    return toValidation(s.validate());
  } finally {
    s.delete();
  }
}

/** The ArrayBuffers of a raw result, for a postMessage transfer list. */
export function transferList(raw) {
  const set = new Set();
  for (const a of Object.values(raw.arrays)) if (a && a.buffer) set.add(a.buffer);
  return [...set];
}

export function errorToMessage(e) {
  if (e instanceof StlError) {
    return { stl: true, code: e.code, message: e.message, offset: e.offset, line: e.line, triangle: e.triangle };
  }
  return { stl: false, name: e && e.name, message: String(e && e.message !== undefined ? e.message : e) };
}

export function errorFromMessage(m) {
  if (m.stl) return new StlError(m.code, m.message, m);
  const e = new Error(m.message);
  if (m.name) e.name = m.name;
  return e;
}
