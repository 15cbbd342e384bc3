// The npm CLI (bin/stltopo.mjs, wasm) prints byte-identical output to the
// native CLI (build/stltopo): JSON on every fixture, the text report, errors,
// usage and exit codes.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import { closeSync, constants, mkdirSync, mkdtempSync, openSync, readFileSync, readdirSync, rmSync, symlinkSync, writeFileSync } from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { damagedTorus, fixtures, fixture, indexedStl, nativeCli, haveNativeCli, pool, root, runAsync, shuffleTriangles, soupStl } from './helpers.mjs';

const npmCli = path.join(root, 'bin/stltopo.mjs');
const files = fixtures().map((f) => path.relative(root, f));
const skip = !haveNativeCli && `no native CLI at ${nativeCli}`;

function run(cmd, args, input) {
  const r = spawnSync(cmd, args, { cwd: root, input, maxBuffer: 1 << 28 });
  return { status: r.status, stdout: r.stdout, stderr: r.stderr };
}
const native = (args, input) => run(nativeCli, args, input);
const wasm = (args, input) => run(process.execPath, [npmCli, ...args], input);

function assertSameRun(args, input) {
  const a = native(args, input);
  const b = wasm(args, input);
  assertSame(args, a, b);
  return a;
}

function assertSame(args, a, b) {
  assert.equal(b.status, a.status, `exit code of ${args.join(' ')}`);
  assert.ok(b.stdout.equals(a.stdout), `stdout of ${args.join(' ')}:\n${firstDiff(a.stdout, b.stdout)}`);
  assert.ok(b.stderr.equals(a.stderr), `stderr of ${args.join(' ')}:\n${firstDiff(a.stderr, b.stderr)}`);
}

function firstDiff(a, b) {
  const x = a.toString('latin1').split('\n');
  const y = b.toString('latin1').split('\n');
  for (let i = 0; i < Math.max(x.length, y.length); ++i) {
    if (x[i] !== y[i]) return `line ${i + 1}\nnative: ${x[i]}\nnpm:    ${y[i]}`;
  }
  return '(same lines)';
}

test('--json: byte-identical, one file per run (every failing fixture, one in three of the rest)', { skip }, async () => {
  // A few files at a time: a native CLI process for each, and an npm CLI process (about 210 ms
  // to start) for each file the native CLI fails on and for one in three of the others; the
  // next test compares every fixture's bytes in one run of each CLI.
  let compared = 0;
  const status = await pool(files, async (f, i) => {
    const args = ['info', '--json', f];
    const a = await runAsync(nativeCli, args, undefined, { cwd: root });
    assert.equal(a.stdout.toString().split('\n').length, 2, f);
    if (a.status !== 0 || i % 3 === 0) {
      ++compared;
      assertSame(args, a, await runAsync(process.execPath, [npmCli, ...args], undefined, { cwd: root }));
    }
    return a.status;
  });
  const failures = status.filter((x) => x === 1).length;
  assert.ok(failures > 0 && failures < files.length);
  assert.ok(compared >= failures + 20, `${compared} compared`);
});

test('--json and text, all fixtures in one run, with missing files', { skip }, () => {
  const all = [...files, 'no/such/file.stl', 'tests/fixtures/SOURCES.md'];
  const a = assertSameRun(['info', '--json', ...all]);
  assert.equal(a.status, 1);
  assert.equal(a.stdout.toString().trimEnd().split('\n').length, all.length);
  assertSameRun(['info', ...all]);
  assertSameRun(['info', '--no-topology', '--json', ...files]);
  assertSameRun(['info', '--tolerance', '0.001', ...files.slice(0, 20)]);
  assertSameRun(['info', '--max-triangles', '1000', '--json', ...files]);
  assertSameRun(['info', '--max-bytes', '100000', '--json', ...files]);
  assertSameRun(['info', '--max-bytes', '-1', '--max-triangles', ' +70000', '--json', ...files.slice(0, 10)]);
});

test('--shells --defects [--max-defects N]: byte-identical on every fixture, JSON and text', { skip }, () => {
  const all = [...files, 'no/such/file.stl'];
  const a = assertSameRun(['info', '--json', '--shells', '--defects', ...all]);
  assert.equal(a.stdout.toString().trimEnd().split('\n').length, all.length);
  assert.match(a.stdout.toString(), /"shellList":\[\{"id":0,/);
  assertSameRun(['info', '--json', '--defects', '--max-defects', '2', ...files]);
  assertSameRun(['info', '--json', '--shells', '--max-defects', '0', ...files]);
  assertSameRun(['info', '--shells', '--defects', '--max-defects', '3', ...files]);
  assertSameRun(['info', '--json', '--shells', '--defects', '--tolerance', '0.001', ...files.slice(0, 30)]);
  // Plain text lists the first defects too.
  const text = assertSameRun(['info', ...files]).stdout.toString();
  assert.match(text, /\n  non-manifold edge \d+-\d+: \[/);
  assert.match(text, /\n  hole \d+: \d+ edges, perimeter /);
});

test('--intersections [--max-pairs N]: byte-identical on every fixture and case (wasm = native)', { skip }, () => {
  const cases = readdirSync(path.join(root, 'tests/judge/cases')).filter((f) => f.endsWith('.stl'))
    .map((f) => path.join('tests/judge/cases', f));
  const all = [...files, ...cases, 'no/such/file.stl'];
  const a = assertSameRun(['info', '--json', '--intersections', '--shells', '--defects', ...all]);
  assert.match(a.stdout.toString(), /"selfIntersections":\{"count":[1-9]/);
  assert.match(a.stdout.toString(), /"kind":"coplanar","point":\[/);
  assertSameRun(['info', '--json', '--intersections', '--max-pairs', '5', ...all]);
  assertSameRun(['info', '--intersections', '--defects', '--max-defects', '3', ...cases]);
  assertSameRun(['info', '--json', '--intersections', '--tolerance', '0.001', ...files.slice(0, 20)]);
  for (const bad of [['--max-pairs', '0'], ['--max-pairs', '-3'], ['--max-pairs', 'x'], ['--no-topology', '--intersections']]) {
    assert.equal(assertSameRun(['info', '--json', ...bad, cases[0]]).status, 2);
  }
});

// The full module runs the loops that go once over the mesh in chunks of 16,384 items (the
// topology, the checks, the shells, the hierarchy: src/parallel.h, forChunks), the native CLI in
// one call: damaged tori of about 60,000 triangles (4 chunks), in file order and shuffled with
// their corners rotated, give the same bytes.
test('--intersections --shells --defects: byte-identical on meshes of several chunks', { skip }, () => {
  const dir = mkdtempSync(path.join(os.tmpdir(), 'stltopo-chunks-'));
  try {
    const { positions, triangles } = damagedTorus(200, 150, 9);
    const nt = triangles.length / 3;
    assert.ok(nt > 3 * 16384, `${nt} triangles`);
    const a = path.join(dir, 'torus.stl'), b = path.join(dir, 'shuffled.stl');
    writeFileSync(a, indexedStl(positions, triangles));
    writeFileSync(b, indexedStl(positions, shuffleTriangles(triangles, 13)));
    const out = assertSameRun(['info', '--json', '--intersections', '--shells', '--defects', a, b]);
    assert.match(out.stdout.toString(), /"duplicateTriangles":\{"count":[1-9]/);
    assertSameRun(['info', '--json', '--shells', '--tolerance', '0.001', a, b]);
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
});

test('--shells --defects of a soup: a report of many pieces, JSON and text, byte-identical, one job or two', { skip }, () => {
  // 30,000 shells and holes: some 20 MB of JSON, which both CLIs now write in pieces of 1 MiB
  // (native: straight to standard output with one job; npm: Uint8Arrays out of wasm, moved
  // from the worker with two). As one string the npm CLI's report stopped at V8's string
  // limit (a soup of 1.4M triangles), with a wrong "invalid-argument: read error".
  const dir = mkdtempSync(path.join(os.tmpdir(), 'stltopo-soup-'));
  try {
    const a = path.join(dir, 'soup.stl'), b = path.join(dir, 'soup2.stl');
    writeFileSync(a, soupStl(30000));
    writeFileSync(b, soupStl(29999));
    const args = ['info', '--json', '--shells', '--defects', '--max-defects', '100000'];
    const one = assertSameRun([...args, a, b]);
    assert.ok(one.stdout.length > 20 << 20, `${one.stdout.length} bytes`);
    const [ra, rb] = one.stdout.toString().trimEnd().split('\n').map((l) => JSON.parse(l));
    assert.equal(ra.shellList.length, 30000);
    assert.equal(rb.defects.holes.items.length, 29999);
    const two = assertSameRun([...args, '--jobs', '2', a, b]);
    assert.ok(two.stdout.equals(one.stdout), 'the same bytes with --jobs 2');
    // The text report, a line a shell (3.8 MB each), in pieces too.
    const text = assertSameRun(['info', '--shells', a, b]);
    assert.ok(text.stdout.length > 6 << 20, `${text.stdout.length} bytes of text`);
    assert.ok(assertSameRun(['info', '--shells', '--jobs', '2', a, b]).stdout.equals(text.stdout), 'text, --jobs 2');
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
});

test('all good files: exit code 0', { skip }, () => {
  const a = assertSameRun(['info', '--json', path.relative(root, fixture('bunny.stl')), path.relative(root, fixture('busted.STL'))]);
  assert.equal(a.status, 0);
});

test("'-' reads standard input", { skip }, () => {
  const bytes = readFileSync(fixture('bunny.stl'));
  assertSameRun(['info', '--json', '-'], bytes);
  assertSameRun(['info', '-'], bytes);
  assertSameRun(['info', '--json', '-'], Buffer.alloc(0));
});

test('usage errors and help: exit code 2 / 0, same messages', { skip }, () => {
  for (const args of [[], ['frobnicate'], ['info'], ['info', '--bogus'], ['info', '--tolerance'], ['info', '--tolerance', 'x', 'f'],
    ['info', '--tolerance', '-1', 'f'], ['info', '--max-triangles', '0', 'f'], ['info', '--max-triangles', '5000000000', 'f'],
    ['info', '--max-triangles', '12x', 'f'], ['info', '--max-bytes', '0', 'f'], ['info', '--max-bytes'], ['info', '--max-bytes', 'x', 'f'],
    ['--help'], ['help'], ['--version'], ['info', '--', '--json'], ['info', '--shells', '--no-topology', 'f'],
    ['info', '--defects', '--no-topology', 'f'], ['info', '--max-defects'], ['info', '--max-defects', '-1', 'f'],
    ['info', '--max-defects', ' -0', 'f'], ['info', '--max-defects', '', 'f'], ['info', '--max-defects', '4294967296', 'f'],
    ['info', '--max-defects', 'x', 'f']]) {
    assertSameRun(args);
  }
  assert.equal(wasm([]).status, 2);
  assert.equal(wasm(['--help']).status, 0);
});

// The log of the hidden --test-jobs-log keeps the memory gate's rules: files start in order,
// each beside others only while the estimates fit the budget, at most `jobs` at once.
function assertGate(log, budget, jobs, n) {
  const starts = log.toString().split('\n').filter((l) => l.startsWith('jobs-log: start '))
    .map((l) => l.split(' ').slice(2).map(BigInt));
  assert.equal(starts.length, n, 'a start for every file');
  starts.forEach(([i, estimate, reading, inFlight], k) => {
    assert.equal(i, BigInt(k), 'in input order');
    assert.ok(reading === 0n || inFlight + estimate <= BigInt(budget), `file ${i} over the budget ${budget}`);
    assert.ok(reading < BigInt(jobs), `file ${i}: more than ${jobs} at once`);
  });
  return starts;
}

test('corpus: the memory gate of --jobs N (--max-memory), and FIFOs read alone, in both CLIs', { skip }, async (t) => {
  const tmp = mkdtempSync(path.join(os.tmpdir(), 'stltopo-gate-'));
  t.after(() => rmSync(tmp, { recursive: true, force: true }));
  const serial = native(['info', '--json', 'tests/fixtures']);
  const n = serial.stdout.toString().trimEnd().split('\n').length;
  for (const [cli, budget] of [[native, '30000000'], [wasm, '30000000'], [wasm, '1']]) {
    const r = cli(['info', '--json', '--jobs', '3', '--max-memory', budget, '--test-jobs-log', 'tests/fixtures']);
    assert.ok(r.stdout.equals(serial.stdout), `--max-memory ${budget}`);
    const starts = assertGate(r.stderr, budget, 3, n);
    if (budget === '1') assert.ok(starts.every(([, , reading]) => reading === 0n), 'a budget of 1 byte: one at a time');
  }
  // Every worker replaced after each file (the threshold above which a worker's wasm heap
  // goes with it): the same bytes.
  const recycled = spawnSync(process.execPath, [npmCli, 'info', '--json', '--jobs', '2', 'tests/judge/cases'],
    { cwd: root, env: { ...process.env, STLTOPO_TEST_RECYCLE_BYTES: '1' } });
  assert.ok(recycled.stdout.equals(native(['info', '--json', 'tests/judge/cases']).stdout), 'workers replaced');
  // Two FIFOs on --jobs 2: a pipe has no size, so each is read alone; the second is not
  // opened while the first waits for its writer (then a non-blocking open for writing fails).
  const good = readFileSync(fixture('bunny.stl'));
  for (const [name, cmd, pre] of [['native', nativeCli, []], ['npm', process.execPath, [npmCli]]]) {
    const [fa, fb] = ['a', 'b'].map((x) => path.join(tmp, `${name}-${x}.stl`));
    assert.equal(spawnSync('mkfifo', [fa, fb]).status, 0);
    const done = runAsync(cmd, [...pre, 'info', '--json', '--jobs', '2', fa, fb], '', { cwd: root });
    await new Promise((resolve) => setTimeout(resolve, 1500));
    assert.throws(() => closeSync(openSync(fb, constants.O_WRONLY | constants.O_NONBLOCK)), { code: 'ENXIO' },
      `${name}: the second FIFO was opened while the first was read`);
    writeFileSync(fa, good);
    writeFileSync(fb, good);
    const r = await done;
    assert.equal(r.status, 0, `${name}: ${r.stderr}`);
    assert.equal(r.stdout.toString().trimEnd().split('\n').length, 2);
  }
  for (const bad of [['--max-memory', '0'], ['--max-memory', 'x'], ['--max-memory', '-1'], ['--max-memory', ''],
    ['--max-memory', '1.5'], ['--max-memory']]) {
    assert.equal(assertSameRun(['info', '--json', '--jobs', '2', ...bad, 'tests/judge/cases']).status, 2, bad.join(' '));
  }
});

test('corpus: DIRs, --list and --jobs N print the same bytes in both CLIs, failures in place', { skip }, (t) => {
  const tmp = mkdtempSync(path.join(os.tmpdir(), 'stltopo-corpus-'));
  t.after(() => rmSync(tmp, { recursive: true, force: true }));
  const stl = files.filter((f) => /\.stl$/i.test(f)).sort((x, y) => Buffer.compare(Buffer.from(x), Buffer.from(y)));
  const serial = assertSameRun(['info', '--json', 'tests/fixtures']);
  assert.equal(serial.status, 1);
  assert.equal(serial.stdout.toString().trimEnd().split('\n').length, stl.length);
  // --jobs N: the same bytes as one job, JSON and text (errors on stderr).
  for (const jobs of ['2', '3']) {
    const r = assertSameRun(['info', '--json', '--jobs', jobs, 'tests/fixtures']);
    assert.ok(r.stdout.equals(serial.stdout), `--jobs ${jobs}`);
  }
  const text = assertSameRun(['info', '--shells', 'tests/fixtures']);
  const text3 = assertSameRun(['info', '--shells', '--jobs', '3', 'tests/fixtures']);
  assert.ok(text3.stdout.equals(text.stdout) && text3.stderr.equals(text.stderr) && text.stderr.length > 0);
  const geo = ['info', '--json', '--intersections', '--defects', '--tolerance', '0.001', 'tests/judge/cases'];
  assert.ok(assertSameRun([...geo, '--jobs', '2']).stdout.equals(assertSameRun(geo).stdout), '--intersections --jobs 2');
  // The DIR = its files as arguments (sorted bytewise) = the same files in a --list.
  assert.ok(assertSameRun(['info', '--json', ...stl]).stdout.equals(serial.stdout), 'DIR vs files');
  const list = path.join(tmp, 'list.txt');
  writeFileSync(list, `\n${stl.join('\r\n')}\n\n`);
  assert.ok(assertSameRun(['info', '--json', '--jobs', '3', '--list', list]).stdout.equals(serial.stdout), 'DIR vs --list');
  assert.ok(assertSameRun(['info', '--json', '--list', '-'], readFileSync(list)).stdout.equals(serial.stdout), '--list -');
  // A missing and a broken file in the middle: reported in place, the rest still read, exit 1.
  const good = path.relative(root, fixture('bunny.stl'));
  const broken = path.join(tmp, 'broken.stl');
  writeFileSync(broken, 'solid x\nfacet normal 0 0 0\n');
  for (const jobs of ['1', '3']) {
    const r = assertSameRun(['info', '--json', '--jobs', jobs, good, 'no/such/file.stl', broken, 'tests/fixtures', good]);
    assert.equal(r.status, 1);
    const lines = r.stdout.toString().trimEnd().split('\n');
    assert.equal(lines.length, stl.length + 4);
    assert.match(lines[1], /^\{"file":"no\/such\/file\.stl","error":\{"code":"invalid-argument"/);
    assert.match(lines[2], /"error":\{"code":"/);
    assert.equal(lines[3], serial.stdout.toString().split('\n')[0]);
    assert.match(lines[lines.length - 1], /^\{"file":"[^"]*bunny\.stl","format":"binary"/);
  }
  // A DIR with a link loop, a broken link, a link to a file, upper-case extensions, a non-STL file.
  const dir = path.join(tmp, 'd');
  mkdirSync(path.join(dir, 'sub'), { recursive: true });
  writeFileSync(path.join(dir, 'sub', 'A.STL'), readFileSync(fixture('bunny.stl')));
  writeFileSync(path.join(dir, 'notes.txt'), 'not an STL file');
  symlinkSync('..', path.join(dir, 'sub', 'loop'));
  symlinkSync('nothing.stl', path.join(dir, 'gone.stl'));
  symlinkSync('sub/A.STL', path.join(dir, 'b.Stl'));
  const d = assertSameRun(['info', '--json', '--jobs', '2', dir]);
  assert.equal(d.status, 1);
  assert.deepEqual(d.stdout.toString().trimEnd().split('\n').map((l) => JSON.parse(l).file),
    ['b.Stl', 'gone.stl', 'sub/A.STL'].map((f) => `${dir}/${f}`));
  assertSameRun(['info', '--jobs', '2', `${dir}/`, '--list', list]);
  // Usage errors: exit status 2, the same messages.
  for (const bad of [['--jobs', '0'], ['--jobs', '257'], ['--jobs', 'x'], ['--jobs', ''], ['--jobs', '-1'], ['--jobs'],
    ['--list'], ['--list', path.join(tmp, 'none')], ['--list', tmp], ['--list', '-', '-'], ['--list', '-', '--list', '-']]) {
    assert.equal(assertSameRun(['info', '--json', ...bad, good]).status, 2, bad.join(' '));
  }
  writeFileSync(list, 'a\0b\n');
  assert.equal(assertSameRun(['info', '--list', list]).status, 2);
});
