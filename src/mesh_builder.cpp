// The mesh builder's cold half: reservation, the weld table's growth, solids, warnings and
// the colour decoding.
#include "mesh_builder.h"

namespace stltopo::detail {

void trim(const char*& b, const char*& e) {
  auto ws = [](unsigned char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; };
  while (b < e && ws(*b)) ++b;
  while (e > b && ws(e[-1])) --e;
}

bool Builder::reserveTriangles(uint64_t n) {
  if (n > opt.maxTriangles) n = opt.maxTriangles;
  if (n <= mesh.nTriangles()) return true;
  uint64_t v = n / 2 + 16;
  if (!mesh.triangles.reserve(size_t(n) * 3) || !mesh.attributes.reserve(size_t(n)) ||
      (opt.keepNormals && !mesh.normals.reserve(size_t(n) * 3)) || !mesh.positions.reserve(size_t(v) * 3) ||
      !growTable(uint32_t(std::min<uint64_t>(v, 1u << 30)))) {
    error = oom("the mesh arrays");
    return false;
  }
  return true;
}

void Builder::dropArrays() {
  mesh = Mesh{};
  releaseWeld();
}

bool Builder::growTable(uint32_t forVertices) {
#if STLTOPO_THREADS
  if (partitioned) {
    for (uint32_t p = 0; p < nParts(); ++p)
      if (!growPart(parts[p], forVertices / nParts() + 1)) return false;
    return true;
  }
#endif
  size_t want = 64;
  while (want < size_t(forVertices) * 2) want *= 2;
  if (want <= table.size()) return true;
  Array<Slot> t;
  if (!t.assign(want, Slot{0, 0, 0, kInvalid})) return false;
  if (recent.empty() && !recent.assign(kRecent, Slot{0, 0, 0, kInvalid})) return false;
  uint32_t m = uint32_t(want - 1);
  for (const Slot& slot : table) {
    if (slot.id == kInvalid) continue;
    uint32_t i = slotHash(slot) & m;
    while (t[i].id != kInvalid) i = (i + 1) & m;
    t[i] = slot;
  }
  table = std::move(t);
  mask = m;
  return true;
}

#if STLTOPO_THREADS
bool Builder::growPart(Part& part, uint32_t forVertices) {
  size_t want = 64;
  while (want < size_t(forVertices) * 2) want *= 2;
  if (want <= part.slots.size()) return true;
  Array<Slot> t;
  if (!t.assign(want, Slot{0, 0, 0, kInvalid})) return false;
  uint32_t m = uint32_t(want - 1);
  for (const Slot& slot : part.slots) {
    if (slot.id == kInvalid) continue;
    uint32_t i = slotHash(slot) & m;
    while (t[i].id != kInvalid) i = (i + 1) & m;
    t[i] = slot;
  }
  part.slots = std::move(t);
  part.mask = m;
  return true;
}

bool Builder::enablePartitions(unsigned threads) {
  if (partitioned) return true;
  uint32_t bits = 1;
  while (bits < kMaxPartBits && (1u << bits) < threads) ++bits;
  const uint32_t n = 1u << bits;
  // Each part sized for its share of what the single table was sized for.
  uint32_t per = uint32_t(std::min<size_t>(table.size() / 2 / n + 16, 1u << 30));
  Part fresh[1u << kMaxPartBits];
  for (uint32_t p = 0; p < n; ++p)
    if (!growPart(fresh[p], per)) return false;
  for (const Slot& slot : table) {
    if (slot.id == kInvalid) continue;
    uint32_t h = slotHash(slot);
    Part& part = fresh[h >> (32 - bits)];
    uint32_t i = h & part.mask;
    while (part.slots[i].id != kInvalid) i = (i + 1) & part.mask;
    part.slots[i] = slot;
    ++part.count;
  }
  for (uint32_t p = 0; p < n; ++p) {
    if (fresh[p].count * 2 > fresh[p].slots.size() && !growPart(fresh[p], fresh[p].count)) return false;
  }
  for (uint32_t p = 0; p < n; ++p) parts[p] = std::move(fresh[p]);
  partBits = bits;
  table.release();
  recent.release();
  mask = 0;
  partitioned = true;
  return true;
}

uint32_t Builder::weldPartitioned(float x, float y, float z) {
  Slot k = keyOf(x, y, z);
  uint32_t h = slotHash(k);
  Part& part = partOf(h);
  uint32_t i = h & part.mask;
  for (;;) {
    const Slot& slot = part.slots[i];
    if (slot.id == kInvalid) break;
    if (slot.x == k.x && slot.y == k.y && slot.z == k.z) return slot.id;
    i = (i + 1) & part.mask;
  }
  if (!finiteBits(k.x) || !finiteBits(k.y) || !finiteBits(k.z)) return kNonFinite;
  uint32_t id = appendVertex(x, y, z);
  if (id == kInvalid) return kInvalid;
  k.id = id;
  part.slots[i] = k;
  ++part.count;
  if (size_t(part.count) * 2 > part.slots.size() && !growPart(part, part.count)) return kInvalid;
  return id;
}

namespace {
inline void decodeRecord(const uint8_t* r, float f[12], uint16_t& attr) {
  std::memcpy(f, r, 48);
  std::memcpy(&attr, r + 48, 2);
  if constexpr (std::endian::native == std::endian::big) {
    for (int i = 0; i < 12; ++i) f[i] = bitCast<float>(__builtin_bswap32(bitCast<uint32_t>(f[i])));
    attr = __builtin_bswap16(attr);
  }
}
}  // namespace

Builder::BatchResult Builder::addBatchParallel(const uint8_t* rec, uint32_t count, unsigned threads) {
  const uint32_t t0 = mesh.nTriangles();
  // The one-thread path owns every case that ends in an error of the input, and ids that
  // would reach the pending bit.
  if (uint64_t(t0) + count > opt.maxTriangles || uint64_t(mesh.nVertices()) + 3 * uint64_t(count) >= kPending)
    return BatchResult::Fallback;
  if (!partitioned && !enablePartitions(threads)) {
    error = oom("the weld table");
    return BatchResult::Failed;
  }
  const size_t nc = size_t(count) * 3;
  if (!batchKeys.resize(nc) || !batchHashes.resize(nc) || !batchOrder.resize(nc) || !batchArea.resize(count) ||
      !batchVolume.resize(count)) {
    error = oom("the weld table");
    return BatchResult::Failed;
  }
  {
    size_t need = size_t(t0) + count, cap = mesh.triangles.capacity() / 3;
    if (need > cap) {
      cap = std::max<size_t>({64, cap * 2, need});
      if (!mesh.triangles.reserve(cap * 3) || !mesh.attributes.reserve(cap) ||
          (opt.keepNormals && !mesh.normals.reserve(cap * 3))) {
        error = oom("the triangle array");
        return BatchResult::Failed;
      }
    }
  }
  Slot* keys = batchKeys.data();
  uint32_t* hashes = batchHashes.data();
  double* area = batchArea.data();
  double* volume = batchVolume.data();
  uint16_t* attrs = mesh.attributes.data() + t0;  // within the capacity; the sizes are set at the end
  float* normals = opt.keepNormals ? mesh.normals.data() + size_t(t0) * 3 : nullptr;

  // The corners are split twice: by record ranges (steps 1 and 3, each thread the corners of
  // its range, in order) and by the weld's hash parts (step 2, each thread the corners whose
  // keys fall in the parts it owns). Step 1 sorts each range's corners by owner, so that step
  // 2 reads only its own, and writes each corner's result in that sorted place: no two
  // threads ever write to the same cache line, except at the ends of the ranges.
  const size_t grain = parallelGrain(4096);
  const unsigned n = std::max(1u, partsFor(threads, count, grain));
  const uint32_t shift = 32 - partBits;
  uint8_t ownerOf[1u << kMaxPartBits];
  for (uint32_t p = 0; p < nParts(); ++p) ownerOf[p] = uint8_t(p % n);
  uint32_t* order = batchOrder.data();
  // ownerStart[r][o]: where owner o's corners of range r start in `order` (from 3 * r0);
  // ownerStart[r][n] is the range's corner count.
  uint32_t ownerStart[kMaxThreads][kMaxThreads + 1];

  // 1. Decode, keys, hashes and figures, by record ranges; then the range's corners sorted
  // by owner (counting sort, stable: corner order within an owner).
  struct RangeResult {
    uint32_t mismatches = 0;
    bool visCam = false, nonFinite = false;
  } rr[kMaxThreads];
  runParts(n, [&](unsigned part) {
    size_t r0 = partBegin(count, n, part), r1 = partBegin(count, n, part + 1);
    RangeResult res;
    uint32_t* start = ownerStart[part];
    for (unsigned o = 0; o <= n; ++o) start[o] = 0;
    for (size_t r = r0; r < r1; ++r) {
      float f[12];
      uint16_t attr;
      decodeRecord(rec + 50 * r, f, attr);
      bool finite = true;
      for (int c = 0; c < 3; ++c) {
        Slot k = keyOf(f[3 + 3 * c], f[4 + 3 * c], f[5 + 3 * c]);
        finite &= finiteBits(k.x) & finiteBits(k.y) & finiteBits(k.z);
        k.id = kInvalid;
        keys[3 * r + c] = k;
        const uint32_t h = slotHash(k);
        hashes[3 * r + c] = h;
        ++start[ownerOf[h >> shift] + 1];
      }
      if (!finite) {
        res.nonFinite = true;
        break;
      }
      TriangleFigures fig = triangleFigures(f + 3, f + 6, f + 9);
      area[r] = fig.area;
      volume[r] = fig.volume;
      if (normalMismatch(f, fig)) ++res.mismatches;
      if (attr & 0x8000u) res.visCam = true;
      attrs[r] = attr;
      if (normals) std::memcpy(normals + 3 * r, f, 3 * sizeof(float));
    }
    rr[part] = res;
    if (res.nonFinite) return;
    for (unsigned o = 0; o < n; ++o) start[o + 1] += start[o];
    uint32_t cursor[kMaxThreads];
    for (unsigned o = 0; o < n; ++o) cursor[o] = start[o];
    uint32_t* mine = order + 3 * r0;
    for (size_t c = 3 * r0; c < 3 * r1; ++c) mine[cursor[ownerOf[hashes[c] >> shift]]++] = uint32_t(c);
  });
  for (unsigned p = 0; p < n; ++p)
    if (rr[p].nonFinite) return BatchResult::Fallback;

  // 2. The weld, by parts: each thread takes the corners of its parts in corner order (range
  // by range). A key seen before the batch gets its vertex id; a new key is stored with
  // kPending | the first corner that has it, which the later corners with that key get too.
  // The result replaces the corner's entry in `order`.
  bool partFailed[kMaxThreads] = {};
  runParts(n, [&](unsigned part) {
    // As in weld(): a small cache of recent keys in front of the parts (neighbouring
    // triangles share corners), and the slots of a window of corners prefetched together.
    constexpr uint32_t kWindow = 64;
    Slot recentKeys[kRecent];
    for (Slot& r : recentKeys) r.id = kInvalid;
    uint32_t window[kWindow];
    Array<uint64_t>& fresh = batchNew[part];
    fresh.clear();
    for (unsigned range = 0; range < n; ++range) {
      uint32_t* list = order + 3 * partBegin(count, n, range);
      const uint32_t i1 = ownerStart[range][part + 1];
      for (uint32_t i0 = ownerStart[range][part]; i0 < i1; i0 += kWindow) {
        uint32_t nw = 0;
        for (uint32_t i = i0; i < std::min(i1, i0 + kWindow); ++i) {
          const uint32_t c = list[i], h = hashes[c];
          const Slot& k = keys[c];
          const Slot& r = recentKeys[h & (kRecent - 1)];
          if (r.id != kInvalid && r.x == k.x && r.y == k.y && r.z == k.z) {
            list[i] = r.id;  // a key seen before (a new key in this window is not in the cache yet)
            continue;
          }
          window[nw++] = i;
#if !defined(__EMSCRIPTEN__)
          const Part& P = parts[h >> shift];
          __builtin_prefetch(&P.slots[h & P.mask]);
#endif
        }
        for (uint32_t w = 0; w < nw; ++w) {
          const uint32_t i = window[w], c = list[i], h = hashes[c];
          Slot k = keys[c];
          Slot& r = recentKeys[h & (kRecent - 1)];
          Part& P = parts[h >> shift];
          uint32_t s = h & P.mask;
          for (;;) {
            const Slot& slot = P.slots[s];
            if (slot.id == kInvalid) break;
            if (slot.x == k.x && slot.y == k.y && slot.z == k.z) {
              k.id = slot.id;
              break;
            }
            s = (s + 1) & P.mask;
          }
          if (k.id == kInvalid) {
            k.id = kPending | c;
            P.slots[s] = k;
            ++P.count;
            if (!fresh.push_back(uint64_t(s) << 32 | c)) {
              partFailed[part] = true;
              return;
            }
            if (size_t(P.count) * 2 > P.slots.size()) {
              if (!growPart(P, P.count)) {
                partFailed[part] = true;
                return;
              }
              // The part's new keys moved: find their slots again.
              for (uint64_t& e : fresh) {
                const uint32_t fc = uint32_t(e), fh = hashes[fc];
                if (&parts[fh >> shift] != &P) continue;
                const Slot& fk = keys[fc];
                uint32_t j = fh & P.mask;
                while (!(P.slots[j].x == fk.x && P.slots[j].y == fk.y && P.slots[j].z == fk.z)) j = (j + 1) & P.mask;
                e = uint64_t(j) << 32 | fc;
              }
            }
          }
          list[i] = k.id;
          r = k;
        }
      }
    }
  });
  for (unsigned p = 0; p < n; ++p)
    if (partFailed[p]) {
      error = oom("the weld table");
      return BatchResult::Failed;
    }

  // 3. The numbering, by ranges: a corner that first had its key is a new vertex, numbered in
  // corner order. (a) each range takes its results back into corner order and counts its
  // first corners; (b) they get their ids and positions; (c) the later corners of a new key
  // take its id.
  uint32_t* tri = mesh.triangles.data() + size_t(t0) * 3;
  uint32_t firsts[kMaxThreads];
  runParts(n, [&](unsigned part) {
    const size_t r0 = partBegin(count, n, part), r1 = partBegin(count, n, part + 1);
    const uint32_t* list = order + 3 * r0;
    uint32_t cursor[kMaxThreads];
    for (unsigned o = 0; o < n; ++o) cursor[o] = ownerStart[part][o];
    uint32_t k = 0;
    for (size_t c = 3 * r0; c < 3 * r1; ++c) {
      const uint32_t id = list[cursor[ownerOf[hashes[c] >> shift]]++];
      k += id == (kPending | uint32_t(c));
      tri[c] = id;
    }
    firsts[part] = k;
  });
  const uint32_t v0 = mesh.nVertices();
  uint32_t firstId[kMaxThreads];
  size_t added = 0;
  for (unsigned p = 0; p < n; ++p) firstId[p] = v0 + uint32_t(added), added += firsts[p];
  {
    const size_t have = mesh.positions.size(), need = have + 3 * added;
    if (need > mesh.positions.capacity() && !mesh.positions.reserve(std::max<size_t>({96, have * 2, need}))) {
      error = oom("the vertex array");
      return BatchResult::Failed;
    }
    (void)mesh.positions.resize(need);
  }
  float* positions = mesh.positions.data();
  struct RangeBox {
    float lo[3], hi[3];
    bool any = false;
  } boxes[kMaxThreads];
  runParts(n, [&](unsigned part) {
    const size_t r0 = partBegin(count, n, part), r1 = partBegin(count, n, part + 1);
    uint32_t id = firstId[part];
    RangeBox b;
    for (size_t c = 3 * r0; c < 3 * r1; ++c) {
      if (tri[c] != (kPending | uint32_t(c))) continue;
      float f[12];
      uint16_t attr;
      decodeRecord(rec + 50 * (c / 3), f, attr);
      const float* q = f + 3 + 3 * (c % 3);  // the first-seen coordinates, as written
      float* out = positions + 3 * size_t(id);
      for (int k = 0; k < 3; ++k) {
        out[k] = q[k];
        if (!b.any) {
          b.lo[k] = b.hi[k] = q[k];
        } else {
          if (q[k] < b.lo[k]) b.lo[k] = q[k];
          if (q[k] > b.hi[k]) b.hi[k] = q[k];
        }
      }
      b.any = true;
      tri[c] = id++;
    }
    boxes[part] = b;
  });
  // (c), and the pending slots get their vertex ids, by parts.
  runParts(n, [&](unsigned part) {
    const size_t r0 = partBegin(count, n, part), r1 = partBegin(count, n, part + 1);
    for (size_t c = 3 * r0; c < 3 * r1; ++c)
      if (tri[c] & kPending) tri[c] = tri[tri[c] & ~kPending];  // an earlier corner: numbered in (b)
    for (uint64_t e : batchNew[part]) {  // c: the new key's first corner, numbered in (b)
      const uint32_t c = uint32_t(e), i = uint32_t(e >> 32);
      partOf(hashes[c]).slots[i].id = tri[c];
    }
  });
  // The box in vertex order: the first vertex of the mesh starts it; strict comparisons keep
  // the first of equal values (-0 and +0), as appendVertex does.
  bool started = v0 > 0;
  for (unsigned p = 0; p < n; ++p) {
    const RangeBox& b = boxes[p];
    if (!b.any) continue;
    for (int k = 0; k < 3; ++k) {
      if (!started) {
        mesh.bboxMin[k] = b.lo[k], mesh.bboxMax[k] = b.hi[k];
      } else {
        if (b.lo[k] < mesh.bboxMin[k]) mesh.bboxMin[k] = b.lo[k];
        if (b.hi[k] > mesh.bboxMax[k]) mesh.bboxMax[k] = b.hi[k];
      }
    }
    started = true;
  }
  // The sums in triangle order: float64 addition is not associative.
  double a = mesh.area, v = mesh.volume;
  uint32_t mm = 0;
  for (uint32_t r = 0; r < count; ++r) a += area[r];
  for (uint32_t r = 0; r < count; ++r) v += volume[r];
  mesh.area = a;
  mesh.volume = v;
  for (unsigned p = 0; p < n; ++p) {
    mm += rr[p].mismatches;
    anyVisCamBit |= rr[p].visCam;
  }
  mesh.normalMismatches += mm;
  (void)mesh.triangles.resize((size_t(t0) + count) * 3);
  (void)mesh.attributes.resize(size_t(t0) + count);
  if (opt.keepNormals) (void)mesh.normals.resize((size_t(t0) + count) * 3);
  return BatchResult::Done;
}

#endif  // STLTOPO_THREADS

bool Builder::beginSolid(const char* name, size_t nameBytes, const PartColor* color) {
  Solid s;
  s.firstTriangle = mesh.nTriangles();
  PartColor pc = color ? *color : PartColor{};
  if (!tryAssign(s.name, name, nameBytes) || !tryPushBack(mesh.solids, std::move(s)) ||
      !tryPushBack(partColors, std::move(pc))) {
    if (mesh.solids.size() > partColors.size()) mesh.solids.pop_back();
    error = oom("the solid list");
    return false;
  }
  solidOpen = true;
  return true;
}

void Builder::endSolid() {
  if (!solidOpen) return;
  Solid& s = mesh.solids.back();
  s.triangleCount = mesh.nTriangles() - s.firstTriangle;
  solidOpen = false;
}

bool Builder::decodeColors() {
  bool magics = false;
  for (const PartColor& p : partColors) magics |= p.magics;
  ColorConvention conv =
      magics ? ColorConvention::Magics : (anyVisCamBit ? ColorConvention::VisCam : ColorConvention::None);
  mesh.colorConvention = conv;
  if (conv == ColorConvention::None) return true;
  uint32_t nt = mesh.nTriangles();
  if (!mesh.colors.assign(size_t(nt) * 3, 0) || !mesh.colorValid.assign(nt, 0)) return false;
  for (size_t s = 0; s < mesh.solids.size(); ++s) {
    const Solid& so = mesh.solids[s];
    const PartColor& pc = partColors[s];
    for (uint32_t t = so.firstTriangle; t < so.firstTriangle + so.triangleCount; ++t) {
      unsigned a = mesh.attributes[t];
      uint8_t* rgb = mesh.colors.data() + size_t(t) * 3;
      if (pc.magics) {
        if (a & 0x8000u) {
          rgb[0] = pc.rgb[0];
          rgb[1] = pc.rgb[1];
          rgb[2] = pc.rgb[2];
        } else {
          rgb[0] = c5(a & 31u);
          rgb[1] = c5((a >> 5) & 31u);
          rgb[2] = c5((a >> 10) & 31u);
        }
        mesh.colorValid[t] = 1;
      } else if (conv == ColorConvention::VisCam && (a & 0x8000u)) {
        rgb[0] = c5((a >> 10) & 31u);
        rgb[1] = c5((a >> 5) & 31u);
        rgb[2] = c5(a & 31u);
        mesh.colorValid[t] = 1;
      }
    }
  }
  return true;
}

bool Builder::addWarning(Code c, const std::string& msg, uint64_t offset, uint64_t line) {
  if (!tryPushBack(mesh.warnings, Status::error(c, msg, offset, line))) {
    error = oom("the warning list");
    return false;
  }
  return true;
}

}  // namespace stltopo::detail
