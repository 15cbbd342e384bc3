// npm pack smoke test (as manifold's): pack, install the tarball into an empty
// folder, import it from a plain .mjs file, parse a file, run the CLI there.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync, spawnSync } from 'node:child_process';
import { mkdtempSync, rmSync, writeFileSync, readdirSync, copyFileSync, readFileSync, existsSync } from 'node:fs';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { fixture, root, nativeCli, haveNativeCli } from './helpers.mjs';

const npm = process.platform === 'win32' ? 'npm.cmd' : 'npm';

test('npm pack → install in a fresh folder → import, parse, worker, CLI', { timeout: 600_000 }, () => {
  const dir = mkdtempSync(path.join(tmpdir(), 'stltopo-pack-'));
  try {
    const packOut = execFileSync(npm, ['pack', '--json', '--pack-destination', dir], { cwd: root, stdio: ['ignore', 'pipe', 'inherit'] });
    // prepack (scripts/build-wasm.sh) prints to stdout too; npm's JSON starts at a line '['.
    const text = packOut.toString();
    const [info] = JSON.parse(text.slice(text.search(/^\[$/m)));
    const names = info.files.map((f) => f.path).sort();
    for (const must of ['package.json', 'bin/stltopo.mjs', 'bin/cli-wasm.mjs', 'bin/cli-corpus.mjs', 'dist/index.js', 'dist/node.js', 'dist/index.d.ts', 'dist/worker.js',
      'dist/worker.node.js', 'dist/worker.d.ts', 'dist/three.js', 'dist/three.d.ts', 'dist/stltopo-wasm.js', 'dist/stltopo-wasm.wasm', 'dist/stltopo-full.js', 'dist/stltopo-full.wasm', 'dist/worker-thread.js', 'docs/JS-API.md', 'docs/EDITING.md', 'docs/REPAIR.md', 'README.md']) {
      assert.ok(names.includes(must), `${must} missing from the package: ${names.join(', ')}`);
    }
    for (const n of names) assert.ok(/^(package\.json|README\.md|LICENSE.*|bin\/(stltopo|cli-wasm|cli-corpus)\.mjs|dist\/.*|docs\/(JS-API|EDITING|REPAIR)\.md)$/.test(n), `unexpected ${n}`);
    // The README is the registry's page: its links are absolute, anchors, or relative links
    // that resolve. There is no public repository yet (package.json has no `repository`), so a
    // relative link is a file of the package, or one of the few repository files the README
    // points readers of the source tree to (REPO_ONLY; a registry page cannot show those).
    const REPO_ONLY = ['docs/demo.png', 'bench/PROFILE.md', 'bench/HISTORY.md', 'tests/fixtures/SOURCES.md', 'tests/fuzz/README.md', 'CONTRIBUTING.md'];
    const readme = readFileSync(path.join(root, 'README.md'), 'utf8');
    for (const [, link] of readme.matchAll(/\]\(([^)\s]+)\)/g)) {
      if (/^(https?:|#)/.test(link)) continue;
      assert.ok(!/github\.com\/stltopo\/stltopo/.test(link), `README links the invented repository: ${link}`);
      const file = link.split('#')[0];
      if (REPO_ONLY.includes(file)) {
        assert.ok(existsSync(path.join(root, file)), `README links ${link}, which does not exist`);
        continue;
      }
      assert.ok(names.includes(file), `README links ${link}, which is not in the package`);
    }
    assert.ok(!readme.includes('github.com/stltopo/stltopo'), 'README names the invented repository github.com/stltopo/stltopo');
    const pkgJson = JSON.parse(readFileSync(path.join(root, 'package.json'), 'utf8'));
    for (const k of ['repository', 'homepage', 'bugs']) assert.equal(pkgJson[k], undefined, `package.json ${k}: no public repository yet`);

    const app = path.join(dir, 'app');
    execFileSync('mkdir', ['-p', app]);
    writeFileSync(path.join(app, 'package.json'), '{ "name": "app", "private": true }\n');
    execFileSync(npm, ['install', '--no-audit', '--no-fund', '--no-package-lock', path.join(dir, info.filename)], { cwd: app, stdio: 'inherit' });
    const stl = path.join(app, 'bunny.stl');
    copyFileSync(fixture('bunny.stl'), stl);
    writeFileSync(path.join(app, 'smoke.mjs'), `
import { loadStl, loadStlFile, StlError } from 'stltopo';
import { loadStl as loadInWorker } from 'stltopo/worker';
import { readFile } from 'node:fs/promises';
const m = await loadStl(await readFile('bunny.stl'));
const f = await loadStlFile('bunny.stl');
const w = await loadInWorker(await readFile('bunny.stl'));
let code = null;
try { await loadStl(new Uint8Array(0)); } catch (e) { code = e instanceof StlError && e.code; }
console.log(JSON.stringify({ n: m.nTriangles, f: f.nTriangles, w: w.nTriangles, valid: m.validate().ok, code, watertight: m.stats.watertight }));
`);
    const out = JSON.parse(execFileSync(process.execPath, ['smoke.mjs'], { cwd: app }).toString());
    assert.ok(out.n > 60000);
    assert.equal(out.f, out.n);
    assert.equal(out.w, out.n);
    assert.equal(out.valid, true);
    assert.equal(out.code, 'empty');

    // ES modules only: require() loads them where Node's require(esm) is on (20.19+, 22.12+).
    if (process.features.require_module) {
      writeFileSync(path.join(app, 'smoke.cjs'), `
const { loadStl } = require('stltopo');
const { loadStl: loadInWorker } = require('stltopo/worker');
const bytes = require('node:fs').readFileSync('bunny.stl');
Promise.all([loadStl(bytes), loadInWorker(bytes)]).then(([m, w]) => console.log(m.nTriangles, w.nTriangles));
`);
      const cjs = spawnSync(process.execPath, ['smoke.cjs'], { cwd: app });
      assert.equal(cjs.status, 0, cjs.stderr.toString());
      assert.equal(cjs.stdout.toString().trim(), `${out.n} ${out.n}`);
      assert.equal(cjs.stderr.toString(), '', 'no warning');
    }

    const cli = spawnSync(npm, ['exec', '--offline', '--', 'stltopo', 'info', '--json', 'bunny.stl'], { cwd: app });
    assert.equal(cli.status, 0, cli.stderr.toString());
    const line = JSON.parse(cli.stdout.toString());
    assert.equal(line.triangles, out.n);
    if (haveNativeCli) {
      const want = execFileSync(nativeCli, ['info', '--json', 'bunny.stl'], { cwd: app });
      assert.ok(cli.stdout.equals(want), 'the installed CLI prints the native JSON');
    }
    assert.ok(readdirSync(path.join(app, 'node_modules/.bin')).includes('stltopo'));
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
});
