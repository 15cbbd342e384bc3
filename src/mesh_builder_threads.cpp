// The mesh builder's threaded read (addBatchParallel and its ways: ranges, pieces, lookups),
// in a file of its own so that the builder's cold half (mesh_builder.cpp) is optimized for size
// in wasm and this one for speed.
#include "mesh_builder.h"

#include "prefetch.h"

#include <atomic>
#if STLTOPO_THREADS && !defined(__EMSCRIPTEN__)
#include <thread>
#endif

namespace stltopo::detail {

namespace {
// How many batches addBatchParallel welded each way (ranges, pieces, lookups), for the tests.
std::atomic<uint64_t> gBatchesByWay[3];
}  // namespace

#if STLTOPO_THREADS
namespace {
// Starts loading the slots of `n` hashes in t (see prepareBatch).
inline void touchSlots(const Builder::Slot* t, uint32_t mask, const uint32_t* hash, uint32_t n, uint32_t& sink) {
#if defined(__EMSCRIPTEN__)
  uint32_t acc = 0;
  for (uint32_t i = 0; i < n; ++i) acc |= t[hash[i] & mask].id;
  sink += acc;
#else
  (void)sink;
  for (uint32_t i = 0; i < n; ++i) __builtin_prefetch(&t[hash[i] & mask]);
#endif
}
}  // namespace

static_assert(sizeof(Builder::RangeWeld::hash) == 3 * Builder::kBatchRecords * sizeof(uint32_t),
              "a range's group of hashes is a batch of records");

bool Builder::weldRange(RangeWeld& w, const uint8_t* rec, uint32_t count, uint32_t* tri, uint16_t* attrs,
                        float* normals) {
  w.positions.clear();
  // A table for about half as many vertices as records (a closed mesh's share), or the size
  // an earlier batch grew it to (a file in random order has more vertices per range), emptied.
  size_t want = 64;
  while (want < (size_t(count) / 2 + 16) * 2) want *= 2;
  if (w.table.size() < want && !w.table.resize(want)) return false;
  w.mask = uint32_t(w.table.size() - 1);
  for (Slot& s : w.table) s.id = kInvalid;
  if (w.recent.size() != kRecent && !w.recent.resize(kRecent)) return false;
  for (Slot& r : w.recent) r.id = kInvalid;
  if (!w.area.resize(count) || !w.volume.resize(count) || !w.positions.reserve(3 * (size_t(count) / 2 + 16)))
    return false;
  uint32_t mismatches = 0, sink = 0;
  bool visCam = false;
  for (uint32_t g = 0; g < count; g += kBatchRecords) {
    const uint32_t ng = std::min(kBatchRecords, count - g);
    hashCorners(rec + 50 * size_t(g), ng, w.hash);
    touchSlots(w.table.data(), w.mask, w.hash, 3 * ng, sink);
    for (uint32_t r = 0; r < ng; ++r) {
      const size_t t = g + r;
      float f[12];
      uint16_t attr;
      decodeRecord(rec + 50 * t, f, attr);
      const float* v = f + 3;
      for (int c = 0; c < 3; ++c) {
        Slot k = keyOf(v[3 * c], v[3 * c + 1], v[3 * c + 2]);
        const uint32_t h = w.hash[3 * r + c];
        Slot& rc = w.recent[h & (kRecent - 1)];
        if (!(rc.x == k.x && rc.y == k.y && rc.z == k.z && rc.id != kInvalid)) {
          const uint32_t i = findSlot(w.table.data(), w.mask, k, h);
          if (w.table[i].id != kInvalid) {
            rc = w.table[i];
          } else {  // a new local vertex, as in weld()
            if (!finiteBits(k.x) || !finiteBits(k.y) || !finiteBits(k.z)) return false;
            k.id = uint32_t(w.positions.size() / 3);
            if (!w.positions.push_back(v[3 * c]) || !w.positions.push_back(v[3 * c + 1]) ||
                !w.positions.push_back(v[3 * c + 2]))
              return false;
            w.table[i] = k;
            rc = k;
            if (size_t(k.id + 1) * 2 > w.table.size() && !growSlots(w.table, w.mask, k.id + 1)) return false;
          }
        }
        tri[3 * t + c] = rc.id;
      }
      attrs[t] = attr;
      if (normals) std::memcpy(normals + 3 * t, f, 3 * sizeof(float));
      const TriangleFigures fig = triangleFigures(v, v + 3, v + 6);
      w.area[t] = fig.area;
      w.volume[t] = fig.volume;
      mismatches += normalMismatch(f, fig, v, v + 3, v + 6);
      visCam |= (attr & 0x8000u) != 0;
    }
  }
  w.mismatches = mismatches;
  w.visCam = visCam;
  keepAlive(sink);
  return true;
}
bool Builder::mergeRange(RangeWeld& w, uint32_t* tri, uint32_t count, unsigned threads) {
  // The range's vertices in their local order, which is their order of first appearance.
  const uint32_t nv = uint32_t(w.positions.size() / 3);
  if (!w.map.resize(nv) || !w.hint.resize(nv)) {
    error = oom("the weld table");
    return false;
  }
  const float* q = w.positions.data();
  uint32_t* map = w.map.data();
  uint32_t* hint = w.hint.data();
  // 1. On the threads (the mesh's table is only read): each vertex's id in the mesh, or
  // kInvalid and the empty slot where its probe stopped (in groups, their slots loaded
  // together).
  const unsigned nl = partsFor(threads, nv, parallelGrain(16384));
  uint32_t sinks[kMaxThreads] = {};
  runParts(nl, [&](unsigned part) {
    const uint32_t b = uint32_t(partBegin(nv, nl, part)), e = uint32_t(partBegin(nv, nl, part + 1));
    uint32_t h[3 * kBatchRecords];
    for (uint32_t g = b; g < e; g += 3 * kBatchRecords) {
      const uint32_t ng = std::min(3 * kBatchRecords, e - g);
      for (uint32_t j = 0; j < ng; ++j) {
        const float* x = q + 3 * size_t(g + j);
        h[j] = slotHash(keyOf(x[0], x[1], x[2]));
      }
      touchSlots(table.data(), mask, h, ng, sinks[part]);
      for (uint32_t j = 0; j < ng; ++j) {
        const float* x = q + 3 * size_t(g + j);
        const uint32_t i = findSlot(table.data(), mask, keyOf(x[0], x[1], x[2]), h[j]);
        map[g + j] = table[i].id;
        hint[g + j] = i;
      }
    }
  });
  for (unsigned p = 0; p < nl; ++p) touchSink += sinks[p];
  // 2. In order, the ones not found are appended, as weld() appends them. The probe goes on
  // from where it stopped: the slots before were full and stay full (the keys inserted
  // since are other keys: a range's vertices are distinct), unless the table grew (told by its
  // size, which only grows: a grown table's address can be the old one's).
  const size_t probed = table.size();
  batchCorners += 3 * uint64_t(count);
  batchRepeats += 3 * uint64_t(count) - nv;
  for (uint32_t v = 0; v < nv; ++v) {
    if (map[v] != kInvalid) continue;
    const float* x = q + 3 * size_t(v);
    Slot k = keyOf(x[0], x[1], x[2]);
    uint32_t i = table.size() == probed ? hint[v] : slotHash(k) & mask;
    while (table[i].id != kInvalid) i = (i + 1) & mask;
    k.id = appendVertex(x[0], x[1], x[2]);
    if (k.id == kInvalid) {
      error = oom("the vertex array");
      return false;
    }
    table[i] = k;
    map[v] = k.id;
    if (size_t(k.id + 1) * 2 > table.size() && !growTable(k.id + 1)) {
      error = oom("the weld table");
      return false;
    }
  }
  // Its corners get the mesh's ids (on the threads: a map of local ids in order).
  const size_t nc = 3 * size_t(count);
  const unsigned n = partsFor(threads, nc, parallelGrain(65536));
  runParts(n, [&](unsigned part) {
    const size_t end = partBegin(nc, n, part + 1);
    for (size_t c = partBegin(nc, n, part); c < end; ++c) tri[c] = map[tri[c]];
  });
  // The sums in record order, after the ranges before it (float64 addition is not associative).
  double a = mesh.area, v = mesh.volume;
  for (uint32_t r = 0; r < count; ++r) a += w.area[r];
  for (uint32_t r = 0; r < count; ++r) v += w.volume[r];
  mesh.area = a;
  mesh.volume = v;
  mesh.normalMismatches += w.mismatches;
  anyVisCamBit |= w.visCam;
  return true;
}

uint64_t Builder::addBatchParallel(const uint8_t* rec, uint32_t count, uint64_t offset, unsigned threads) {
  const uint32_t t0 = mesh.nTriangles();
  // One by one past maxTriangles (add() has the error), and before the table exists.
  if (uint64_t(t0) + count > opt.maxTriangles || table.empty()) return 0;
  const unsigned n = partsFor(threads, count, parallelGrain(4096));
  if (n < 2) return 0;
  {  // room for the whole batch, so that add() on the first piece never moves the arrays
    const size_t need = size_t(t0) + count;
    size_t cap = mesh.triangles.capacity() / 3;
    if (need > cap) {
      cap = std::max<size_t>({64, cap * 2, need});
      if (!mesh.triangles.reserve(cap * 3) || !mesh.attributes.reserve(cap) ||
          (opt.keepNormals && !mesh.normals.reserve(cap * 3)))
        return 0;  // one by one: add() grows them as it can
    }
  }
#if defined(__EMSCRIPTEN__)
  // The threaded wasm modules weld by ranges only: pieces made their core module 1.6 kB
  // (gzipped) larger, over its download budget, for no gain we could measure in Node, and
  // lookups 2.0 kB for none either (bench/PROFILE.md, *Stop 57*).
  return addBatchRanges(rec, count, offset, n);
#else
  // Which way, from the batch before: pieces when more than 3 in 5 of its corners repeated a
  // vertex that first appeared in that batch (a file in grid order: a vertex's triangles come
  // close together, so pieces weld apart with few vertices at their seams); lookups otherwise
  // (a file in random order: a vertex's triangles are spread over the file, and past its first
  // batches most corners find their vertex in the mesh's table); ranges for the first batch,
  // a small one (parallelBatchRecords). Ranges and pieces both weld each stretch twice (in a
  // private table, then the merge's lookups), which on the 4M shuffled torus cost as much as
  // the one-thread read: there lookups made the read 0.77x the ranges' time (2 threads, pairs
  // alternated, bench/PROFILE.md *Stop 57*); grid order kept the pieces' time.
  const bool first = batchCorners == 0;
  const bool local = batchRepeats * 5 > batchCorners * 3;
  batchCorners = batchRepeats = 0;
  const unsigned way = first ? 0 : local ? 1 : 2;
  gBatchesByWay[way].fetch_add(1, std::memory_order_relaxed);
  if (way == 0) return addBatchRanges(rec, count, offset, n);
  return way == 1 ? addBatchPieces(rec, count, offset, n) : addBatchLookups(rec, count, n);
#endif
}

void Builder::endBatchAt(size_t nt) {  // within the capacity addBatchParallel reserved
  (void)mesh.triangles.resize(nt * 3);
  (void)mesh.attributes.resize(nt);
  if (opt.keepNormals) (void)mesh.normals.resize(nt * 3);
}

uint32_t Builder::addRecords(const uint8_t* rec, uint32_t count, uint64_t offset) {
  for (uint32_t r = 0; r < count; ++r) {  // the parser's one-by-one loop (BinaryParser::feed)
    if (r % kBatchRecords == 0) prepareBatch(rec + 50 * size_t(r), std::min(kBatchRecords, count - r));
    float f[12];
    uint16_t attr;
    decodeRecord(rec + 50 * size_t(r), f, attr);
    if (!add(f, f + 3, attr, offset + 50 * uint64_t(r), 0, batchHash + 3 * (r % kBatchRecords))) return r + 1;
  }
  return count;
}

uint64_t Builder::addBatchRanges(const uint8_t* rec, uint32_t count, uint64_t offset, unsigned n) {
  const uint32_t t0 = mesh.nTriangles();
  uint32_t* tri = mesh.triangles.data() + size_t(t0) * 3;
  uint16_t* attrs = mesh.attributes.data() + t0;
  float* normals = opt.keepNormals ? mesh.normals.data() + size_t(t0) * 3 : nullptr;
  const uint32_t first = uint32_t(partBegin(count, n, 1));
  uint32_t added = 0;  // of the first range, by add() (the failing record included)
  bool ok[kMaxThreads] = {};
  runParts(n, [&](unsigned part) {
    if (part == 0) {
      added = addRecords(rec, first, offset);
      return;
    }
    const size_t r0 = partBegin(count, n, part), r1 = partBegin(count, n, part + 1);
    ok[part] = weldRange(ranges[part], rec + 50 * r0, uint32_t(r1 - r0), tri + 3 * r0, attrs + r0,
                         normals ? normals + 3 * r0 : nullptr);
  });
  if (failed()) return added;
  for (unsigned part = 1; part < n; ++part) {
    const size_t r0 = partBegin(count, n, part), r1 = partBegin(count, n, part + 1);
    if (!ok[part]) return r0;  // the parser adds the rest one by one
    if (!mergeRange(ranges[part], tri + 3 * r0, uint32_t(r1 - r0), n)) return r1;
    endBatchAt(size_t(t0) + r1);
  }
  return count;
}

#if !defined(__EMSCRIPTEN__)
uint64_t Builder::addBatchPieces(const uint8_t* rec, uint32_t count, uint64_t offset, unsigned n) {
  const uint32_t t0 = mesh.nTriangles();
  uint32_t* tri = mesh.triangles.data() + size_t(t0) * 3;
  uint16_t* attrs = mesh.attributes.data() + t0;
  float* normals = opt.keepNormals ? mesh.normals.data() + size_t(t0) * 3 : nullptr;
  const size_t grain = parallelGrain(4096);
  // Pieces of records, in order: piece 0 goes through add(); every other one is welded apart
  // (weldRange, into one of `slots` RangeWelds) and merged, in order, once welded
  // (mergeRange). Whichever thread is free welds the next piece or merges what is ready, so
  // that the merges, which must run one after another, overlap the welds. A thread takes a
  // RangeWeld before a piece, so the first piece not merged always has one, and the merges
  // always progress. Which thread does what changes nothing in the mesh: a piece's new
  // vertices join it in their order of first appearance whatever the split.
  const unsigned pieces = unsigned(std::min<size_t>({size_t(kPiecesPerThread) * n, count / grain, kMaxPieces}));
  const unsigned slots = std::min<unsigned>({pieces - 1, n + 2, 64});
  auto pieceBegin = [&](uint32_t j) { return uint32_t(partBegin(count, pieces, j)); };
  std::atomic<int> state[kMaxPieces];  // 0: being welded; 1: welded; 2: stopped (weldRange failed)
  uint8_t slotOf[kMaxPieces];
  for (unsigned j = 0; j < pieces; ++j) state[j].store(j == 0 ? 1 : 0, std::memory_order_relaxed);
  std::atomic<uint32_t> nextWeld{1}, nextMerge{0};
  std::atomic<uint64_t> freeSlots{slots == 64 ? ~uint64_t(0) : (uint64_t(1) << slots) - 1};
  std::atomic<bool> merging{false}, stop{false};
  uint64_t result = count;  // the records added; written by the merger only
  // Merges the pieces that are ready, in order; true when it merged one. One thread at a time
  // merges (`merging`). A welder that finds it taken leaves its piece to the merger, which
  // looks at the next piece's state again after letting go (seq_cst: the welder stored the
  // state before it tried, so the merger's second look sees it).
  auto tryMerge = [&]() {
    bool progressed = false;
    for (;;) {
      if (merging.exchange(true)) return progressed;
      uint32_t j = nextMerge.load(std::memory_order_relaxed);
      for (; j < pieces && !stop.load(std::memory_order_relaxed); nextMerge.store(++j)) {
        const uint32_t r0 = pieceBegin(j), r1 = pieceBegin(j + 1);
        if (j == 0) {
          const uint32_t added = addRecords(rec, r1, offset);
          if (failed()) {
            result = added;
            stop.store(true);
          }
          progressed = true;
          continue;
        }
        const int st = state[j].load();
        if (st == 0) break;
        if (st == 2) {  // the parser adds the rest one by one
          result = r0;
          stop.store(true);
          break;
        }
        if (!mergeRange(ranges[slotOf[j]], tri + 3 * size_t(r0), r1 - r0, 1)) {
          result = r1;
          stop.store(true);
          break;
        }
        endBatchAt(size_t(t0) + r1);
        freeSlots.fetch_or(uint64_t(1) << slotOf[j]);
        progressed = true;
      }
      merging.store(false);
      if (stop.load() || j >= pieces || state[j].load() == 0) return progressed;
    }
  };
  runParts(n, [&](unsigned) {
    for (;;) {
      const bool merged = tryMerge();
      if (stop.load() || nextWeld.load() >= pieces) break;
      uint64_t free = freeSlots.load();
      if (free == 0) {  // every RangeWeld holds a piece: the merges must catch up first
        if (!merged) std::this_thread::yield();
        continue;
      }
      const unsigned s = unsigned(std::countr_zero(free));
      if (!freeSlots.compare_exchange_weak(free, free & ~(uint64_t(1) << s))) continue;
      const uint32_t j = nextWeld.fetch_add(1);
      if (j >= pieces) {
        freeSlots.fetch_or(uint64_t(1) << s);
        break;
      }
      slotOf[j] = uint8_t(s);
      const uint32_t r0 = pieceBegin(j), r1 = pieceBegin(j + 1);
      const bool ok = weldRange(ranges[s], rec + 50 * size_t(r0), r1 - r0, tri + 3 * size_t(r0), attrs + r0,
                                normals ? normals + 3 * size_t(r0) : nullptr);
      state[j].store(ok ? 1 : 2);
    }
    tryMerge();
  });
  return result;
}

uint64_t Builder::addBatchLookups(const uint8_t* rec, uint32_t count, unsigned n) {
  if (!lookupMisses.resize(6 * size_t(count)) || !lookupArea.resize(count) || !lookupVolume.resize(count))
    return 0;  // one by one
  const uint32_t t0 = mesh.nTriangles();
  uint32_t* tri = mesh.triangles.data() + size_t(t0) * 3;
  uint16_t* attrs = mesh.attributes.data() + t0;
  float* normals = opt.keepNormals ? mesh.normals.data() + size_t(t0) * 3 : nullptr;
  uint32_t* misses = lookupMisses.data();  // part p's from 6 * partBegin(p): (corner, slot) pairs
  double* area = lookupArea.data();
  double* volume = lookupVolume.data();
  const Slot* tb = table.data();
  const uint32_t m = mask;
  uint32_t mismatches[kMaxThreads] = {}, sinks[kMaxThreads] = {}, missed[kMaxThreads] = {};
  bool visCam[kMaxThreads] = {}, nonFinite[kMaxThreads] = {};
  // 1. On the threads, by records: each corner's id in the mesh, or, when it is not there, the
  // corner and the empty slot where its probe stopped on the part's list of misses (in corner
  // order); the attributes, normals and figures.
  runParts(n, [&](unsigned part) {
    const uint32_t b = uint32_t(partBegin(count, n, part)), e = uint32_t(partBegin(count, n, part + 1));
    uint32_t h[3 * kBatchRecords];
    uint32_t mm = 0, nm = 0;
    uint32_t* list = misses + 6 * size_t(b);
    bool vc = false, bad = false;
    for (uint32_t g = b; g < e; g += kBatchRecords) {
      const uint32_t ng = std::min(kBatchRecords, e - g);
      hashCorners(rec + 50 * size_t(g), ng, h);
      touchSlots(tb, m, h, 3 * ng, sinks[part]);
      for (uint32_t r = 0; r < ng; ++r) {
        const size_t t = g + r;
        float f[12];
        uint16_t attr;
        decodeRecord(rec + 50 * t, f, attr);
        const float* v = f + 3;
        for (int c = 0; c < 3; ++c) {
          const Slot k = keyOf(v[3 * c], v[3 * c + 1], v[3 * c + 2]);
          bad |= !finiteBits(k.x) || !finiteBits(k.y) || !finiteBits(k.z);
          const uint32_t i = findSlot(tb, m, k, h[3 * r + c]);
          const uint32_t id = tb[i].id;
          tri[3 * t + c] = id;
          if (id == kInvalid) {
            list[2 * nm] = uint32_t(3 * t + c);
            list[2 * nm + 1] = i;
            ++nm;
          }
        }
        attrs[t] = attr;
        if (normals) std::memcpy(normals + 3 * t, f, 3 * sizeof(float));
        const TriangleFigures fig = triangleFigures(v, v + 3, v + 6);
        area[t] = fig.area;
        volume[t] = fig.volume;
        mm += normalMismatch(f, fig, v, v + 3, v + 6);
        vc |= (attr & 0x8000u) != 0;
      }
    }
    mismatches[part] = mm;
    missed[part] = nm;
    visCam[part] = vc;
    nonFinite[part] = bad;
  });
  uint32_t sink = 0;
  for (unsigned p = 0; p < n; ++p) {
    sink += sinks[p];
    if (nonFinite[p]) return 0;  // one by one, for add()'s error at the first such record
  }
  touchSink += sink;
  // 2. On the caller, in corner order: the corners not found, looked up again from where
  // their probe stopped (the slots before were full then and stay full: a key added since
  // went to the first empty slot on its path, and the table has not grown since, or the probe
  // starts over; see mergeRange), and the new vertices added, as weld() adds them.
  const size_t probed = table.size();
  constexpr uint32_t kMissAhead = 16;
  uint64_t nMissed = 0, added = 0;
  for (unsigned p = 0; p < n; ++p) {
    const uint32_t* list = misses + 6 * partBegin(count, n, p);
    const uint32_t nm = missed[p];
    nMissed += nm;
    for (uint32_t j = 0; j < nm; ++j) {
      if (j + kMissAhead < nm) __builtin_prefetch(&table[list[2 * (j + kMissAhead) + 1]]);
      const uint32_t c = list[2 * j];
      const uint8_t* q = rec + 50 * size_t(c / 3) + 12 + 12 * (c % 3);
      const float x = floatLE(q), y = floatLE(q + 4), z = floatLE(q + 8);
      Slot k = keyOf(x, y, z);
      uint32_t i = table.size() == probed ? list[2 * j + 1] : slotHash(k) & mask;
      while (table[i].id != kInvalid && !(table[i].x == k.x && table[i].y == k.y && table[i].z == k.z))
        i = (i + 1) & mask;
      if (table[i].id != kInvalid) {
        tri[c] = table[i].id;
        continue;
      }
      ++added;
      k.id = appendVertex(x, y, z);
      if (k.id == kInvalid ||
          (table[i] = k, size_t(k.id + 1) * 2 > table.size() && !growTable(k.id + 1, t0 + c / 3))) {
        error = oom(k.id == kInvalid ? "the vertex array" : "the weld table");
        return c / 3 + 1;
      }
      tri[c] = k.id;
    }
  }
  batchCorners += 3 * uint64_t(count);
  batchRepeats += nMissed - added;
  // The sums in record order (float64 addition is not associative).
  double a = mesh.area, v = mesh.volume;
  for (uint32_t r = 0; r < count; ++r) a += area[r];
  for (uint32_t r = 0; r < count; ++r) v += volume[r];
  mesh.area = a;
  mesh.volume = v;
  for (unsigned p = 0; p < n; ++p) {
    mesh.normalMismatches += mismatches[p];
    anyVisCamBit |= visCam[p];
  }
  endBatchAt(size_t(t0) + count);
  return count;
}
#endif  // !__EMSCRIPTEN__
#endif  // STLTOPO_THREADS

}  // namespace stltopo::detail

namespace stltopo {
uint64_t threadedReadBatchesForTesting(unsigned way) {
  return way < 3 ? detail::gBatchesByWay[way].load(std::memory_order_relaxed) : 0;
}
}  // namespace stltopo
