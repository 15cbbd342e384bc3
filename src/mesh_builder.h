// The mesh builder: collects the parsers' triangles into a welded Mesh (the exact weld
// table), gathers the figures (area, volume, bounding box, normal mismatches) and decodes
// the colours at the end. Both parsers feed it; its per-corner work is inline here.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "bit_cast.h"
#include "parallel.h"
#include "stltopo/mesh.h"
#include "stltopo/read.h"
#include "stltopo/status.h"
#include "text_format.h"
#include "triangle_figures.h"
#include "try_alloc.h"

namespace stltopo::detail {

// out-of-memory: "could not allocate <what>".

inline uint32_t bitsOf(float f) { return detail::bitCast<uint32_t>(f); }
inline bool finiteBits(uint32_t b) { return (b & 0x7f800000u) != 0x7f800000u; }

inline uint32_t hash3(uint32_t x, uint32_t y, uint32_t z) {
  uint32_t h = x * 0x9E3779B1u;
  h ^= y * 0x85EBCA77u + (h << 6) + (h >> 2);
  h ^= z * 0xC2B2AE3Du + (h << 6) + (h >> 2);
  h ^= h >> 16;
  h *= 0x7feb352du;
  h ^= h >> 15;
  return h;
}

// Removes leading and trailing ASCII whitespace from [b, e).
void trim(const char*& b, const char*& e);

// Per binary part: the header's colour information.
struct PartColor {
  bool magics = false;
  uint8_t rgb[3] = {0, 0, 0};
};

// Builder: collects triangles into a welded Mesh.
struct Builder {
  ReadOptions opt;
  Mesh mesh;
  // Weld table: open addressing, each slot holds the normalised coordinate bits and the
  // vertex id, so a probe never touches the positions array. In front of it sits a small
  // direct-mapped cache of recent vertices: STL files list neighbouring triangles close
  // together, so most corners are found there without a cache miss.
  struct Slot {
    uint32_t x, y, z, id;  // id == kInvalid: empty
  };
  static constexpr uint32_t kRecent = 4096;
  Array<Slot> table;
  Array<Slot> recent;
  uint32_t mask = 0;
  std::vector<PartColor> partColors;  // parallel to mesh.solids (binary only)
  bool anyVisCamBit = false;
  bool solidOpen = false;
  Status error;  // sticky

#if STLTOPO_THREADS
  // A stretch of a threaded batch (addBatchParallel) past the first, welded on a thread
  // against a private table, in local ids (first appearance within the stretch), which the
  // merge maps to the mesh's. In use: ranges[1 .. threads - 1] by ranges, up to threads + 2
  // by pieces; kept from one batch to the next.
  struct RangeWeld {
    Array<Slot> table;
    uint32_t mask = 0;
    Array<Slot> recent;
    Array<float> positions;      // per local vertex: the first-seen coordinates, as written
    Array<double> area, volume;  // per record: its figures, summed in order by the merge
    Array<uint32_t> map;         // per local vertex: its id in the mesh (the merge)
    Array<uint32_t> hint;        // per local vertex: where the merge's probe stopped
    uint32_t hash[3 * 32];       // a group's corner hashes (see prepareBatch)
    uint32_t mismatches = 0;
    bool visCam = false;
  };
  RangeWeld ranges[kMaxThreads];
#endif

  explicit Builder(const ReadOptions& o) : opt(o) {}

  bool failed() const { return !error.ok(); }

  bool reserveTriangles(uint64_t n);

  void releaseWeld() {
    table.release();
    recent.release();
#if STLTOPO_THREADS
    for (RangeWeld& r : ranges) r = RangeWeld{};
#if !defined(__EMSCRIPTEN__)
    lookupMisses.release();
    lookupArea.release();
    lookupVolume.release();
#endif
#endif
  }
  void dropArrays();

  static inline uint32_t slotHash(const Slot& k) { return hash3(k.x, k.y, k.z); }

  // Grows the weld table for forVertices vertices (kept at most half full), and the recent
  // list. trianglesDone: how many triangles were welded before the one being welded (0 when
  // unknown). When nearly every corner so far was a new vertex (a triangle soup: 3 a
  // triangle) and the input's size says how many triangles are left (reserveTriangles), the
  // table is sized at once for as many new vertices as their corners, and the positions with
  // it, instead of doubling two or three times into fresh memory (see growTable).
  bool growTable(uint32_t forVertices, uint64_t trianglesDone = 0);
  uint64_t plannedTriangles = 0;  // reserveTriangles's figure: what the input can hold
#if STLTOPO_THREADS
  // A batch of `count` whole binary records at rec (the first at input offset `offset`) on up
  // to `threads` threads, with the mesh that add() gives one record at a time. Records are
  // added by add() itself on a first stretch; every later stretch is welded against a private
  // table (weldRange), in local ids, and merged in order (mergeRange): its vertices looked up
  // in the mesh's table, which by then holds the stretches before, the ones not there
  // appended in their order of first appearance; its corners mapped; its figures summed in
  // record order. The stretches are one range a thread (addBatchRanges), or pieces, 4 a
  // thread, that the free threads weld and merge as they become ready (addBatchPieces; not in
  // wasm): see the body for which. Returns the number of records added: `count`, or fewer
  // when a stretch could not be welded apart (a non-finite coordinate, no memory), and the
  // parser adds the rest one by one to meet the exact error. When add() fails on the first
  // stretch, or mergeRange runs out of memory, error is set, and the records up to the
  // failing one are counted (as one by one). 0 with nothing done when the batch is not for
  // threads (see the body).
  static constexpr unsigned kPiecesPerThread = 4, kMaxPieces = kPiecesPerThread * kMaxThreads;
  uint64_t addBatchParallel(const uint8_t* rec, uint32_t count, uint64_t offset, unsigned threads);
  // The two ways of addBatchParallel on n >= 2 threads, with its result: one range a thread,
  // the first by add(), the others welded apart at the same time, then merged in order with
  // the merges' lookups on the threads; or pieces (see above).
  uint64_t addBatchRanges(const uint8_t* rec, uint32_t count, uint64_t offset, unsigned n);
#if !defined(__EMSCRIPTEN__)
  uint64_t addBatchPieces(const uint8_t* rec, uint32_t count, uint64_t offset, unsigned n);
  // A third way, for files whose batches find most of their vertices in the mesh already (a
  // file in random order, past its first batch): every corner looked up in the mesh's table
  // on the threads (which only read it), with the records' figures; then, on the caller, in
  // corner order, the corners not found are looked up again and the new vertices added, as
  // add() adds them. Its work arrays (the corners not found, with the slot where their probe
  // stopped; a record's area and volume) are kept from one batch to the next.
  uint64_t addBatchLookups(const uint8_t* rec, uint32_t count, unsigned n);
  Array<uint32_t> lookupMisses;
  Array<double> lookupArea, lookupVolume;
#endif
  // The mesh's triangle arrays sized to nt triangles, once a batch's stretch is merged.
  void endBatchAt(size_t nt);
  // add() of `count` records at rec, one by one; the records added, the failing one included.
  uint32_t addRecords(const uint8_t* rec, uint32_t count, uint64_t offset);
  // The corners of the last batch that addBatchParallel welded on threads (of its ranges or
  // pieces past the first, or all), and how many of them were the repeat of a vertex that
  // first appeared in the same batch (a sign of a file in grid order: see addBatchParallel).
  uint64_t batchCorners = 0, batchRepeats = 0;
  // The records of addBatchParallel's next batch: a small first one (32,768 records), whose
  // corners tell which way the next ones go, then 262,144 (both scale with the test grain).
  size_t parallelBatchRecords() const { return (batchCorners == 0 ? 8 : 64) * parallelGrain(4096); }
  // Welds `count` records at rec into w: local ids to tri (3 a record), attributes to attrs,
  // stored normals to normals (when not null), the figures to w. False on a non-finite
  // coordinate or when memory runs out.
  static bool weldRange(RangeWeld& w, const uint8_t* rec, uint32_t count, uint32_t* tri, uint16_t* attrs,
                        float* normals);
  // The merge of range w (weldRange of `count` records, whose local ids are at tri): its new
  // vertices join the mesh, its corners get the mesh's ids, its figures are summed. False
  // (error set) when memory runs out.
  bool mergeRange(RangeWeld& w, uint32_t* tri, uint32_t count, unsigned threads);
#endif

  // Batches of binary records: their corner hashes are computed once, up front, and used
  // to start loading the weld-table slots, so that the cache misses of a batch overlap
  // instead of running one after another. Native code prefetches; wasm has no prefetch
  // instruction, so there each slot's id is loaded (independent loads that out-of-order
  // execution overlaps) and folded into touchSink, which keeps the loads alive.
  static constexpr uint32_t kBatchRecords = 32;
  uint32_t batchHash[3 * kBatchRecords];
  uint32_t touchSink = 0;

  static inline Slot keyOf(float x, float y, float z) {
    // -0 and +0 are the same vertex: compare the bits of x + 0.0f (which maps -0 to +0).
    return Slot{bitsOf(x + 0.0f), bitsOf(y + 0.0f), bitsOf(z + 0.0f), 0};
  }
  static inline float floatLE(const uint8_t* p) {
    uint32_t w;
    std::memcpy(&w, p, 4);
    if constexpr (std::endian::native == std::endian::big) w = __builtin_bswap32(w);
    return detail::bitCast<float>(w);
  }
  // A binary record (50 bytes at r): its 12 floats (normal, then the corners) and its
  // attribute word, from little-endian.
  static inline void decodeRecord(const uint8_t* r, float f[12], uint16_t& attr) {
    std::memcpy(f, r, 48);
    std::memcpy(&attr, r + 48, 2);
    if constexpr (std::endian::native == std::endian::big) {
      for (int i = 0; i < 12; ++i) f[i] = detail::bitCast<float>(__builtin_bswap32(detail::bitCast<uint32_t>(f[i])));
      attr = __builtin_bswap16(attr);
    }
  }
  // The key hashes of the corners of `count` binary records at rec, 3 a record, to h.
  static void hashCorners(const uint8_t* rec, uint32_t count, uint32_t* h) {
    for (uint32_t r = 0; r < count; ++r, rec += 50)
      for (int c = 0; c < 3; ++c) {
        const uint8_t* q = rec + 12 + 12 * c;
        h[3 * r + c] = slotHash(keyOf(floatLE(q), floatLE(q + 4), floatLE(q + 8)));
      }
  }
  // Fills batchHash for `count` (<= kBatchRecords) records at rec; the table must exist.
  void prepareBatch(const uint8_t* rec, uint32_t count) {
    uint32_t acc = 0;
    for (uint32_t r = 0; r < count; ++r, rec += 50) {
      for (int c = 0; c < 3; ++c) {
        const uint8_t* q = rec + 12 + 12 * c;
        uint32_t h = slotHash(keyOf(floatLE(q), floatLE(q + 4), floatLE(q + 8)));
        batchHash[3 * r + c] = h;
#if !defined(__EMSCRIPTEN__)
        __builtin_prefetch(&table[h & mask]);
#endif
      }
    }
#if defined(__EMSCRIPTEN__)
    // The loads in a loop of their own: a few instructions each, so that many more of them
    // fit in the out-of-order window (and miss at the same time) than between the hashes.
    const Slot* tb = table.data();
    for (uint32_t i = 0; i < 3 * count; ++i) acc |= tb[batchHash[i] & mask].id;
#endif
    touchSink += acc;
  }

  // Returns the welded vertex id; kInvalid on allocation failure, kNonFinite for NaN/Inf.
  static constexpr uint32_t kNonFinite = kInvalid - 1;
  // hash: slotHash of the key when already known (a batch), else null. Always inlined into
  // add(), as it was before the stage split (bench/PROFILE.md).
  __attribute__((always_inline)) inline uint32_t weld(float x, float y, float z, const uint32_t* hash) {
    Slot k = keyOf(x, y, z);
    uint32_t h = hash ? *hash : slotHash(k);
    Slot& r = recent[h & (kRecent - 1)];
    if (r.x == k.x && r.y == k.y && r.z == k.z && r.id != kInvalid) return r.id;
    const uint32_t i = findSlot(table.data(), mask, k, h);
    if (table[i].id != kInvalid) {
      r = table[i];
      return r.id;
    }
    // A new vertex. Only here can a coordinate be NaN or Inf (such a key never matches a
    // stored vertex), and only here can the bounding box grow.
    if (!finiteBits(k.x) || !finiteBits(k.y) || !finiteBits(k.z)) return kNonFinite;
    const uint32_t id = appendVertex(x, y, z);
    if (id == kInvalid) return kInvalid;
    k.id = id;
    table[i] = k;
    r = k;
    if (size_t(id + 1) * 2 > table.size() && !growTable(id + 1, mesh.nTriangles())) return kInvalid;
    return id;
  }

  // The slot of key k (hash h) in an open-addressed table of mask + 1 slots: the one that
  // holds it, or the empty one where it goes.
  static inline uint32_t findSlot(const Slot* t, uint32_t mask, const Slot& k, uint32_t h) {
    uint32_t i = h & mask;
    while (t[i].id != kInvalid && !(t[i].x == k.x && t[i].y == k.y && t[i].z == k.z)) i = (i + 1) & mask;
    return i;
  }
  // Appends a vertex at the first-seen coordinates (as written), and grows the bounding box;
  // its id, or kInvalid when the array cannot grow.
  inline uint32_t appendVertex(float x, float y, float z) {
    const uint32_t id = mesh.nVertices();
    const size_t n = mesh.positions.size();
    if (n + 3 > mesh.positions.capacity() && !mesh.positions.reserve(std::max<size_t>(96, n * 2))) return kInvalid;
    (void)mesh.positions.resize(n + 3);  // capacity checked above
    float* q = mesh.positions.data() + n;
    q[0] = x;
    q[1] = y;
    q[2] = z;
    if (id == 0) {
      for (int c = 0; c < 3; ++c) mesh.bboxMin[c] = mesh.bboxMax[c] = q[c];
    } else {
      for (int c = 0; c < 3; ++c) {
        if (q[c] < mesh.bboxMin[c]) mesh.bboxMin[c] = q[c];
        if (q[c] > mesh.bboxMax[c]) mesh.bboxMax[c] = q[c];
      }
    }
    return id;
  }
  // Sizes t for forVertices vertices at most half full (mask: its size - 1), keeping the keys
  // it holds; false (nothing changed) when memory runs out.
  static bool growSlots(Array<Slot>& t, uint32_t& mask, uint32_t forVertices);

  // Opens a solid named [name, name + nameBytes) at the next triangle; color: its binary
  // header's colour (null for ASCII). False (error set to out-of-memory) when the name or
  // the lists cannot grow.
  bool beginSolid(const char* name, size_t nameBytes, const PartColor* color);
  void endSolid();

  // v: 9 floats (3 corners). n: 3 floats. Returns false on error (sticky).
  // hashes: the corners' key hashes when already computed (binary batches), else null.
  inline bool add(const float* n, const float* v, uint16_t attr, uint64_t offset, uint64_t line,
                  const uint32_t* hashes = nullptr) {
    uint32_t t = mesh.nTriangles();
    if (t >= opt.maxTriangles) {
      error = Status::error(Code::TooLarge, format("more than maxTriangles (%u) triangles", opt.maxTriangles), offset,
                            line, t);
      return false;
    }
    if (mesh.triangles.size() + 3 > mesh.triangles.capacity()) {
      size_t cap = std::max<size_t>(64, mesh.triangles.capacity() / 3 * 2);
      if (!mesh.triangles.reserve(cap * 3) || !mesh.attributes.reserve(cap) ||
          (opt.keepNormals && !mesh.normals.reserve(cap * 3))) {
        error = oom("the triangle array");
        return false;
      }
    }
    if (table.empty() && !growTable(64)) {
      error = oom("the weld table");
      return false;
    }
    uint32_t ids[3];
    for (int c = 0; c < 3; ++c) {
      ids[c] = weld(v[3 * c], v[3 * c + 1], v[3 * c + 2], hashes ? hashes + c : nullptr);
      if (ids[c] >= kNonFinite) {
        if (ids[c] == kInvalid) {
          error = oom("the vertex array");
          return false;
        }
        int k = 3 * c;
        while (finiteBits(bitsOf(v[k]))) ++k;
        error = Status::error(Code::NonFinite,
                              format("triangle %u has a non-finite coordinate (corner %d: %g)", t, c, double(v[k])),
                              offset, line, t);
        return false;
      }
    }
    size_t tn = mesh.triangles.size();
    (void)mesh.triangles.resize(tn + 3);
    std::memcpy(mesh.triangles.data() + tn, ids, sizeof ids);
    (void)mesh.attributes.push_back(attr);
    if (opt.keepNormals) {
      size_t nn = mesh.normals.size();
      (void)mesh.normals.resize(nn + 3);
      std::memcpy(mesh.normals.data() + nn, n, 3 * sizeof(float));
    }
    figures(n, v, attr);
    return true;
  }

  // The figures of a triangle (corners v, stored normal n, attribute word attr): area,
  // volume, normal mismatch and whether a word has the VisCAM bit (the bounding box grows
  // in weld()).
  inline void figures(const float* n, const float* v, uint16_t attr) {
    TriangleFigures fig = triangleFigures(v, v + 3, v + 6);
    mesh.area += fig.area;
    mesh.volume += fig.volume;
    if (normalMismatch(n, fig, v, v + 3, v + 6)) ++mesh.normalMismatches;
    if (attr & 0x8000u) anyVisCamBit = true;
  }

  // A 5-bit colour channel as 8 bits, and back: to5(c5(v)) == v for every v < 32, and
  // to5 gives the nearest 5-bit value for the other bytes.
  static uint8_t c5(unsigned v) { return uint8_t((v * 255u + 15u) / 31u); }
  static unsigned to5(uint8_t c) { return (unsigned(c) * 31u + 127u) / 255u; }
  // The VisCAM word of a colour: bit 15 set, R in bits 10-14, G 5-9, B 0-4.
  static uint16_t visCamWord(const uint8_t* rgb) {
    return uint16_t(0x8000u | to5(rgb[0]) << 10 | to5(rgb[1]) << 5 | to5(rgb[2]));
  }

  bool decodeColors();

  // Appends a warning; false (error set to out-of-memory) when the list cannot grow.
  bool addWarning(Code c, const std::string& msg, uint64_t offset = kNoOffset, uint64_t line = 0);
};
}  // namespace stltopo::detail
