// stltopo/read.h: reading STL bytes (whole or streamed) into a Mesh.
#pragma once

#include <cstddef>
#include <cstdint>

#include "stltopo/mesh.h"
#include "stltopo/status.h"

namespace stltopo {

inline constexpr size_t kMaxNumberChars = 4096;  // longer ASCII numbers are an error

struct ReadOptions {
  uint32_t maxTriangles = 1u << 28;  // more gives Code::TooLarge
  uint64_t maxBytes = 0;             // 0 = unlimited; more gives Code::TooLarge
  uint64_t sizeHint = 0;             // total input size if known (lets the reader reserve
                                     // and fail early); 0 = unknown. Never trusted beyond
                                     // what arrives.
  bool keepNormals = false;          // store the facet normals in Mesh::normals
  // Threads for binary input (decoding, the per-triangle figures and the exact weld, in
  // batches): 1 = one thread (the default); 0 = the machine's hardware threads. The mesh,
  // its vertex numbering, warnings and errors are the same for every value. The wasm build
  // always uses one.
  unsigned threads = 1;
};

// Streaming reader. Feed bytes in chunks of any size (down to 1 byte), then call
// finish(). The result is identical for every chunking.
//
// Contract. feed() returns Ok, or the first error of the input: too-large (maxBytes or
// maxTriangles passed), out-of-memory, or an error of the format (truncated, ascii-syntax,
// non-finite, not-stl, ...) as soon as neither format can still be the answer. finish()
// returns Ok and moves the mesh into `out` (warnings in out.warnings), or an error (empty,
// not-stl, truncated, unexpected-end, ascii-syntax, non-finite, too-large, out-of-memory)
// and leaves `out` untouched. After an error, feed() and finish() keep returning it;
// feed() after finish() and a second finish() give invalid-argument. reset() starts a new
// read with the same options. `data` may be null when `size` is 0. If the reader's state
// could not be allocated, feed() and finish() return out-of-memory.
class Reader {
 public:
  explicit Reader(const ReadOptions& options = {});
  ~Reader();
  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;

  Status feed(const uint8_t* data, size_t size);
  // Completes the read and moves the mesh into `out` on success.
  Status finish(Mesh& out);
  void reset();
  uint64_t bytesRead() const;

  struct Impl;

 private:
  Impl* impl_;
};

// Whole-buffer convenience: one feed() plus finish(), with sizeHint = size unless set; the
// same codes, and `out` is untouched on failure.
Status readStl(const uint8_t* data, size_t size, Mesh& out, const ReadOptions& options = {});

// Test-only: the smallest number of work items (records, triangles, vertices) per part
// before a threaded stage splits its work (0: each stage's default, the thousands). The
// tests set 1, so that the threaded paths run on small inputs too. Process-wide; set it
// while no read, topology or geometry call runs.
void setParallelGrainForTesting(size_t items);
// Test-only: natively, the loops that run once over a whole mesh (the topology's passes, the
// shells' triangle pass, the triangle checks, the intersection hierarchy) run in pieces of
// this many items, as they always do in wasm (0, the default: one piece), so that the tests
// can check that the pieces give the whole loop's result. Process-wide, as above.
void setChunkItemsForTesting(size_t items);
// Test-only: how many times a stage has split its work over two or more threads since the
// process started (so that a test can tell that the threaded paths ran).
uint64_t parallelSplitsForTesting();
// Test-only: how many batches of binary records the threaded read has welded each way since
// the process started: 0 by ranges, 1 by pieces, 2 by lookups (src/mesh_builder.h). Native
// builds only: the threaded wasm modules weld by ranges and do not count.
uint64_t threadedReadBatchesForTesting(unsigned way);

}  // namespace stltopo
