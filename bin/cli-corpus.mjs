// The inputs and the per-file reports of the npm CLI's `info` (bin/stltopo.mjs), as
// tools/cli.cpp does them: FILE and DIR arguments and --list files expanded into the files
// to report (expand, readList: a DIR is walked for *.stl files, sorted bytewise by path), one
// report per file (reportOne), and every report printed in input order with --jobs N worker
// threads (reportAll). This module is also the workers' entry point.
import { readdirSync, readFileSync, statSync } from 'node:fs';
import { Worker, isMainThread, parentPort, workerData } from 'node:worker_threads';
import { api, fileSource } from '../dist/instance.node.js';
import { cliCalls } from './cli-wasm.mjs';

const _internal = api.internal;
const wasm = cliCalls(_internal);

// strerror(3) texts (glibc) for the errors fopen/fread/opendir report most often.
const STRERROR = {
  ENOENT: 'No such file or directory',
  EEXIST: 'File exists',
  EACCES: 'Permission denied',
  EISDIR: 'Is a directory',
  ENOTDIR: 'Not a directory',
  ELOOP: 'Too many levels of symbolic links',
  ENAMETOOLONG: 'File name too long',
  EMFILE: 'Too many open files',
  ENFILE: 'Too many open files in system',
  EIO: 'Input/output error',
  EPERM: 'Operation not permitted',
  ENXIO: 'No such device or address',
  ENODEV: 'No such device',
  EINVAL: 'Invalid argument',
  EROFS: 'Read-only file system',
  EBUSY: 'Device or resource busy',
  ETXTBSY: 'Text file busy',
  EOVERFLOW: 'Value too large for defined data type',
  ENOMEM: 'Cannot allocate memory',
};
export const strerror = (e) => STRERROR[e && e.code] || (e && e.message) || String(e);

/** A *.stl name, any case (tools/cli.cpp isStlName). */
const isStlName = (name) => name.length >= 4 && name.slice(-4).toLowerCase() === '.stl';

// A link that points to a regular file or to nothing (a broken link is reported as a file
// that cannot be opened).
function linkToFile(p) {
  try {
    return statSync(p).isFile();
  } catch {
    return true;
  }
}

// Appends the *.stl files under the directory `root` to `out`, sorted bytewise by path
// (tools/cli.cpp walk(): regular files and links to them, links to directories not
// followed; a directory that cannot be read is an input { path, err: its error code }).
function walk(root, out) {
  const found = [];
  const dirs = [root];
  while (dirs.length > 0) {
    const dir = dirs.pop();
    let entries;
    try {
      entries = readdirSync(dir, { withFileTypes: true });
    } catch (e) {
      found.push({ path: dir, err: (e && e.code) || 'EIO' });
      continue;
    }
    const prefix = dir.endsWith('/') ? dir : `${dir}/`;
    for (const e of entries) {
      const p = prefix + e.name;
      if (e.isDirectory()) dirs.push(p);
      else if (isStlName(e.name) && (e.isFile() || (e.isSymbolicLink() && linkToFile(p)))) found.push({ path: p });
    }
  }
  const keyed = found.map((f) => ({ f, key: Buffer.from(f.path) }));
  keyed.sort((x, y) => Buffer.compare(x.key, y.key));
  for (const { f } of keyed) out.push(f);
}

/** A FILE or DIR argument (or a line of a list): a directory is walked, anything else is one input. */
export function expand(arg, out) {
  let dir = false;
  if (arg !== '-') {
    try {
      dir = statSync(arg).isDirectory();
    } catch {
      dir = false;
    }
  }
  if (dir) walk(arg, out);
  else out.push({ path: arg });
}

async function readAll(stream) {
  const chunks = [];
  for await (const c of stream) chunks.push(c);
  return Buffer.concat(chunks);
}

/**
 * Reads a --list (one FILE or DIR per line, '\r\n' or '\n', empty lines skipped) into
 * `out`. Empty string on success, else the usage error to print (tools/cli.cpp readList).
 */
export async function readList(list, out) {
  let bytes;
  try {
    bytes = list === '-' ? await readAll(process.stdin) : readFileSync(list);
  } catch (e) {
    return `stltopo: cannot read the list ${list}: ${strerror(e)}\n`;
  }
  let line = 0;
  for (let at = 0; at < bytes.length;) {
    let end = bytes.indexOf(10, at);
    if (end < 0) end = bytes.length;
    let path = bytes.subarray(at, end);
    at = end + 1;
    ++line;
    if (path.length > 0 && path[path.length - 1] === 13) path = path.subarray(0, path.length - 1);
    if (path.includes(0)) return `stltopo: the list ${list} has a NUL byte on line ${line}\n`;
    if (path.length > 0) expand(path.toString('utf8'), out);
  }
  return '';
}

function stdinSource() {
  const it = process.stdin[Symbol.asyncIterator]();
  return {
    total: 0,
    async next() {
      const { done, value } = await it.next();
      return done ? null : value;
    },
    cancel() {},
  };
}

export { stdinSource };

async function failed(file, json, message) {
  const err = { code: 'invalid-argument', message };
  return { ok: false, text: json ? `${await _internal.errorJson(file, err)}\n` : `${file}: ${message}\n` };
}

/**
 * The report of one input ({ path, err? }) with the options `a` of bin/stltopo.mjs:
 * { ok, text }, text for standard output (ok or --json) or standard error.
 */
export async function reportOne(input, a) {
  const file = input.path;
  const opts = { file, json: a.json, topology: a.topology, tolerance: a.tolerance, maxTriangles: a.maxTriangles,
    maxBytes: a.maxBytes, shells: a.shells, defects: a.defects, maxDefects: a.maxDefects,
    intersections: a.intersections, maxPairs: a.maxPairs, threads: a.threads };
  if (input.err) return failed(file, a.json, `invalid-argument: cannot open ${file}: ${strerror({ code: input.err })}`);
  if (file === '-') return wasm.report(stdinSource(), opts);
  let source;
  try {
    source = await fileSource(file);
  } catch (e) {
    return failed(file, a.json, `invalid-argument: cannot open ${file}: ${strerror(e)}`);
  }
  try {
    return await wasm.report(source, opts);
  } catch (e) {
    if (!e || !e.code || !String(e.code).startsWith('E')) throw e;
    return failed(file, a.json, `invalid-argument: read error on ${file}: ${strerror(e)}`);
  }
}

// A worker thread: reports the inputs it is sent, one at a time.
function startWorker(a) {
  const worker = new Worker(new URL(import.meta.url), { workerData: { stltopoCorpus: true, a } });
  let pending = null;
  const fail = (e) => {
    if (pending) pending.reject(e);
    pending = null;
  };
  worker.on('message', (m) => {
    const p = pending;
    pending = null;
    if (!p) return;
    if (m.error !== undefined) p.reject(new Error(m.error));
    else p.resolve({ ok: m.ok, text: m.text });
  });
  worker.on('error', fail);
  worker.on('exit', (code) => fail(new Error(`a worker thread stopped (exit code ${code})`)));
  return {
    run(input) {
      return new Promise((resolve, reject) => {
        pending = { resolve, reject };
        worker.postMessage(input);
      });
    },
    terminate: () => worker.terminate(),
  };
}

/**
 * Reports every input in order (tools/cli.cpp reportAll): with jobs > 1, worker threads
 * take the next input while this thread prints the reports in input order (standard input
 * is read here); an input starts only when it is fewer than 4 * jobs inputs after the first
 * one not yet printed, so a slow file holds a bounded number of reports. emit(result)
 * prints one. 0 when every file was read, else 1.
 */
export async function reportAll(inputs, a, jobs, emit) {
  const n = inputs.length;
  let rc = 0;
  jobs = Math.min(jobs, n);
  if (jobs <= 1) {
    for (const input of inputs) {
      const r = await reportOne(input, a);
      if (!r.ok) rc = 1;
      await emit(r);
    }
    return rc;
  }
  const window = jobs * 4;
  const slots = new Array(window).fill(null);
  let next = 0;
  let head = 0;
  let failure = null;
  let waiters = [];
  const wake = () => {
    const w = waiters;
    waiters = [];
    for (const f of w) f();
  };
  const changed = () => new Promise((resolve) => waiters.push(resolve));
  const workers = [];
  const lane = async (worker) => {
    for (;;) {
      const i = next++;
      if (i >= n) return;
      while (i >= head + window && !failure) await changed();
      if (failure) return;
      const input = inputs[i];
      slots[i % window] = input.path === '-' && !input.err ? await reportOne(input, a) : await worker.run(input);
      wake();
    }
  };
  try {
    for (let k = 0; k < jobs; ++k) {
      const w = startWorker(a);
      workers.push(w);
      lane(w).catch((e) => {
        failure = failure || e;
        wake();
      });
    }
    for (let k = 0; k < n; ++k) {
      while (!slots[k % window] && !failure) await changed();
      if (failure) throw failure;
      const r = slots[k % window];
      slots[k % window] = null;
      head = k + 1;
      wake();
      if (!r.ok) rc = 1;
      await emit(r);
    }
  } finally {
    failure = failure || new Error('stopped');
    wake();
    await Promise.all(workers.map((w) => w.terminate()));
  }
  return rc;
}

if (!isMainThread && workerData && workerData.stltopoCorpus) {
  const { a } = workerData;
  parentPort.on('message', async (input) => {
    try {
      const r = await reportOne(input, a);
      parentPort.postMessage({ ok: r.ok, text: r.text });
    } catch (e) {
      parentPort.postMessage({ error: String((e && e.stack) || e) });
    }
  });
}
