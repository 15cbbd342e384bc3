// Input sources. A source is { total, next(): Promise<Uint8Array|null>, cancel(reason) }:
// total is the size in bytes when known (else 0), next() gives the next chunk or null at
// the end, cancel() stops the producer (a no-op once it was read to its end).
import { invalid } from './errors.js';

function toBytes(chunk) {
  if (chunk instanceof Uint8Array) return chunk;
  if (ArrayBuffer.isView(chunk)) return new Uint8Array(chunk.buffer, chunk.byteOffset, chunk.byteLength);
  if (chunk instanceof ArrayBuffer) return new Uint8Array(chunk);
  throw invalid('stream chunks must be Uint8Array (or ArrayBuffer)');
}

export function bufferSource(bytes) {
  let done = false;
  return {
    total: bytes.byteLength,
    async next() {
      if (done) return null;
      done = true;
      return bytes;
    },
    cancel() {},
  };
}

// A source over read() -> Promise<{ done, value }> (a stream reader or an async iterator);
// stop(reason) ends the producer early.
function readerSource(total, read, stop) {
  let finished = false;
  return {
    total,
    async next() {
      if (finished) return null;
      const { done, value } = await read();
      if (done) {
        finished = true;
        return null;
      }
      return toBytes(value);
    },
    cancel(reason) {
      if (finished) return;
      finished = true;
      stop(reason);
    },
  };
}

export function streamSource(stream, total) {
  let reader;
  try {
    reader = stream.getReader();
  } catch (e) {
    throw invalid(`cannot read the stream (${e.message})`);
  }
  return readerSource(total, () => reader.read(), (reason) => reader.cancel(reason).catch(() => {}));
}

export function iteratorSource(iterable, total) {
  const it = iterable[Symbol.asyncIterator]();
  return readerSource(total, () => it.next(), () => {
    if (typeof it.return === 'function') Promise.resolve(it.return()).catch(() => {});
  });
}

function isResponse(x) {
  return (typeof Response !== 'undefined' && x instanceof Response) ||
    (typeof x.arrayBuffer === 'function' && 'body' in x && 'status' in x && x.headers && typeof x.headers.get === 'function');
}

function contentLength(response) {
  const enc = response.headers.get('content-encoding');
  if (enc && enc !== 'identity') return 0; // the length counts compressed bytes
  const n = Number(response.headers.get('content-length'));
  return Number.isFinite(n) && n > 0 ? n : 0;
}

export function toSource(input) {
  if (input == null) throw invalid('no input');
  if (input instanceof ArrayBuffer) return bufferSource(new Uint8Array(input));
  if (typeof SharedArrayBuffer !== 'undefined' && input instanceof SharedArrayBuffer) {
    return bufferSource(new Uint8Array(input));
  }
  if (ArrayBuffer.isView(input)) return bufferSource(new Uint8Array(input.buffer, input.byteOffset, input.byteLength));
  if (typeof input.getReader === 'function') return streamSource(input, 0);
  if (typeof input.stream === 'function' && typeof input.size === 'number') return streamSource(input.stream(), input.size);
  if (typeof input === 'object' && isResponse(input)) {
    if (!input.ok && input.status !== 0) throw invalid(`HTTP response status ${input.status}`);
    if (input.bodyUsed) throw invalid('the Response body was already used');
    if (!input.body) return bufferSource(new Uint8Array(0));
    return streamSource(input.body, contentLength(input));
  }
  if (typeof input[Symbol.asyncIterator] === 'function') return iteratorSource(input, 0);
  throw invalid('input must be an ArrayBuffer, a typed array, a Blob/File, a Response or a ReadableStream');
}
