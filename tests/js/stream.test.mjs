// Chunked input (streams of 1, 7 and 4096 bytes, Blob, Response, typed-array
// views, async iterables) gives exactly the buffer result.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync, createReadStream } from 'node:fs';
import { loadStl, loadStlFile } from 'stltopo';
import { fixtures, chunkedStream, meshArrays } from './helpers.mjs';

const loadable = [];
for (const f of fixtures()) {
  const bytes = new Uint8Array(readFileSync(f));
  try {
    loadable.push({ f, bytes, mesh: await loadStl(bytes) });
  } catch {
    loadable.push({ f, bytes, mesh: null });
  }
}

function assertSame(a, b, what) {
  assert.deepEqual(meshArrays(a), meshArrays(b), what);
  assert.deepEqual(a.stats, b.stats, what);
  assert.deepEqual(a.solids, b.solids, what);
  assert.deepEqual(a.warnings, b.warnings, what);
}

async function outcome(promise) {
  try {
    return { mesh: await promise };
  } catch (e) {
    return { error: { code: e.code, message: e.message, offset: e.offset, line: e.line, triangle: e.triangle } };
  }
}

for (const size of [1, 7, 4096]) {
  test(`ReadableStream in ${size}-byte chunks equals buffer input, on every fixture`, async () => {
    let n = 0;
    for (const { f, bytes, mesh } of loadable) {
      if (bytes.length > (size === 1 ? 100_000 : size === 7 ? 1_500_000 : Infinity)) continue; // tiny chunks: smaller files suffice
      const got = await outcome(loadStl(chunkedStream(bytes, size)));
      const want = mesh ? { mesh } : await outcome(loadStl(bytes));
      if (want.mesh) assertSame(got.mesh, want.mesh, `${f} @${size}`);
      else assert.deepEqual(got.error, want.error, `${f} @${size}`);
      ++n;
    }
    assert.ok(n >= 10);
  });
}

test('Blob, Response, ArrayBuffer, offset views, Node streams and loadStlFile agree', async () => {
  const { f, bytes, mesh } = loadable.find((x) => x.mesh && x.mesh.nTriangles > 1000);
  assertSame(await loadStl(bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.length)), mesh, 'ArrayBuffer');
  const padded = new Uint8Array(bytes.length + 10);
  padded.set(bytes, 5);
  assertSame(await loadStl(padded.subarray(5, 5 + bytes.length)), mesh, 'offset view');
  assertSame(await loadStl(new DataView(padded.buffer, 5, bytes.length)), mesh, 'DataView');
  assertSame(await loadStl(new Blob([bytes.subarray(0, 100), bytes.subarray(100)])), mesh, 'Blob');
  assertSame(await loadStl(new Response(bytes)), mesh, 'Response');
  assertSame(await loadStl(new Response(chunkedStream(bytes, 999))), mesh, 'Response(stream)');
  assertSame(await loadStl(createReadStream(f, { highWaterMark: 333 })), mesh, 'fs.ReadStream');
  assertSame(await loadStlFile(f), mesh, 'loadStlFile');
  assertSame(await loadStlFile(new URL(`file://${f}`)), mesh, 'loadStlFile(URL)');
});

test('onProgress reports growing byte counts and ends at 1', async () => {
  const { bytes } = loadable.reduce((a, b) => (b.mesh && b.bytes.length > a.bytes.length ? b : a));
  const calls = [];
  await loadStl(new Blob([bytes]), { onProgress: (fraction, read) => calls.push([fraction, read]) });
  assert.ok(calls.length >= 1);
  assert.deepEqual(calls.at(-1), [1, bytes.length]);
  for (let i = 1; i < calls.length; ++i) assert.ok(calls[i][1] >= calls[i - 1][1]);
  for (const [fr] of calls) assert.ok(fr >= 0 && fr <= 1);
  const unknown = [];
  await loadStl(chunkedStream(bytes, 1 << 16), { onProgress: (fraction, read) => unknown.push([fraction, read]) });
  assert.deepEqual(unknown.at(-1), [1, bytes.length]);
});
