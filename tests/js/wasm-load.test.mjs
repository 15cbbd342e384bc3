// init({ wasmUrl | wasmBinary }) in Node, and the 'wasm-load' error when the wasm cannot be
// read or compiled: it names where the wasm came from and what it held. (The browser side,
// with a server that answers HTML for the .wasm and a worker URL that 404s, is in
// browser.test.mjs.)
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { pathToFileURL } from 'node:url';
import { execFileSync } from 'node:child_process';
import { loadStl, init, StlError } from 'stltopo';
import { loadStl as loadInWorker } from 'stltopo/worker';
import { fixture, root } from './helpers.mjs';

const cube = readFileSync(fixture('unit_cube.STL'));
const wasmPath = `${root}dist/stltopo-wasm.wasm`;

async function loadError(load = loadStl) {
  try {
    await load(cube);
  } catch (e) {
    return e;
  }
  assert.fail('the load succeeded');
}

test('init: bytes that are no wasm, a missing file: StlError wasm-load naming them; then the default works', async () => {
  init({ wasmBinary: new TextEncoder().encode('<!doctype html><p>not found') });
  let e = await loadError();
  assert.ok(e instanceof StlError);
  assert.equal(e.code, 'wasm-load');
  assert.match(e.message, /^wasm-load: wasmBinary is not a WebAssembly module: first bytes 3c 21 64 6f 63 74 79 70 "<!doctyp"$/);

  init({ wasmBinary: null, wasmUrl: '/nonexistent/stltopo-wasm.wasm' });
  e = await loadError();
  assert.equal(e.code, 'wasm-load');
  assert.match(e.message, /cannot read the WebAssembly module \/nonexistent\/stltopo-wasm\.wasm: ENOENT/);

  // A worker gets the same settings and the same error.
  e = await loadError(loadInWorker);
  assert.ok(e instanceof StlError);
  assert.equal(e.code, 'wasm-load');
  assert.match(e.message, /\/nonexistent\/stltopo-wasm\.wasm/);

  init({ wasmUrl: null });
  assert.equal((await loadStl(cube)).nTriangles, 12);
  assert.equal((await loadInWorker(cube)).nTriangles, 12);
});

// Each in a fresh process: init() applies to the instance that the first load starts.
test('init: wasmUrl as a path and as a file: URL, wasmBinary as bytes', () => {
  for (const options of [`{ wasmUrl: ${JSON.stringify(wasmPath)} }`, `{ wasmUrl: new URL(${JSON.stringify(pathToFileURL(wasmPath).href)}) }`,
    `{ wasmBinary: readFileSync(${JSON.stringify(wasmPath)}) }`, "{ wasmUrl: '/nonexistent.wasm', wasmBinary: readFileSync(" + JSON.stringify(wasmPath) + ') }']) {
    const script = `import { readFileSync } from 'node:fs'; import { loadStl, init } from 'stltopo';
      init(${options}); const m = await loadStl(readFileSync(${JSON.stringify(fixture('unit_cube.STL'))})); console.log(m.nTriangles);`;
    const out = execFileSync(process.execPath, ['--input-type=module', '-e', script], { cwd: root }).toString().trim();
    assert.equal(out, '12', options);
  }
});

test('init: bad options are invalid-argument', () => {
  for (const bad of [null, 'x', { wasmUrl: 3 }, { wasmBinary: 'bytes' }, { workerUrl: {} }, { locateFile: () => '' }]) {
    assert.throws(() => init(bad), (e) => e instanceof StlError && e.code === 'invalid-argument', JSON.stringify(bad));
  }
});

test("wasm-load is a code of the core too: the npm CLI's error JSON keeps it", async () => {
  const { api } = await import('../../dist/instance.node.js');
  const err = new StlError('wasm-load', 'wasm-load: /x/stltopo-wasm.wasm is not the WebAssembly module: HTTP 404');
  const json = JSON.parse(await api.internal.errorJson('part.stl', err));
  assert.deepEqual(json, { file: 'part.stl', error: { code: 'wasm-load', message: err.message } });
});
