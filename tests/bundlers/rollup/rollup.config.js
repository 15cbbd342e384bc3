// The README's Rollup config: node-resolve for the packages, ES module output, and
// stltopo's worker script as a second entry named worker-thread.js (the package's
// package.json "build" copies stltopo-wasm.wasm next to the bundle).
import { nodeResolve } from '@rollup/plugin-node-resolve';

export default {
  input: { main: 'src/main.js', 'worker-thread': 'stltopo/worker-thread' },
  output: { dir: 'dist', format: 'es', entryFileNames: '[name].js' },
  plugins: [nodeResolve({ browser: true })],
};
