// The README's snippet for Vite 5 and 7: their dev server pre-bundles dependencies into
// node_modules/.vite (optimizeDeps), away from stltopo's .wasm and worker files.
export default {
  optimizeDeps: { exclude: ['stltopo'] },
};
