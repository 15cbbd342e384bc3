// The Web Worker script behind stltopo/worker.
import { createInstance } from './instance.js';
import { serve } from './worker-handler.js';

serve({
  post: (msg, transfer) => self.postMessage(msg, transfer || []),
  onMessage: (fn) => { self.onmessage = (e) => fn(e.data); },
}, createInstance().internal);
