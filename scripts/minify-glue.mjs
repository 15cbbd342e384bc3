// Minifies an Emscripten glue file (ES module) with esbuild: identifiers mangled and dead
// branches dropped, which Emscripten 3.1.6 does only with the Closure compiler (Java).
// Usage: node scripts/minify-glue.mjs IN OUT
import fs from 'node:fs';

const [input, output] = process.argv.slice(2);
let esbuild;
try {
  esbuild = await import('esbuild');
} catch {
  console.error('minify-glue: the npm dev dependency esbuild is missing (npm install)');
  process.exit(1);
}
const { code } = await esbuild.transform(fs.readFileSync(input, 'utf8'), {
  minify: true,
  format: 'esm',
  target: 'es2020',
  legalComments: 'none',
});
fs.writeFileSync(output, code);
