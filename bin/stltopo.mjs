#!/usr/bin/env node
// npm CLI: `npx stltopo info [--json] [--jobs N] [--list LIST] FILE|DIR...`, `convert IN OUT` and `split IN OUTDIR` on the wasm build.
// Mirrors the native CLI (tools/cli.cpp): the same usage text, options, exit codes
// (0 all read, 1 a file failed, 2 usage), the same text report, and with --json
// byte-identical JSON (both come from stltopo::infoJson / errorJson).
import { mkdir, open, rename, stat, unlink } from 'node:fs/promises';
import path from 'node:path';
import { api, fileSource } from '../dist/instance.node.js';
import { DEFAULTS, REPAIR_DEFAULTS, REPAIR_STEPS, normalizeOptions } from '../dist/options.js';
import { cliCalls } from './cli-wasm.mjs';
import { expand, readList, reportAll, stdinSource, strerror } from './cli-corpus.mjs';

const _internal = api.internal;
const wasm = cliCalls(_internal);

const USAGE =
  "usage: stltopo info [--json] [--shells] [--defects] [--max-defects N] [--intersections] [--max-pairs N]\n" +
  "                    [--no-topology] [--tolerance D] [--max-triangles N] [--max-bytes N] [--threads N]\n" +
  "                    [--jobs N] [--max-memory N] [--list LIST]... FILE|DIR...\n" +
  "  Reads STL files (binary or ASCII; '-' reads standard input in chunks) and reports\n" +
  "  their mesh and topology. --json prints one JSON object per file, one per line.\n" +
  "  A DIR is searched recursively for *.stl files (any case), sorted bytewise by path\n" +
  "  (links to directories are not followed); --list LIST reads FILE and DIR arguments\n" +
  "  from LIST, one per line ('-': standard input). Files are reported in the order\n" +
  "  given, DIRs and LISTs expanded in place; a failed file never stops the others.\n" +
  "  --jobs N reads N files at a time (1 to 256, default 1); the output is the same.\n" +
  "  Files start in order, each only while the files being read fit in --max-memory N\n" +
  "  bytes (default: half the machine's memory), a file counted at 8 times its size (48\n" +
  "  with --shells); a larger one, or one of unknown size ('-', a pipe), is read alone.\n" +
  "  --shells adds a report per shell, --defects every defect with its location (the\n" +
  "  first N of each kind, default 1000; the text report always lists the first 5).\n" +
  "  --intersections finds every self-intersecting pair (exact), how shells nest and\n" +
  "  whether the mesh is solid; --max-pairs N is its work limit (default 4000000).\n" +
  "  --threads N uses N threads per file (0, the default: the machine's cores; the npm\n" +
  "  CLI's default is 1, and N > 1 runs its threaded wasm module); the output is the same.\n" +
  "  Exit status: 0 when every file was read, 1 when a file failed, 2 on usage errors.\n" +
  "usage: stltopo convert IN OUT [--ascii|--binary] [--colors viscam|magics|none] [--name NAME]\n" +
  "  Writes IN as STL to OUT ('-': standard input/output), in IN's format unless told.\n" +
  "  OUT appears only when complete. A failure prints the error JSON on stderr (exit 1).\n" +
  "usage: stltopo split IN OUTDIR [--ascii|--binary]\n" +
  "  Writes each shell of IN to OUTDIR/<stem>-shell-<k>.stl (OUTDIR is created when\n" +
  "  missing), in IN's format unless told, and prints a JSON line per file with its shell\n" +
  "  report. A failure prints the error JSON on stderr (exit 1).\n" +
  "usage: stltopo repair IN OUT [--plan] [--steps a,b,...] [--stitch-tolerance D] [--max-hole-edges N]\n" +
  "                      [--max-hole-area A] [--max-hole-perimeter P] [--fill refine,fair|none]\n" +
  "                      [--min-shell-triangles N] [--min-shell-volume V] [--remove-walls]\n" +
  "                      [--exclude step:item,...] [--no-intersections] [--max-pairs N] [--threads N]\n" +
  "                      [--ascii|--binary]\n" +
  "  Plans the chosen repair steps (default duplicates,zero-area,stitch,orient,fill-holes; also\n" +
  "  split-nonmanifold, small-shells) and prints the plan as JSON (--plan: nothing is written),\n" +
  "  or carries it out, writes OUT and prints the change log as JSON. OUT appears only when\n" +
  "  complete. Exit status: 0 when the result is watertight, manifold and solid, 3 when it\n" +
  "  is not (the JSON says which), 1 on failure (error JSON on stderr), 2 on usage errors.\n";

// Writes text (a string, bytes, or an array of them, in order: a report in pieces).
async function write(stream, text) {
  for (const piece of Array.isArray(text) ? text : [text]) {
    await new Promise((resolve) => {
      if (stream.write(piece)) resolve();
      else stream.once('drain', resolve);
    });
  }
}

function usageError(message) {
  process.stderr.write(message);
  process.exitCode = 2;
}

async function main(argv) {
  if (argv.length < 1) return usageError(USAGE);
  const cmd = argv[0];
  if (cmd === '--help' || cmd === '-h' || cmd === 'help') return write(process.stdout, USAGE);
  if (cmd === '--version') return write(process.stdout, 'stltopo 0.1.0\n');
  if (cmd === 'convert') return convert(argv);
  if (cmd === 'split') return split(argv);
  if (cmd === 'repair') return repair(argv);
  if (cmd !== 'info') return usageError(`stltopo: unknown command '${cmd}'\n${USAGE}`);

  const a = {
    json: false, topology: DEFAULTS.topology, tolerance: DEFAULTS.tolerance, maxTriangles: DEFAULTS.maxTriangles,
    maxBytes: DEFAULTS.maxBytes, shells: false, defects: false, maxDefects: -1, intersections: false,
    maxPairs: DEFAULTS.maxPairs, jobs: 1, maxMemory: 0n, jobsLog: false, threads: 1, inputs: [],
  };
  let endOfOptions = false;
  for (let i = 1; i < argv.length; ++i) {
    const s = argv[i];
    const value = (name) => {
      if (i + 1 >= argv.length) {
        usageError(`stltopo: ${name} needs a value\n`);
        return null;
      }
      return argv[++i];
    };
    if (!endOfOptions && s === '--') endOfOptions = true;
    else if (!endOfOptions && s === '--json') a.json = true;
    else if (!endOfOptions && s === '--no-topology') a.topology = false;
    else if (!endOfOptions && s === '--shells') a.shells = true;
    else if (!endOfOptions && s === '--defects') a.defects = true;
    else if (!endOfOptions && s === '--intersections') a.intersections = true;
    else if (!endOfOptions && s === '--max-pairs') {
      const v = value('--max-pairs');
      if (v === null) return;
      const n = parseCUnsigned(v);
      if (v === '' || v[0] === '-' || n === null || n === 0n || n > 2n ** 40n) return usageError(`stltopo: bad --max-pairs '${v}'\n`);
      a.maxPairs = Number(n);
    }
    else if (!endOfOptions && s === '--max-defects') {
      const v = value('--max-defects');
      if (v === null) return;
      const n = parseCUnsigned(v);
      if (v === '' || v[0] === '-' || n === null || n > 0xffffffffn) return usageError(`stltopo: bad --max-defects '${v}'\n`);
      a.maxDefects = Number(n);
    }
    else if (!endOfOptions && s === '--tolerance') {
      const v = value('--tolerance');
      if (v === null) return;
      const t = parseCDouble(v);
      if (t === null || !(t >= 0)) return usageError(`stltopo: bad --tolerance '${v}'\n`);
      a.tolerance = t;
    } else if (!endOfOptions && s === '--max-triangles') {
      const v = value('--max-triangles');
      if (v === null) return;
      const n = parseCUnsigned(v);
      if (n === null || n === 0n || n > 0xffffffffn) return usageError(`stltopo: bad --max-triangles '${v}'\n`);
      a.maxTriangles = Number(n);
    } else if (!endOfOptions && s === '--max-bytes') {
      const v = value('--max-bytes');
      if (v === null) return;
      const n = parseCUnsigned(v);
      if (n === null || n === 0n) return usageError(`stltopo: bad --max-bytes '${v}'\n`);
      a.maxBytes = Number(n);
    } else if (!endOfOptions && s === '--jobs') {
      const v = value('--jobs');
      if (v === null) return;
      const n = parseCUnsigned(v);
      if (v === '' || v[0] === '-' || n === null || n === 0n || n > 256n) return usageError(`stltopo: bad --jobs '${v}' (1 to 256)\n`);
      a.jobs = Number(n);
    } else if (!endOfOptions && s === '--max-memory') {
      const v = value('--max-memory');
      if (v === null) return;
      const n = parseCUnsigned(v);
      if (v === '' || v[0] === '-' || n === null || n === 0n) return usageError(`stltopo: bad --max-memory '${v}'\n`);
      a.maxMemory = n;
    } else if (!endOfOptions && s === '--test-jobs-log') { // not in the usage: the tests' view of the gate
      a.jobsLog = true;
    } else if (!endOfOptions && s === '--list') {
      const v = value('--list');
      if (v === null) return;
      a.inputs.push({ path: v, list: true });
    } else if (!endOfOptions && s === '--threads') {
      // Checked as the native CLI checks it; N > 1 loads through the threaded wasm module.
      const v = value('--threads');
      if (v === null) return;
      const n = parseCUnsigned(v);
      if (v === '' || v[0] === '-' || n === null || n > 1024n) return usageError(`stltopo: bad --threads '${v}'\n`);
      a.threads = Number(n);
    } else if (!endOfOptions && s.length > 1 && s[0] === '-') {
      return usageError(`stltopo: unknown option '${s}'\n${USAGE}`);
    } else {
      a.inputs.push({ path: s, list: false });
    }
  }
  if (a.inputs.length === 0) return usageError(`stltopo: no input files\n${USAGE}`);
  if (!a.topology && (a.shells || a.defects || a.intersections)) {
    return usageError('stltopo: --shells, --defects and --intersections need the topology (not --no-topology)\n');
  }

  // Standard input is read once: by one --list, or as one file, not both.
  const stdinLists = a.inputs.filter((x) => x.list && x.path === '-').length;
  if (stdinLists > 0 && (stdinLists > 1 || a.inputs.some((x) => !x.list && x.path === '-'))) {
    return usageError("stltopo: '--list -' reads standard input: no other input can\n");
  }
  const inputs = [];
  for (const x of a.inputs) {
    if (!x.list) {
      expand(x.path, inputs);
      continue;
    }
    const error = await readList(x.path, inputs);
    if (error) return usageError(error);
  }
  // '-' more than once: each reads what the one before left, so in order, on one thread.
  const jobs = inputs.filter((x) => x.path === '-').length > 1 ? 1 : a.jobs;
  process.exitCode = await reportAll(inputs, a, jobs,
    (r) => write(r.ok || a.json ? process.stdout : process.stderr, r.text));
}

// `stltopo convert`, as tools/cli.cpp: the same options, messages, exit codes and bytes
// (the same writer); OUT through a temporary file in its folder, renamed when complete.
// The arguments of convert and split (tools/cli.cpp writeArgs): { files, w }, or null after a
// usage error; split takes only --ascii/--binary (colorsAndName false).
function writeArgs(argv, colorsAndName) {
  const files = [];
  const w = {};
  for (let i = 1; i < argv.length; ++i) {
    const s = argv[i];
    if (s === '--') {
      files.push(...argv.slice(i + 1));
      break;
    }
    if (s.length < 2 || s[0] !== '-') {
      files.push(s);
      continue;
    }
    const takesValue = colorsAndName && (s === '--colors' || s === '--name');
    if (takesValue && i + 1 >= argv.length) return usageError(`stltopo: ${s} needs a value\n`), null;
    const v = takesValue ? argv[++i] : '';
    if (s === '--ascii' || s === '--binary') w.format = s.slice(2);
    else if (takesValue && s === '--name') w.name = v;
    else if (takesValue && ['viscam', 'magics', 'none'].includes(v)) w.colors = v;
    else if (takesValue) return usageError(`stltopo: bad --colors '${v}' (viscam, magics or none)\n`), null;
    else return usageError(`stltopo: unknown option '${s}'\n${USAGE}`), null;
  }
  return { files, w };
}

// A file that failed in convert or split: its error JSON on stderr, exit status 1.
// err: an StlError (its location goes into the JSON too) or { code, message }.
async function fail(file, code, message, err = { code, message }) {
  await write(process.stderr, `${await _internal.errorJson(file, err)}\n`);
  process.exitCode = 1;
}

// The input of convert and split: standard input for '-', else the file; null (after
// reporting it) when the file cannot be opened.
async function openInput(input) {
  try {
    return input === '-' ? stdinSource() : await fileSource(input);
  } catch (e) {
    await fail(input, 'invalid-argument', `invalid-argument: cannot open ${input}: ${strerror(e)}`);
    return null;
  }
}

async function convert(argv) {
  const args = writeArgs(argv, true);
  if (!args) return;
  const { files, w } = args;
  if (files.length !== 2) return usageError(`stltopo: convert needs IN and OUT\n${USAGE}`);
  const [input, output] = files;
  const source = await openInput(input);
  if (!source) return;
  const out = outputFile(output, fail);
  try {
    for await (const chunk of wasm.convert(source, w)) {
      if (!(await out.write(chunk))) return;
    }
    await out.finish();
  } catch (e) {
    if (!e || !e.code || String(e.code).startsWith('E')) throw e;
    return await fail(input, e.code, e.message, e);
  } finally {
    await out.abort();
  }
}

// An output file as tools/cli.cpp's Output: standard output for '-', else a temporary file
// next to `output`, renamed over it by finish() once complete and removed by abort()
// otherwise. write() and finish() report a failure through fail(file, code, message) and
// give false.
function outputFile(output, fail) {
  let out = null;
  let temp = null;
  let offset = 0;
  return {
    async write(chunk) {
      if (!out) {
        if (output === '-') {
          out = { write: (c) => write(process.stdout, c), close: async () => {} };
        } else {
          const { randomBytes } = await import('node:crypto'); // here: info, the common call, never writes
          temp = path.join(path.dirname(output), `.${path.basename(output)}.tmp-${randomBytes(4).toString('hex').slice(0, 6)}`);
          try {
            out = await open(temp, 'wx', 0o666);
          } catch (e) {
            temp = null;
            await fail(output, 'write-failed', `write-failed: cannot create a file next to ${output}: ${strerror(e)}`);
            return false;
          }
        }
      }
      try {
        await out.write(chunk);
      } catch {
        await fail(output, 'write-failed', `write-failed: the output refused the ${chunk.length} bytes at offset ${offset}`);
        return false;
      }
      offset += chunk.length;
      return true;
    },
    async finish() {
      if (!temp) return true;
      try {
        await out.sync();
        await out.close();
        out = null;
        await rename(temp, output);
        temp = null;
        return true;
      } catch (e) {
        await fail(output, 'write-failed', `write-failed: cannot write ${output}: ${strerror(e)}`);
        return false;
      }
    },
    async abort() {
      if (!temp) return;
      if (out) await out.close().catch(() => {});
      await unlink(temp).catch(() => {});
      temp = null;
    },
  };
}

// The file of shell k (tools/cli.cpp splitPath): OUTDIR/<stem>-shell-<k>.stl, the stem
// being IN's file name without its last extension ("stdin" for '-').
function splitPath(input, dir, k) {
  let base = input === '-' ? 'stdin' : input.slice(input.lastIndexOf('/') + 1);
  const dot = base.lastIndexOf('.');
  if (input !== '-' && dot > 0) base = base.slice(0, dot);
  while (dir.length > 1 && dir.endsWith('/')) dir = dir.slice(0, -1);
  return `${dir === '/' ? dir : `${dir}/`}${base}-shell-${k}.stl`;
}

// `stltopo split`, as tools/cli.cpp: one STL per shell, a JSON line per file.
async function split(argv) {
  const args = writeArgs(argv, false);
  if (!args) return;
  const { files, w } = args;
  if (files.length !== 2) return usageError(`stltopo: split needs IN and OUTDIR\n${USAGE}`);
  const [input, dir] = files;
  const source = await openInput(input);
  if (!source) return;
  let out = null;
  let file = null;
  let line = null;
  try {
    for await (const item of wasm.split(source, w)) {
      if (item.shells !== undefined) { // the input is read: OUTDIR next
        try {
          await mkdir(dir);
        } catch (e) {
          if (e.code !== 'EEXIST' || !(await stat(dir)).isDirectory()) {
            return await fail(dir, 'write-failed', `write-failed: cannot create the folder ${dir}: ${strerror(e)}`);
          }
        }
        continue;
      }
      if (!ArrayBuffer.isView(item)) {
        if (out && !(await out.finish())) return;
        if (line) await write(process.stdout, `${line}\n`);
        file = splitPath(input, dir, item.k);
        line = item.line(file);
        out = outputFile(file, fail);
        continue;
      }
      if (!(await out.write(item))) return;
    }
    if (out && !(await out.finish())) return;
    if (line) await write(process.stdout, `${line}\n`);
  } catch (e) {
    if (!e || !e.code || String(e.code).startsWith('E')) throw e;
    return await fail(out ? file : input, e.code, e.message, e);
  } finally {
    if (out) await out.abort();
  }
}

// `stltopo repair`, as tools/cli.cpp: the same options, messages, JSON and exit codes.
async function repair(argv) {
  const files = [];
  const o = { steps: [...REPAIR_DEFAULTS.steps], fill: [], exclude: [] };
  const w = {};
  let planOnly = false;
  const usage = (m) => usageError(`stltopo: ${m}\n${USAGE}`);
  // strtod, then the native numberArg() checks: finite, >= 0, <= max, whole when asked.
  const number = (v, integer, max) => {
    const d = parseCDouble(v);
    return v !== '' && d !== null && d >= 0 && d <= max && (!integer || Number.isInteger(d)) ? d : null;
  };
  const takes = ['--steps', '--stitch-tolerance', '--max-hole-edges', '--max-hole-area', '--max-hole-perimeter', '--fill',
    '--min-shell-triangles', '--min-shell-volume', '--exclude', '--max-pairs', '--threads'];
  for (let i = 1; i < argv.length; ++i) {
    const s = argv[i];
    if (s === '--') {
      files.push(...argv.slice(i + 1));
      break;
    }
    if (s.length < 2 || s[0] !== '-') {
      files.push(s);
      continue;
    }
    if (s === '--plan') { planOnly = true; continue; }
    if (s === '--remove-walls') { o.removeWalls = true; continue; }
    if (s === '--no-intersections') { o.intersections = false; continue; }
    if (s === '--ascii' || s === '--binary') { w.format = s.slice(2); continue; }
    if (!takes.includes(s)) return usage(`unknown option '${s}'`);
    if (i + 1 >= argv.length) return usage(`${s} needs a value`);
    const v = argv[++i];
    if (s === '--threads') {
      // Checked as the native CLI checks it. The repair runs in the full module's
      // EditableMesh, on one thread: the output is the same for every count.
      const n = parseCUnsigned(v);
      if (v === '' || v[0] === '-' || n === null || n > 1024n) return usageError(`stltopo: bad --threads '${v}'\n`);
    } else if (s === '--steps') {
      o.steps = [];
      for (const n of v.split(',')) {
        if (!REPAIR_STEPS.includes(n)) return usage(`unknown repair step '${n}'`);
        o.steps.push(n);
      }
    } else if (s === '--fill') {
      o.fill = [];
      for (const n of v.split(',')) {
        if (n === 'refine' || n === 'fair') o.fill.push(n);
        else if (n !== 'none') return usage(`bad --fill '${n}' (refine, fair or none)`);
      }
    } else if (s === '--exclude') {
      for (const n of v.split(',')) {
        const colon = n.lastIndexOf(':');
        const item = colon < 0 ? null : number(n.slice(colon + 1), true, 4294967295);
        if (colon < 0 || !REPAIR_STEPS.includes(n.slice(0, colon)) || item === null) {
          return usage(`bad --exclude '${n}' (step:item, e.g. fill-holes:2)`);
        }
        o.exclude.push({ step: n.slice(0, colon), item });
      }
    } else if (s === '--max-hole-edges' || s === '--min-shell-triangles') {
      const d = number(v, true, 4294967295);
      if (d === null) return usage(`bad ${s} '${v}' (a whole number)`);
      o[s === '--max-hole-edges' ? 'maxHoleEdges' : 'minShellTriangles'] = d;
    } else if (s === '--max-pairs') {
      const d = number(v, true, 2 ** 40);
      if (d === null || d < 1) return usage(`bad --max-pairs '${v}' (1 to 2^40)`);
      o.maxPairs = d;
    } else {
      const d = number(v, false, 1e300);
      if (d === null) return usage(`bad ${s} '${v}' (a number >= 0)`);
      o[{ '--stitch-tolerance': 'stitchTolerance', '--max-hole-area': 'maxHoleArea', '--max-hole-perimeter': 'maxHolePerimeter',
        '--min-shell-volume': 'minShellVolume' }[s]] = d;
    }
  }
  if (files.length !== 2 && !(planOnly && files.length === 1)) return usage(planOnly ? 'repair --plan needs IN' : 'repair needs IN and OUT');
  const [input, output] = files;
  const source = await openInput(input);
  if (!source) return;
  let em = null;
  try {
    // The editor's modules only for repair (info, the common call, starts without them).
    const [{ EditableMesh }, { RAW_JSON }] = await Promise.all([import('../dist/node.js'), import('../dist/edit.js')]);
    const mesh = await api.loadFromSource(source, normalizeOptions({ topology: false }));
    em = await EditableMesh.from(mesh);
    const plan = em.planRepair(o);
    // {"file":..., ("out":...,) then the plan's or log's keys: the file name as the native
    // CLI's jsonString() writes it (taken from the error JSON, which starts with it).
    const quoted = async (f) => {
      const e = await _internal.errorJson(f, { code: 'invalid-argument', message: '' });
      return e.slice('{"file":'.length, e.indexOf(',"error":'));
    };
    const head = `{"file":${await quoted(input)}` + (planOnly ? '' : `,"out":${await quoted(output)}`);
    const line = (json) => `${head}${json.length > 2 ? `,${json.slice(1)}` : '}'}\n`;
    const verdict = (f) => (f.watertight && f.manifold && f.solid === true ? 0 : 3);
    if (planOnly) {
      await write(process.stdout, line(plan[RAW_JSON]));
      process.exitCode = verdict(plan.after);
      return;
    }
    const log = em.applyRepair(plan);
    const bytes = em.toStl({ format: w.format || (mesh.format === 'ascii' ? 'ascii' : 'binary') });
    const out = outputFile(output, fail);
    try {
      if (!(await out.write(bytes)) || !(await out.finish())) return;
    } finally {
      await out.abort();
    }
    await write(process.stdout, line(log[RAW_JSON]));
    process.exitCode = verdict(log.after);
  } catch (e) {
    if (!e || !e.code || String(e.code).startsWith('E')) throw e;
    return await fail(input, e.code, e.message, e);
  } finally {
    if (em) em.dispose();
  }
}

// strtoull(3) base 10 on the whole string: leading space, a sign (a minus
// negates modulo 2^64), digits; out of range gives ULLONG_MAX. null when
// characters are left over (or there are no digits and the string is not empty).
function parseCUnsigned(v) {
  const m = /^[ \t\n\v\f\r]*([+-]?)([0-9]+)$/.exec(v);
  if (!m) return v === '' ? 0n : null;
  const max = (1n << 64n) - 1n;
  let n = BigInt(m[2]);
  if (n > max) return max;
  if (m[1] === '-') n = (-n) & max;
  return n;
}

// strtod(3) in the C locale, whole string: decimal and hex floats, inf, nan.
function parseCDouble(v) {
  const s = v.replace(/^[ \t\n\v\f\r]+/, '');
  if (/^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$/.test(s)) return Number(s);
  if (/^[+-]?(inf|infinity)$/i.test(s)) return s[0] === '-' ? -Infinity : Infinity;
  if (/^[+-]?nan(\([0-9A-Za-z_]*\))?$/i.test(s)) return NaN;
  const hex = /^([+-]?)0[xX]([0-9a-fA-F]*)\.?([0-9a-fA-F]*)(?:[pP]([+-]?\d+))?$/.exec(s);
  if (hex && (hex[2] || hex[3])) {
    const digits = hex[2] + hex[3];
    let x = 0;
    for (const d of digits) x = x * 16 + parseInt(d, 16);
    x *= 2 ** (Number(hex[4] || 0) - 4 * hex[3].length);
    return hex[1] === '-' ? -x : x;
  }
  return null;
}

main(process.argv.slice(2)).catch((e) => {
  process.stderr.write(`stltopo: ${e && e.stack ? e.stack : e}\n`);
  process.exitCode = 1;
});
