// The binary STL parser: 84-byte headers and 50-byte records, concatenated parts, any
// chunking. Feeds a Builder; end() tells the reader how the input ended.
#pragma once

#include "mesh_builder.h"

namespace stltopo::detail {

inline constexpr uint64_t kHeaderBytes = 84;
inline constexpr uint64_t kRecordBytes = 50;

// Binary parser (handles concatenated parts).
struct BinaryParser {
  Builder b;
  uint8_t header[kHeaderBytes];
  uint32_t headerHave = 0;
  uint8_t rec[kRecordBytes];
  uint32_t recHave = 0;
  bool inRecords = false;
  uint32_t partIndex = 0;  // number of parts whose header has been read
  uint64_t partStart = 0;  // offset of the current part's header
  uint32_t partCount = 0;  // triangles promised by the current part
  uint32_t partDone = 0;
  uint64_t partFirst = 0;   // triangles read before the current part
  uint64_t offset = 0;      // bytes consumed
  bool skipping = false;    // over maxTriangles or after a content error: count bytes only
  uint64_t skipNeeded = 0;  // bytes needed to complete the current part when skipping
  Status contentError;      // e.g. non-finite: reported unless the file is also truncated

#if STLTOPO_THREADS
  explicit BinaryParser(const ReadOptions& o) : b(o), threads(threadCount(o.threads)) {}
#else
  explicit BinaryParser(const ReadOptions& o) : b(o) {}
#endif

  void startPart();

  void finishPart();

  inline void record(const uint8_t* r, uint64_t recOffset, const uint32_t* hashes = nullptr) {
    float f[12];
    uint16_t attr;
    Builder::decodeRecord(r, f, attr);
    if (!b.add(f, f + 3, attr, recOffset, 0, hashes)) addFailed();
  }

  // After b.add() failed: a size problem (truncated) outranks a content problem found
  // before it, so keep counting bytes to learn whether the part is complete; drop the arrays.
  void addFailed() {
    contentError = b.error;
    b.error = Status{};
    b.dropArrays();
    skipping = true;
    skipNeeded = kHeaderBytes + kRecordBytes * uint64_t(partCount);
  }

  unsigned threads = 1;  // threadCount(ReadOptions::threads)

  void feed(const uint8_t* p, size_t n);

  // Outcome at end of input.
  enum class End { Exact, Trailing, Error, TooShort };
  End end(Status& st);

  Status truncated(uint64_t needBytes);
};
}  // namespace stltopo::detail
