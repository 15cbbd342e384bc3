// The npm CLI's calls into wasm (bin/stltopo.mjs): the report of `info`, `convert` and
// `split`, done as the native CLI (tools/cli.cpp) does them, on the session helpers and
// the module table of the package (dist/wasm.js: internal.sessionCall, MODULE_OF).
import { StlError, fromStatus, MESSAGE_BYTES } from '../dist/errors.js';
import { DEFAULTS, normalizeOptions, normalizeWriteOptions } from '../dist/options.js';
import { concatBytes } from '../dist/wasm.js';

/** report, convert and split on the hooks of an instance (api.internal of instance.node.js). */
export function cliCalls(internal) {
  const { moduleFor, sessionCall, withSession, readerOf, readInto, sessionChunks } = internal;

  // The format to write: writeOptions.format, else the input's.
  const inputFormat = (w, writeOptions, session) => {
    if (writeOptions.format === undefined) w.format = session.meta().format === 'ascii' ? 'ascii' : 'binary';
  };

  // convert: reads a source as the native CLI does (default options, no normals, no
  // topology) and yields the chunks of its STL file (format: the input's unless
  // writeOptions.format says). Throws the StlError of the read or of the write.
  async function* convert(source, writeOptions) {
    const entry = await moduleFor('write');
    const o = { ...normalizeOptions({ topology: false }), tolerance: 0 };
    const w = normalizeWriteOptions(writeOptions);
    yield* sessionCall(entry, readerOf(source, o), async function* converted(session) {
      await readInto(session, entry, source, o);
      inputFormat(w, writeOptions, session);
      yield* sessionChunks(entry, session, w);
    });
  }

  // split: reads a source as the native CLI does (default options, the report-only topology
  // with shells) and yields { shells: n } once it is read, then per shell k { k, line(file) }
  // followed by the chunks of its STL file (format: the input's unless writeOptions.format says).
  async function* split(source, writeOptions) {
    const entry = await moduleFor('write');
    const o = { ...normalizeOptions({ topology: true, shells: true }), tolerance: 0 };
    const w = normalizeWriteOptions(writeOptions);
    yield* sessionCall(entry, readerOf(source, o), async function* shells(session) {
      await readInto(session, entry, source, o);
      inputFormat(w, writeOptions, session);
      const n = session.shellCount();
      yield { shells: n };
      for (let k = 0; k < n; ++k) {
        yield { k, line: (file) => session.splitLine(file, k) };
        const st = session.selectShell(k);
        if (st) throw fromStatus(st);
        yield* sessionChunks(entry, session, w);
      }
    });
  }

  // info: the native CLI's JSON line or text for one input (the text report always lists
  // the first defects of each kind, as the native one does).
  async function report(source, { file, json, topology = DEFAULTS.topology, tolerance = DEFAULTS.tolerance,
    maxTriangles = DEFAULTS.maxTriangles, maxBytes = DEFAULTS.maxBytes, shells = false, defects = false,
    maxDefects = -1, intersections = false, maxPairs = DEFAULTS.maxPairs, threads = 1 }) {
    const withDefects = defects || !json;
    const o = { ...normalizeOptions({ topology, maxTriangles, maxBytes, shells: shells || withDefects, intersections,
      maxPairs, threads: Math.min(threads, 1024) }), tolerance, keepMessageBytes: !json };
    const entry = await moduleFor('load', o);
    const max = maxDefects >= 0 ? maxDefects : json ? 1000 : 5;
    return withSession(entry, readerOf(source, o), async (session) => {
      await readInto(session, entry, source, o);
      return {
        ok: true,
        // The full module's report comes in pieces (Uint8Arrays): as one string, the JSON of
        // some 1.4M shells would pass V8's string limit.
        text: !session.infoJsonPieces ? (json ? `${session.infoJson(file, shells, withDefects, max)}\n`
          : session.infoText(file, shells, withDefects, max))
          : json ? [...session.infoJsonPieces(file, shells, withDefects, max), new Uint8Array([10])]
            : session.infoTextPieces(file, shells, withDefects, max),
      };
    }, {
      async fail(err) {
        if (!(err instanceof StlError)) throw err;
        if (json) return { ok: false, error: err, text: `${await internal.errorJson(file, err, entry)}\n` };
        const bytes = err[MESSAGE_BYTES];
        if (!bytes) return { ok: false, error: err, text: `${file}: ${err.message}\n` };
        return { ok: false, error: err, text: concatBytes(new TextEncoder().encode(`${file}: `), bytes, new Uint8Array([10])) };
      },
    });
  }

  return { report, convert, split };
}
