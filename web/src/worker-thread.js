// The Web Worker script behind stltopo/worker. It imports the full module's glue statically
// (a worker bundle must not import dynamically); its .wasm is fetched only when needed.
import createStltopoFullModule from './stltopo-full.js';
import { createInstance } from './instance.js';
import { serve } from './worker-handler.js';

serve({
  post: (msg, transfer) => self.postMessage(msg, transfer || []),
  onMessage: (fn) => { self.onmessage = (e) => fn(e.data); },
}, createInstance({ importFull: async () => ({ default: createStltopoFullModule }) }).internal);
