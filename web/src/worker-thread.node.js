// The worker_threads script behind stltopo/worker in Node.
import { parentPort } from 'node:worker_threads';
import { api, fileSource } from './instance.node.js';
import { serve } from './worker-handler.js';

serve({
  post: (msg, transfer) => parentPort.postMessage(msg, transfer || []),
  onMessage: (fn) => parentPort.on('message', fn),
}, api.internal, { fileSource });
