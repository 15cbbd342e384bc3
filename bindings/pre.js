// --pre-js for the wasm glue (runs inside the factory function).
// Emscripten 3.1.6's EXPORT_ES6 glue reads `__dirname` when it runs under Node,
// which ES modules do not have. The package always hands Node the .wasm bytes
// (wasmBinary, read with fs), so the directory is never used: define it empty.
var __dirname = '';
