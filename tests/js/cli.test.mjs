// The npm CLI (bin/stltopo.mjs, wasm) prints byte-identical output to the
// native CLI (build/stltopo): JSON on every fixture, the text report, errors,
// usage and exit codes.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import { readFileSync, readdirSync } from 'node:fs';
import path from 'node:path';
import { fixtures, fixture, nativeCli, haveNativeCli, root } from './helpers.mjs';

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
  assert.equal(b.status, a.status, `exit code of ${args.join(' ')}`);
  assert.ok(b.stdout.equals(a.stdout), `stdout of ${args.join(' ')}:\n${firstDiff(a.stdout, b.stdout)}`);
  assert.ok(b.stderr.equals(a.stderr), `stderr of ${args.join(' ')}:\n${firstDiff(a.stderr, b.stderr)}`);
  return a;
}

function firstDiff(a, b) {
  const x = a.toString('latin1').split('\n');
  const y = b.toString('latin1').split('\n');
  for (let i = 0; i < Math.max(x.length, y.length); ++i) {
    if (x[i] !== y[i]) return `line ${i + 1}\nnative: ${x[i]}\nnpm:    ${y[i]}`;
  }
  return '(same lines)';
}

test('--json: byte-identical on every fixture, one file per run', { skip }, () => {
  let failures = 0;
  for (const f of files) {
    const a = assertSameRun(['info', '--json', f]);
    if (a.status === 1) ++failures;
    assert.equal(a.stdout.toString().split('\n').length, 2, f);
  }
  assert.ok(failures > 0 && failures < files.length);
});

test('--json and text, all fixtures in one run, with missing files and a directory', { skip }, () => {
  const all = [...files, 'no/such/file.stl', 'tests'];
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
