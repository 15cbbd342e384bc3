// The worker_threads script behind stltopo/worker in Node.
import { parentPort } from 'node:worker_threads';
import { _internal, fileSource } from './node.js';
import { serve } from './worker-handler.js';

serve({
  post: (msg, transfer) => parentPort.postMessage(msg, transfer || []),
  onMessage: (fn) => parentPort.on('message', fn),
}, _internal, { fileSource });
