// stltopo/status.h: status codes and the Status every fallible call returns.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace stltopo {

inline constexpr uint32_t kInvalid = ~0u;
inline constexpr uint64_t kNoOffset = ~uint64_t(0);

// ---------------------------------------------------------------------------
// Status codes. The string names (codeName) are stable and shared with JS.
enum class Code : uint8_t {
  Ok = 0,
  // errors
  Empty,            // "empty": zero bytes
  NotStl,           // "not-stl": neither binary nor ASCII STL
  Truncated,        // "truncated": binary data shorter than its count promises
  UnexpectedEnd,    // "unexpected-end": ASCII file ends inside a facet
  AsciiSyntax,      // "ascii-syntax": malformed ASCII (bad keyword, number, vertex count)
  NonFinite,        // "non-finite": NaN or Inf coordinate
  TooLarge,         // "too-large": more than maxTriangles / maxBytes
  OutOfMemory,      // "out-of-memory": an allocation failed
  InvalidArgument,  // "invalid-argument": API misuse (e.g. feed after finish)
  Aborted,          // "aborted": cancelled by the caller (JS AbortSignal)
  Invalid,          // "invalid": validate() found a broken invariant
  // warnings
  TrailingBytes,    // "trailing-bytes": < 84 extra bytes after the last binary triangle
  MissingEndsolid,  // "missing-endsolid": ASCII file ends without endsolid
  NameTruncated,    // "name-truncated": a solid name longer than kMaxNameBytes
  // errors (after the warnings: the numbering of the codes above stays)
  InvalidIndex,  // "invalid-index": a vertex id out of range (element: the triangle)
  WriteFailed,   // "write-failed": the output sink refused the data
  // errors of the JS layer (the core never returns them; named here so that JS errors print as the core's)
  WasmLoad,  // "wasm-load": the npm package could not fetch or compile its wasm, or start its worker
  // errors (continued)
  EditRefused,  // "edit-refused": an EditableMesh edit was refused; nothing changed
  // New codes go above this line; kCodeCount and the name table in status.cpp follow.
};
inline constexpr int kCodeCount = int(Code::EditRefused) + 1;

// The stable name of a code ("truncated"), "unknown" for a value outside the enum.
const char* codeName(Code c);
// The code whose name is `name`; false (and `out` unchanged) when no code has that name.
bool codeFromName(const char* name, Code& out);

// A status: a code, a human message and where it happened. Fields that do not
// apply are kNoOffset / 0 (line numbers start at 1) / kInvalid.
struct Status {
  Code code = Code::Ok;
  std::string message;
  uint64_t offset = kNoOffset;   // byte offset in the input
  uint64_t line = 0;             // 1-based ASCII line, 0 = not applicable
  uint32_t triangle = kInvalid;  // triangle index, kInvalid = not applicable
  uint32_t element = kInvalid;   // validate(): the offending half-edge/vertex/face id
  bool ok() const { return code == Code::Ok; }

  // An error or warning whose message starts with the code's name: "truncated: <message>".
  static Status error(Code c, const std::string& message, uint64_t offset = kNoOffset, uint64_t line = 0,
                      uint32_t triangle = kInvalid);
};

}  // namespace stltopo
