// Node only, not public: a file on disk as an input source (loadStlFile, the worker
// thread's 'path' inputs and the npm CLI).
import { open } from 'node:fs/promises';

const FILE_CHUNK = 1 << 20;

// A source (sources.js) that streams a file from disk in 1 MiB reads (one buffer, reused:
// the core copies each chunk before the next read).
export async function fileSource(path) {
  const fh = await open(path instanceof URL ? path : String(path), 'r');
  let total = 0;
  try {
    const st = await fh.stat();
    if (st.isFile()) total = st.size;
  } catch {
    // no size hint
  }
  const buf = new Uint8Array(FILE_CHUNK);
  let closed = false;
  const close = () => {
    if (closed) return;
    closed = true;
    fh.close().catch(() => {});
  };
  return {
    total,
    async next() {
      if (closed) return null;
      let n;
      try {
        ({ bytesRead: n } = await fh.read(buf, 0, buf.length, null));
      } catch (e) {
        close();
        throw e;
      }
      if (n === 0) {
        close();
        return null;
      }
      return buf.subarray(0, n);
    },
    cancel: close,
  };
}
