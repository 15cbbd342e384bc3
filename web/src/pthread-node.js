// Node only: the worker_threads script behind each pool worker of a threaded module
// (instance.node.js). The glue's worker script (stltopo-*-mt.worker.js) is written for Web
// Workers: this gives it self, postMessage and onmessage over the worker's port, then runs
// it. Messages that arrive before it set onmessage are kept and handed over in order.
import { parentPort, workerData } from 'node:worker_threads';

const early = [];
globalThis.self = globalThis;
globalThis.postMessage = (msg, transfer) => parentPort.postMessage(msg, transfer);
parentPort.on('message', (data) => {
  if (typeof globalThis.onmessage === 'function') globalThis.onmessage({ data });
  else early.push(data);
});
await import(workerData.script);
for (const data of early.splice(0)) globalThis.onmessage({ data });
