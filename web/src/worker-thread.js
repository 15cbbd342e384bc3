// The Web Worker script behind stltopo/worker.
import { api } from './instance.js';
import { serve } from './worker-handler.js';

serve({
  post: (msg, transfer) => self.postMessage(msg, transfer || []),
  onMessage: (fn) => { self.onmessage = (e) => fn(e.data); },
}, api.internal);
