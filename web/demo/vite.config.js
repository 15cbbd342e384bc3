// Vite config for the demo (root: web/demo). Two small plugins:
// - stltopo-package: `import 'stltopo'`, 'stltopo/worker', 'stltopo/three' resolve through the
//   "exports" of the package's own package.json to the built dist/, so the page runs exactly what
//   npm users get. STLTOPO_PACKAGE_DIR points it at another copy (e.g. an unpacked `npm pack`).
// - stltopo-samples: serves the sample fixtures from tests/fixtures at /samples/<file> in dev and
//   copies them into the static build, so the repository keeps one copy of each.
import { defineConfig } from 'vite';
import { existsSync, readFileSync } from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { samples } from './samples.js';

const demoDir = path.dirname(fileURLToPath(import.meta.url));
const repoRoot = path.resolve(demoDir, '../..');
const packageDir = path.resolve(process.env.STLTOPO_PACKAGE_DIR || repoRoot);
const fixturesDir = path.join(repoRoot, 'tests/fixtures');

/** Picks the browser ESM target of one "exports" entry (string or condition object). */
function pickTarget(entry) {
  if (typeof entry === 'string' || entry == null) return entry;
  if (Array.isArray(entry)) return entry.map(pickTarget).find(Boolean);
  for (const condition of ['browser', 'import', 'module', 'default']) {
    if (condition in entry) {
      const target = pickTarget(entry[condition]);
      if (target) return target;
    }
  }
  return null;
}

function stltopoPackage() {
  return {
    name: 'stltopo-package',
    enforce: 'pre',
    resolveId(id) {
      if (id !== 'stltopo' && !id.startsWith('stltopo/')) return null;
      const pkg = JSON.parse(readFileSync(path.join(packageDir, 'package.json'), 'utf8'));
      const subpath = id === 'stltopo' ? '.' : `./${id.slice('stltopo/'.length)}`;
      // Without "exports" (yet), fall back to the dist/ layout: dist/index.js, dist/<subpath>.js.
      const target = pkg.exports
        ? pickTarget(pkg.exports[subpath])
        : `./dist/${subpath === '.' ? 'index' : subpath.slice(2)}.js`;
      if (!target) this.error(`stltopo: package.json in ${packageDir} does not export "${subpath}"`);
      const file = path.resolve(packageDir, target);
      if (!existsSync(file)) {
        this.error(`stltopo: ${path.relative(repoRoot, file)} is missing; build the package first (npm run build)`);
      }
      return file;
    },
  };
}

// Threads (README, *Threads in JS*): the threaded modules need SharedArrayBuffer, which the
// browser gives only to a cross-origin isolated page. The dev and preview servers send the two
// headers; a static host of the built site must send them too (else the page loads on one
// thread). The build copies the threaded modules' files to stltopo-mt/ (a bundle does not
// hold them: their glue is imported and their workers started from URLs at run time) and
// the page points init({ threadsUrl }) there (main.js).
const ISOLATION = { 'Cross-Origin-Opener-Policy': 'same-origin', 'Cross-Origin-Embedder-Policy': 'require-corp' };
const THREADED_FILES = ['wasm', 'full'].flatMap((m) => ['js', 'wasm', 'worker.js'].map((x) => `stltopo-${m}-mt.${x}`));

function stltopoThreads() {
  return {
    name: 'stltopo-threads',
    configureServer(server) {
      server.middlewares.use((req, res, next) => {
        const match = /\/stltopo-mt\/([^/?#]+)$/.exec((req.url ?? '').split('?')[0]);
        if (match && THREADED_FILES.includes(match[1])) {
          const data = readFileSync(path.join(packageDir, 'dist', match[1]));
          // A worker script of an isolated page needs COEP itself, or the browser blocks it.
          for (const [k, v] of Object.entries(ISOLATION)) res.setHeader(k, v);
          res.setHeader('Content-Type', match[1].endsWith('.wasm') ? 'application/wasm' : 'text/javascript');
          res.setHeader('Content-Length', data.length);
          res.end(data);
          return;
        }
        next();
      });
    },
    generateBundle() {
      for (const name of THREADED_FILES) {
        this.emitFile({ type: 'asset', fileName: `stltopo-mt/${name}`, source: readFileSync(path.join(packageDir, 'dist', name)) });
      }
    },
  };
}

function stltopoSamples() {
  const files = new Map(samples.filter((s) => s.path).map((s) => [s.file, path.join(fixturesDir, s.path)]));
  return {
    name: 'stltopo-samples',
    configureServer(server) {
      server.middlewares.use((req, res, next) => {
        const match = /\/samples\/([^/?#]+)/.exec(req.url ?? '');
        const file = match && files.get(decodeURIComponent(match[1]));
        if (!file) return next();
        const data = readFileSync(file);
        res.setHeader('Content-Type', 'model/stl');
        res.setHeader('Content-Length', data.length);
        res.end(data);
      });
    },
    generateBundle() {
      for (const [name, file] of files) {
        this.emitFile({ type: 'asset', fileName: `samples/${name}`, source: readFileSync(file) });
      }
    },
  };
}

export default defineConfig({
  root: demoDir,
  base: './', // relative URLs: the built site works from any folder of any static host
  plugins: [stltopoPackage(), stltopoSamples(), stltopoThreads()],
  server: {
    fs: { allow: [repoRoot, packageDir] },
    headers: ISOLATION,
  },
  worker: { format: 'es' },
  build: {
    outDir: 'dist',
    emptyOutDir: true,
    target: 'es2022',
    chunkSizeWarningLimit: 2000,
  },
  optimizeDeps: {
    entries: ['index.html'],
    // manifold-3d finds its .wasm next to itself (new URL('manifold.wasm', import.meta.url)),
    // which a pre-bundled copy would not have beside it.
    exclude: ['stltopo', 'manifold-3d'],
  },
  preview: { host: '127.0.0.1', headers: ISOLATION },
});
