// Errors of the JS layer: StlError and the one way to make one.

export class StlError extends Error {
  constructor(code, message, location) {
    super(message);
    this.name = 'StlError';
    this.code = code;
    if (location) {
      if (location.offset !== undefined) this.offset = location.offset;
      if (location.line !== undefined) this.line = location.line;
      if (location.triangle !== undefined) this.triangle = location.triangle;
    }
  }
}

/** An StlError whose message starts with its code, as the core's: "code: message". */
export function stlError(code, message, location) {
  return new StlError(code, `${code}: ${message}`, location);
}

export const invalid = (message) => stlError('invalid-argument', message);
export const abortError = () => stlError('aborted', 'the load was cancelled (AbortSignal)');
export function checkAbort(signal) {
  if (signal && signal.aborted) throw abortError();
}

// The CLI prints core messages as raw bytes, like the native CLI.
export const MESSAGE_BYTES = Symbol('stltopo.messageBytes');
export const FROM_CORE = Symbol('stltopo.fromCore');

/** The StlError of a status object from the bindings ({ code, message, offset?, ... }). */
export function fromStatus(st) {
  const e = new StlError(st.code, st.message, st);
  e[FROM_CORE] = true;
  return e;
}
