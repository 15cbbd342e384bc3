// The inputs and the per-file reports of the npm CLI's `info` (bin/stltopo.mjs), as
// tools/cli.cpp does them: FILE and DIR arguments and --list files expanded into the files
// to report (expand, readList: a DIR is walked for *.stl files, sorted bytewise by path), one
// report per file (reportOne), and every report printed in input order with --jobs N worker
// threads (reportAll). This module is also the workers' entry point.
import { readdirSync, readFileSync, statSync } from 'node:fs';
import { totalmem } from 'node:os';
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
    // A system error of the read (ENOENT, EIO, ...); anything else is not the file's.
    if (!e || !/^E[A-Z0-9]+$/.test(String(e.code))) throw e;
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

const U64_MAX = (1n << 64n) - 1n;

/**
 * What reading an input may take at its peak, for the memory gate (tools/cli.cpp
 * peakEstimate, which gives the measured worst cases): `factor` times a regular file's size;
 * standard input, a pipe or a device counts as the whole budget (read alone); an input that
 * cannot be looked at, as nothing (it fails when opened). BigInts, as the native CLI's
 * uint64_t.
 */
function peakEstimate(input, budget, factor) {
  if (input.err) return 0n;
  if (input.path === '-') return budget;
  let st;
  try {
    st = statSync(input.path, { bigint: true });
  } catch {
    return 0n;
  }
  if (!st.isFile()) return budget;
  return st.size > U64_MAX / factor ? U64_MAX : st.size * factor;
}

// A worker that read a file past this estimate is replaced by a fresh one: a wasm heap
// never shrinks, so the worker would otherwise hold that file's memory for every later one,
// out of the gate's sight. (STLTOPO_TEST_RECYCLE_BYTES: the tests' own threshold.)
const RECYCLE_ESTIMATE = BigInt(process.env.STLTOPO_TEST_RECYCLE_BYTES || 256 << 20);

/**
 * Reports every input in order (tools/cli.cpp reportAll): with jobs > 1, worker threads
 * take the next input while this thread prints the reports in input order (standard input
 * is read here); an input starts only when it is fewer than 4 * jobs inputs after the first
 * one not yet printed, so a slow file holds a bounded number of reports, and only when the
 * memory gate lets it: in input order, each while the estimates of the inputs being read,
 * its own included, fit in a.maxMemory bytes (0n: half the machine's memory), or when no
 * other input is being read. a.jobsLog (the hidden --test-jobs-log) prints each start and
 * end to standard error after the reports, as the native CLI does. emit(result) prints one.
 * 0 when every file was read, else 1.
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
  const budget = a.maxMemory ? BigInt(a.maxMemory) : BigInt(Math.floor(totalmem() / 2));
  let next = 0;
  let head = 0;
  let admitted = 0;
  let reading = 0;
  let inFlight = 0n;
  let events = '';
  let failure = null;
  let waiters = [];
  const wake = () => {
    const w = waiters;
    waiters = [];
    for (const f of w) f();
  };
  const changed = () => new Promise((resolve) => waiters.push(resolve));
  const workers = [];
  const lane = async (k) => {
    for (;;) {
      const i = next++;
      if (i >= n) return;
      const input = inputs[i];
      const estimate = peakEstimate(input, budget, a.shells ? 48n : 8n);
      while (!failure && !(i < head + window && admitted === i &&
        (reading === 0 || (inFlight <= budget && estimate <= budget - inFlight)))) await changed();
      if (failure) return;
      if (a.jobsLog) events += `jobs-log: start ${i} ${estimate} ${reading} ${inFlight}\n`;
      ++admitted;
      ++reading;
      inFlight = estimate > U64_MAX - inFlight ? U64_MAX : inFlight + estimate;
      wake(); // input i + 1 may start now
      const onMain = input.path === '-' && !input.err;
      const r = onMain ? await reportOne(input, a) : await workers[k].run(input);
      if (!onMain && estimate > RECYCLE_ESTIMATE) {
        const old = workers[k];
        workers[k] = startWorker(a);
        await old.terminate();
      }
      slots[i % window] = r;
      --reading;
      inFlight = reading === 0 ? 0n : inFlight - (estimate < inFlight ? estimate : inFlight);
      if (a.jobsLog) events += `jobs-log: end ${i}\n`;
      wake();
    }
  };
  try {
    for (let k = 0; k < jobs; ++k) {
      workers.push(startWorker(a));
      lane(k).catch((e) => {
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
  if (a.jobsLog) process.stderr.write(events);
  return rc;
}

if (!isMainThread && workerData && workerData.stltopoCorpus) {
  const { a } = workerData;
  parentPort.on('message', async (input) => {
    try {
      const r = await reportOne(input, a);
      // A report in pieces (Uint8Arrays) moves without a copy.
      const pieces = Array.isArray(r.text) ? r.text.map((p) => p.buffer) : [];
      parentPort.postMessage({ ok: r.ok, text: r.text }, pieces);
    } catch (e) {
      parentPort.postMessage({ error: String((e && e.stack) || e) });
    }
  });
}
