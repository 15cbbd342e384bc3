// Streaming STL reader: binary and ASCII parsers fed side by side, an exact
// weld while triangles arrive, and the detection rule applied at the end.
#include <algorithm>
#include <bit>
#include <cerrno>
#include <cstdarg>
#include <clocale>
#include <cmath>
#include <cstdio>
#include <locale.h>

#include "detail.h"
#include "stltopo.h"

namespace stltopo {
namespace {

constexpr uint64_t kHeaderBytes = 84;
constexpr uint64_t kRecordBytes = 50;

using detail::cLocale;
using detail::makeStatus;
using detail::format;

Status oom(const char* what) { return makeStatus(Code::OutOfMemory, std::string("could not allocate ") + what); }

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

std::string trimmed(const std::string& s) {
  size_t b = 0, e = s.size();
  auto ws = [](unsigned char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; };
  while (b < e && ws(s[b])) ++b;
  while (e > b && ws(s[e - 1])) --e;
  return s.substr(b, e - b);
}

// Per binary part: the header's colour information.
struct PartColor {
  bool magics = false;
  uint8_t rgb[3] = {0, 0, 0};
};

// ---------------------------------------------------------------------------
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

  explicit Builder(const ReadOptions& o) : opt(o) {}

  bool failed() const { return !error.ok(); }

  bool reserveTriangles(uint64_t n) {
    if (n > opt.maxTriangles) n = opt.maxTriangles;
    if (n <= mesh.nTriangles()) return true;
    uint64_t v = n / 2 + 16;
    if (!mesh.triangles.reserve(size_t(n) * 3) || !mesh.attributes.reserve(size_t(n)) ||
        (opt.keepNormals && !mesh.normals.reserve(size_t(n) * 3)) ||
        !mesh.positions.reserve(size_t(v) * 3) || !growTable(uint32_t(std::min<uint64_t>(v, 1u << 30)))) {
      error = oom("the mesh arrays");
      return false;
    }
    return true;
  }

  void releaseWeld() {
    table.release();
    recent.release();
  }
  void dropArrays() {
    mesh = Mesh{};
    releaseWeld();
  }

  static inline uint32_t slotHash(const Slot& k) { return hash3(k.x, k.y, k.z); }

  bool growTable(uint32_t forVertices) {
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
  // hash: slotHash of the key when already known (a batch), else null.
  inline uint32_t weld(float x, float y, float z, const uint32_t* hash) {
    Slot k = keyOf(x, y, z);
    uint32_t h = hash ? *hash : slotHash(k);
    Slot& r = recent[h & (kRecent - 1)];
    if (r.x == k.x && r.y == k.y && r.z == k.z && r.id != kInvalid) return r.id;
    uint32_t i = h & mask;
    for (;;) {
      const Slot& slot = table[i];
      if (slot.id == kInvalid) break;
      if (slot.x == k.x && slot.y == k.y && slot.z == k.z) {
        r = slot;
        return slot.id;
      }
      i = (i + 1) & mask;
    }
    // A new vertex. Only here can a coordinate be NaN or Inf (such a key never matches a
    // stored vertex), and only here can the bounding box grow.
    if (!finiteBits(k.x) || !finiteBits(k.y) || !finiteBits(k.z)) return kNonFinite;
    uint32_t id = mesh.nVertices();
    size_t n = mesh.positions.size();
    if (n + 3 > mesh.positions.capacity() && !mesh.positions.reserve(std::max<size_t>(96, n * 2)))
      return kInvalid;
    (void)mesh.positions.resize(n + 3);  // capacity checked above
    float* q = mesh.positions.data() + n;  // the first-seen coordinates, as written
    q[0] = x; q[1] = y; q[2] = z;
    if (id == 0) {
      for (int c = 0; c < 3; ++c) mesh.bboxMin[c] = mesh.bboxMax[c] = q[c];
    } else {
      for (int c = 0; c < 3; ++c) {
        if (q[c] < mesh.bboxMin[c]) mesh.bboxMin[c] = q[c];
        if (q[c] > mesh.bboxMax[c]) mesh.bboxMax[c] = q[c];
      }
    }
    k.id = id;
    table[i] = k;
    r = k;
    if (size_t(id + 1) * 2 > table.size() && !growTable(id + 1)) return kInvalid;
    return id;
  }

  void beginSolid(std::string name, const PartColor* color) {
    Solid s;
    s.name = std::move(name);
    s.firstTriangle = mesh.nTriangles();
    mesh.solids.push_back(std::move(s));
    partColors.push_back(color ? *color : PartColor{});
    solidOpen = true;
  }
  void endSolid() {
    if (!solidOpen) return;
    Solid& s = mesh.solids.back();
    s.triangleCount = mesh.nTriangles() - s.firstTriangle;
    solidOpen = false;
  }

  // v: 9 floats (3 corners). n: 3 floats. Returns false on error (sticky).
  // hashes: the corners' key hashes when already computed (binary batches), else null.
  inline bool add(const float* n, const float* v, uint16_t attr, uint64_t offset, uint64_t line,
                  const uint32_t* hashes = nullptr) {
    uint32_t t = mesh.nTriangles();
    if (t >= opt.maxTriangles) {
      error = makeStatus(Code::TooLarge, format("more than maxTriangles (%u) triangles", opt.maxTriangles), offset, line, t);
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
        error = makeStatus(Code::NonFinite,
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
    // Figures: area, volume, normal mismatch (the bounding box grows in weld()).
    double ax = v[0], ay = v[1], az = v[2], bx = v[3], by = v[4], bz = v[5], cx = v[6], cy = v[7], cz = v[8];
    double ux = bx - ax, uy = by - ay, uz = bz - az, wx = cx - ax, wy = cy - ay, wz = cz - az;
    double nx = uy * wz - uz * wy, ny = uz * wx - ux * wz, nz = ux * wy - uy * wx;
    mesh.area += 0.5 * std::sqrt(nx * nx + ny * ny + nz * nz);
    mesh.volume += (ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx)) / 6.0;
    if (n[0] != 0.0f || n[1] != 0.0f || n[2] != 0.0f) {
      double d = double(n[0]) * nx + double(n[1]) * ny + double(n[2]) * nz;
      if (d < 0) ++mesh.normalMismatches;
    }
    if (attr & 0x8000u) anyVisCamBit = true;
    return true;
  }

  static uint8_t c5(unsigned v) { return uint8_t((v * 255u + 15u) / 31u); }

  bool decodeColors() {
    bool magics = false;
    for (const PartColor& p : partColors) magics |= p.magics;
    ColorConvention conv = magics ? ColorConvention::Magics
                                  : (anyVisCamBit ? ColorConvention::VisCam : ColorConvention::None);
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
            rgb[0] = pc.rgb[0]; rgb[1] = pc.rgb[1]; rgb[2] = pc.rgb[2];
          } else {
            rgb[0] = c5(a & 31u); rgb[1] = c5((a >> 5) & 31u); rgb[2] = c5((a >> 10) & 31u);
          }
          mesh.colorValid[t] = 1;
        } else if (conv == ColorConvention::VisCam && (a & 0x8000u)) {
          rgb[0] = c5((a >> 10) & 31u); rgb[1] = c5((a >> 5) & 31u); rgb[2] = c5(a & 31u);
          mesh.colorValid[t] = 1;
        }
      }
    }
    return true;
  }

  void addWarning(Code c, std::string msg, uint64_t offset = kNoOffset, uint64_t line = 0) {
    mesh.warnings.push_back(makeStatus(c, std::move(msg), offset, line));
  }
};

// ---------------------------------------------------------------------------
// Binary parser (handles concatenated parts).
struct BinaryParser {
  Builder b;
  uint8_t header[kHeaderBytes];
  uint32_t headerHave = 0;
  uint8_t rec[kRecordBytes];
  uint32_t recHave = 0;
  bool inRecords = false;
  uint32_t partIndex = 0;      // number of parts whose header has been read
  uint64_t partStart = 0;      // offset of the current part's header
  uint32_t partCount = 0;      // triangles promised by the current part
  uint32_t partDone = 0;
  uint64_t partFirst = 0;      // triangles read before the current part
  uint64_t offset = 0;         // bytes consumed
  bool skipping = false;       // over maxTriangles or after a content error: count bytes only
  uint64_t skipNeeded = 0;     // bytes needed to complete the current part when skipping
  Status contentError;         // e.g. non-finite: reported unless the file is also truncated

  explicit BinaryParser(const ReadOptions& o) : b(o) {}

  void startPart() {
    uint32_t n;
    std::memcpy(&n, header + 80, 4);
    if constexpr (std::endian::native == std::endian::big) n = __builtin_bswap32(n);
    partCount = n;
    partDone = 0;
    partFirst = b.mesh.nTriangles();
    ++partIndex;
    size_t len = 0;
    while (len < 80 && header[len] != 0) ++len;
    std::string name = trimmed(std::string(reinterpret_cast<const char*>(header), len));
    PartColor pc;
    static const char kColor[] = "COLOR=";
    for (size_t i = 0; i + 6 + 4 <= 80; ++i) {
      if (std::memcmp(header + i, kColor, 6) == 0) {
        pc.magics = true;
        pc.rgb[0] = header[i + 6]; pc.rgb[1] = header[i + 7]; pc.rgb[2] = header[i + 8];
        break;
      }
    }
    b.beginSolid(std::move(name), &pc);
    uint64_t total = uint64_t(b.mesh.nTriangles()) + n;
    if (total > b.opt.maxTriangles) {
      skipping = true;
      skipNeeded = kHeaderBytes + kRecordBytes * uint64_t(n);
      return;
    }
    // Reserve only what the known input size can hold.
    if (b.opt.sizeHint > partStart + kHeaderBytes) {
      uint64_t fits = (b.opt.sizeHint - partStart - kHeaderBytes) / kRecordBytes;
      b.reserveTriangles(uint64_t(b.mesh.nTriangles()) + std::min<uint64_t>(n, fits));
    }
    inRecords = n > 0;
    if (!inRecords) finishPart();
  }

  void finishPart() {
    b.endSolid();
    inRecords = false;
    headerHave = 0;
    partStart = offset;
  }

  inline void record(const uint8_t* r, uint64_t recOffset, const uint32_t* hashes = nullptr) {
    float f[12];
    std::memcpy(f, r, 48);
    uint16_t attr;
    std::memcpy(&attr, r + 48, 2);
    if constexpr (std::endian::native == std::endian::big) {
      for (float& x : f) x = detail::bitCast<float>(__builtin_bswap32(detail::bitCast<uint32_t>(x)));
      attr = __builtin_bswap16(attr);
    }
    if (!b.add(f, f + 3, attr, recOffset, 0, hashes)) {
      // A size problem (truncated) outranks a content problem found before it, so keep
      // counting bytes to learn whether the part is complete; drop the arrays.
      contentError = b.error;
      b.error = Status{};
      b.dropArrays();
      skipping = true;
      skipNeeded = kHeaderBytes + kRecordBytes * uint64_t(partCount);
    }
  }

  void feed(const uint8_t* p, size_t n) {
    size_t i = 0;
    while (i < n && !b.failed()) {
      if (skipping) {
        uint64_t have = offset - partStart;
        uint64_t take = std::min<uint64_t>(n - i, skipNeeded > have ? skipNeeded - have : 0);
        if (take == 0) take = n - i;  // beyond: the outcome (too-large) is known; just count
        offset += take;
        i += size_t(take);
        continue;
      }
      if (!inRecords) {
        uint32_t take = uint32_t(std::min<size_t>(kHeaderBytes - headerHave, n - i));
        std::memcpy(header + headerHave, p + i, take);
        headerHave += take;
        i += take;
        offset += take;
        if (headerHave == kHeaderBytes) startPart();
        continue;
      }
      if (recHave > 0) {
        uint32_t take = uint32_t(std::min<size_t>(kRecordBytes - recHave, n - i));
        std::memcpy(rec + recHave, p + i, take);
        recHave += take;
        i += take;
        offset += take;
        if (recHave == kRecordBytes) {
          recHave = 0;
          record(rec, offset - kRecordBytes);
          if (skipping) continue;
          if (++partDone == partCount) finishPart();
        }
        continue;
      }
      // Fast path: whole records straight from the input.
      uint64_t left = uint64_t(partCount - partDone);
      uint64_t whole = std::min<uint64_t>(left, (n - i) / kRecordBytes);
      constexpr uint64_t kBatch = Builder::kBatchRecords;
      bool hashed = false;
      for (uint64_t k = 0; k < whole && !skipping; ++k) {
        if (k % kBatch == 0) {
          hashed = !b.table.empty();
          if (hashed) b.prepareBatch(p + i, uint32_t(std::min<uint64_t>(kBatch, whole - k)));
        }
        record(p + i, offset, hashed ? b.batchHash + 3 * (k % kBatch) : nullptr);
        i += kRecordBytes;
        offset += kRecordBytes;
        ++partDone;
      }
      if (skipping) continue;
      if (partDone == partCount) {
        finishPart();
        continue;
      }
      if (i < n) {
        uint32_t take = uint32_t(n - i);  // < 50
        std::memcpy(rec, p + i, take);
        recHave = take;
        i += take;
        offset += take;
      }
    }
  }

  // Outcome at end of input.
  enum class End { Exact, Trailing, Error, TooShort };
  End end(Status& st) {
    if (b.failed()) { st = b.error; return End::Error; }
    if (partIndex == 0) return End::TooShort;  // < 84 bytes: no header at all
    if (skipping) {
      uint64_t needBytes = partStart + skipNeeded;
      if (offset < needBytes) {
        st = truncated(needBytes);
      } else if (!contentError.ok()) {
        st = contentError;
      } else {
        st = makeStatus(Code::TooLarge,
                        format("the header promises %u triangles, more than maxTriangles (%u)", partCount, b.opt.maxTriangles),
                        partStart + 80);
      }
      return End::Error;
    }
    if (inRecords) {
      st = truncated(partStart + kHeaderBytes + kRecordBytes * uint64_t(partCount));
      return End::Error;
    }
    if (headerHave > 0) return End::Trailing;  // < 84 bytes after the last part
    return End::Exact;
  }

  Status truncated(uint64_t needBytes) {
    // The first incomplete triangle: triangles before this part plus the complete records.
    uint64_t body = offset - partStart > kHeaderBytes ? offset - partStart - kHeaderBytes : 0;
    uint32_t tri = uint32_t(std::min<uint64_t>(partFirst + body / kRecordBytes, kInvalid - 1));
    std::string part = partIndex > 1 ? format("part %u (header at offset %llu): ", partIndex, (unsigned long long)partStart) : std::string();
    return makeStatus(Code::Truncated,
                      format("%sthe header promises %u triangles (%llu bytes) but the file has %llu bytes; "
                          "data stops at offset %llu, inside triangle %u",
                          part.c_str(), partCount, (unsigned long long)needBytes, (unsigned long long)offset,
                          (unsigned long long)offset, tri),
                      offset, 0, tri);
  }
};

// ---------------------------------------------------------------------------
// Helpers for the ASCII parser's fast paths.
constexpr uint64_t kOnes = 0x0101010101010101ull;
constexpr uint64_t kHigh = 0x8080808080808080ull;

inline bool isSpace(uint8_t c) { return c == ' ' || unsigned(c - '\t') <= unsigned('\r' - '\t'); }

// 8 bytes as a word, the first in the lowest bits.
inline uint64_t load8(const void* s) {
  uint64_t w;
  std::memcpy(&w, s, 8);
  if constexpr (std::endian::native == std::endian::big) w = __builtin_bswap64(w);
  return w;
}
// 0x80 in each byte of w that ends a token (a byte <= 0x20 or 0x7F), else 0; exact per
// byte (no carry crosses a byte).
inline uint64_t tokenStops(uint64_t w) {
  uint64_t low = w & ~kHigh;
  uint64_t below21 = ~(low + (0x80 - 0x21) * kOnes) & ~w & kHigh;  // low + 0x5F < 0x80 iff low < 0x21
  uint64_t del = (low + kOnes) & ~w & kHigh;                        // low + 1 == 0x80 iff low == 0x7F
  return below21 | del;
}

// A keyword as one word, for keywordAt(): lower case, at most 8 bytes.
struct Keyword {
  uint64_t word, mask;
  unsigned len;
};
constexpr Keyword keyword(const char* s) {
  Keyword k{0, 0, 0};
  for (; s[k.len]; ++k.len) k.word |= uint64_t(uint8_t(s[k.len])) << (8 * k.len);
  k.mask = k.len == 8 ? ~uint64_t(0) : (uint64_t(1) << (8 * k.len)) - 1;
  return k;
}
constexpr Keyword kFacet = keyword("facet"), kNormal = keyword("normal"), kOuter = keyword("outer"),
                  kLoop = keyword("loop"), kVertex = keyword("vertex"), kEndloop = keyword("endloop"),
                  kEndfacet = keyword("endfacet");
// Whether kw is at q as AsciiParser::ieq() compares ((byte | 0x20) == letter), followed
// by whitespace. Reads 9 bytes.
inline bool keywordAt(const uint8_t* q, const Keyword& kw) {
  return ((load8(q) | 0x20 * kOnes) & kw.mask) == kw.word && isSpace(q[kw.len]);
}

// Reads the digits at q (stopping at limit) into m; returns their end. Past 19 digits m
// wraps around: the caller checks the count.
inline const char* digits(const char* q, const char* limit, uint64_t& m) {
  for (; q < limit && unsigned(*q - '0') < 10; ++q) m = m * 10 + unsigned(*q - '0');
  return q;
}

// The fast path of parseFloat, for the plain decimal at s: [sign] digits [. digits]
// [e [sign] digits] with at most 19 digits (leading zeros included) and a small exponent,
// e.g. "3.99992108", "-0.5", "1.234567e+01". Reads nothing at or past limit. Returns the
// end of the number (the caller checks that the token ends there), or nullptr when it
// cannot decide (the caller then takes the general path).
inline const char* parseDecimal(const char* s, const char* limit, float& out) {
  const char* q = s;
  bool neg = false;
  if (q < limit && (*q == '-' || *q == '+')) neg = *q++ == '-';
  uint64_t m = 0;
  const char* intAt = q;
  q = digits(q, limit, m);
  int nDigits = int(q - intAt), fracDigits = 0;
  if (q < limit && *q == '.') {
    const char* fracAt = ++q;
    q = digits(q, limit, m);
    fracDigits = int(q - fracAt);
    nDigits += fracDigits;
  }
  if (nDigits == 0 || nDigits > 19) return nullptr;
  int e = 0;
  if (q < limit && (*q | 0x20) == 'e') {
    ++q;
    bool eneg = false;
    if (q < limit && (*q == '-' || *q == '+')) eneg = *q++ == '-';
    const char* expAt = q;
    for (; q < limit && unsigned(*q - '0') < 10 && q - expAt < 4; ++q) e = e * 10 + (*q - '0');
    if (q == expAt) return nullptr;
    if (eneg) e = -e;
  }
  if (m == 0) {
    out = neg ? -0.0f : 0.0f;
    return q;
  }
  // m * 10^ex in double, with a multiplication (a division is much slower): m is exact,
  // 10^ex is rounded when ex < 0, and so is the product, so d is within 2 units in the last
  // place (ulp) of the exact value. The float nearest to d is then the float nearest to the
  // exact value unless d lies within those 2 ulp of a halfway point between two floats,
  // where the low 29 bits of d (those a float drops) read 0x10000000: there, and for the
  // rest (m >= 2^53, |ex| > 22), take the general path.
  static constexpr double kPow10[45] = {1e-22, 1e-21, 1e-20, 1e-19, 1e-18, 1e-17, 1e-16, 1e-15, 1e-14,
                                        1e-13, 1e-12, 1e-11, 1e-10, 1e-9,  1e-8,  1e-7,  1e-6,  1e-5,
                                        1e-4,  1e-3,  1e-2,  1e-1,  1e0,   1e1,   1e2,   1e3,   1e4,
                                        1e5,   1e6,   1e7,   1e8,   1e9,   1e10,  1e11,  1e12,  1e13,
                                        1e14,  1e15,  1e16,  1e17,  1e18,  1e19,  1e20,  1e21,  1e22};
  int ex = e - fracDigits;
  if (m >= (1ull << 53) || ex < -22 || ex > 22) return nullptr;
  double d = double(m) * kPow10[ex + 22];
  uint64_t dropped = detail::bitCast<uint64_t>(d) & 0x1FFFFFFFull;
  if (dropped - (0x10000000ull - 4) <= 8) return nullptr;
  float f = float(d);
  out = neg ? -f : f;
  return q;
}

// Parses a whole token as a float exactly as strtof does in the C locale.
bool parseFloat(const char* s, size_t len, float& out) {
  if (len > kMaxNumberChars) return false;  // also for the fast path: any chunking agrees
  {
    float f = 0;
    if (parseDecimal(s, s + len, f) == s + len) {
      out = f;
      return true;
    }
  }
  // What parseDecimal leaves (more digits, larger exponents, near ties, other syntax):
  // [sign] digits [. digits] [e [sign] digits] with trailing zeros of the mantissa moved
  // into the exponent, through the exact float and double fast paths, then strtof.
  {
    size_t i = 0;
    bool neg = false;
    if (i < len && (s[i] == '-' || s[i] == '+')) neg = s[i++] == '-';
    uint64_t m = 0;
    int digits = 0, fracDigits = 0;
    bool overflow = false;
    while (i < len && unsigned(s[i] - '0') < 10) {
      if (m < 100000000000000000ull) m = m * 10 + unsigned(s[i] - '0'); else overflow = true;
      ++digits; ++i;
    }
    if (i < len && s[i] == '.') {
      ++i;
      while (i < len && unsigned(s[i] - '0') < 10) {
        if (m < 100000000000000000ull) m = m * 10 + unsigned(s[i] - '0'); else overflow = true;
        ++digits; ++fracDigits; ++i;
      }
    }
    int e = 0;
    bool ok = digits > 0;
    if (ok && i < len && (s[i] == 'e' || s[i] == 'E')) {
      ++i;
      bool eneg = false;
      if (i < len && (s[i] == '-' || s[i] == '+')) eneg = s[i++] == '-';
      int ed = 0;
      while (i < len && unsigned(s[i] - '0') < 10) {
        if (e < 10000) e = e * 10 + (s[i] - '0');
        ++ed; ++i;
      }
      if (ed == 0) ok = false;
      if (eneg) e = -e;
    }
    if (ok && i == len && !overflow) {
      int ex = e - fracDigits;
      // Strip trailing zeros of the mantissa into the exponent.
      while (m != 0 && m % 10 == 0 && ex < 0) { m /= 10; ++ex; }
      if (m == 0) { out = neg ? -0.0f : 0.0f; return true; }
      static const float kPow10[] = {1e0f, 1e1f, 1e2f, 1e3f, 1e4f, 1e5f, 1e6f, 1e7f, 1e8f, 1e9f, 1e10f};
      if (m <= (1u << 24) && ex >= -10 && ex <= 10) {
        float f = float(m);
        f = ex < 0 ? f / kPow10[-ex] : f * kPow10[ex];
        out = neg ? -f : f;
        return true;
      }
      // Clinger's fast path, as in parseDecimal.
      static const double kPow10d[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                       1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
      if (m < (1ull << 53) && ex >= -22 && ex <= 22) {
        double d = ex < 0 ? double(m) / kPow10d[-ex] : double(m) * kPow10d[ex];
        if ((detail::bitCast<uint64_t>(d) & 0x1FFFFFFFull) != 0x10000000ull) {
          float f = float(d);
          out = neg ? -f : f;
          return true;
        }
      }
    }
  }
  // General path: the C library's strtof in the "C" locale.
  char buf[kMaxNumberChars + 1];
  std::memcpy(buf, s, len);
  buf[len] = 0;
  char* end = nullptr;
  float f = strtof_l(buf, &end, cLocale());
  if (end != buf + len || len == 0) return false;
  out = f;
  return true;
}

// ---------------------------------------------------------------------------
// ASCII parser: a token state machine that survives any chunking.
struct AsciiParser {
  enum State : uint8_t {
    ExpectSolid, SolidName, ExpectFacetOrEnd, AfterFacet, NormalNums, ExpectOuter, ExpectLoop,
    ExpectVertexOrEndloop, VertexNums, ExpectEndfacet, SkipLine,
  };
  Builder b;
  State state = ExpectSolid;
  State afterSkip = ExpectSolid;
  bool isSolid = false;      // first token began with "solid"
  bool decided = false;      // we know whether the file starts with "solid"
  bool binaryLooking = false;  // died on a control byte
  bool sawCR = false;
  uint64_t line = 1;
  uint64_t offset = 0;
  uint64_t tokenOffset = 0, tokenLine = 1;
  std::string carry;         // a token split across chunks
  bool inToken = false;
  // A token split across chunks is kept up to kMaxCarry bytes: more than any number
  // (kMaxNumberChars) and than 'solid' + a name (kMaxNameBytes + 1), so a cut token reads
  // exactly like the whole one.
  static constexpr size_t kMaxCarry = (kMaxNameBytes + 5 > kMaxNumberChars ? kMaxNameBytes + 5 : kMaxNumberChars) + 1;
  std::string name;
  bool nameCut = false;
  uint64_t nameLine = 1;
  int numIndex = 0, vertexCount = 0;
  float normal[3] = {0, 0, 0};
  float verts[9];
  uint64_t facetLine = 1, facetOffset = 0;
  bool bomChecked = false;
  uint8_t bomHave = 0;
  uint32_t fastBackoff = 0, fastWait = 0;  // see scan()

  explicit AsciiParser(const ReadOptions& o) : b(o) {}

  bool dead() const { return b.failed() || (decided && !isSolid); }

  void fail(Code c, std::string msg, uint64_t atLine, uint64_t atOffset) {
    if (!b.failed()) b.error = makeStatus(c, std::move(msg), atOffset, atLine);
  }

  static bool ieq(const char* t, size_t n, const char* kw) {
    size_t k = std::strlen(kw);
    if (n != k) return false;
    for (size_t i = 0; i < n; ++i)
      if ((t[i] | 0x20) != kw[i]) return false;
    return true;
  }
  static bool iprefix(const char* t, size_t n, const char* kw) {
    size_t k = std::strlen(kw);
    if (n < k) return false;
    for (size_t i = 0; i < k; ++i)
      if ((t[i] | 0x20) != kw[i]) return false;
    return true;
  }

  std::string show(const char* t, size_t n) {
    std::string s(t, std::min<size_t>(n, 40));
    for (char& c : s)
      if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) c = '?';
    if (n > 40) s += "...";
    return s;
  }

  void token(const char* t, size_t n) {
    switch (state) {
      case ExpectSolid:
        if (iprefix(t, n, "solid")) {
          if (!decided) { decided = true; isSolid = true; }
          name.assign(t + 5, std::min(n - 5, kMaxNameBytes + 1));
          nameCut = false;
          nameLine = tokenLine;
          state = SolidName;
          return;
        }
        if (!decided) { decided = true; isSolid = false; return; }
        fail(Code::AsciiSyntax, format("expected 'solid' but found '%s' at line %llu", show(t, n).c_str(), (unsigned long long)tokenLine), tokenLine, tokenOffset);
        return;
      case ExpectFacetOrEnd:
        if (ieq(t, n, "facet")) {
          state = AfterFacet;
          facetLine = tokenLine;
          facetOffset = tokenOffset;
          normal[0] = normal[1] = normal[2] = 0;
          vertexCount = 0;
          return;
        }
        if (iprefix(t, n, "endsolid")) {
          b.endSolid();
          state = SkipLine;
          afterSkip = ExpectSolid;
          return;
        }
        fail(Code::AsciiSyntax, format("expected 'facet' or 'endsolid' but found '%s' at line %llu", show(t, n).c_str(), (unsigned long long)tokenLine), tokenLine, tokenOffset);
        return;
      case AfterFacet:
        if (ieq(t, n, "normal")) { state = NormalNums; numIndex = 0; return; }
        if (ieq(t, n, "outer")) { state = ExpectLoop; return; }
        fail(Code::AsciiSyntax, format("expected 'normal' or 'outer' after 'facet' but found '%s' at line %llu", show(t, n).c_str(), (unsigned long long)tokenLine), tokenLine, tokenOffset);
        return;
      case NormalNums:
      case VertexNums: {
        float v;
        if (number(t, n, v)) putNumber(v);
        return;
      }
      case ExpectOuter:
        if (ieq(t, n, "outer")) { state = ExpectLoop; return; }
        fail(Code::AsciiSyntax, format("expected 'outer' but found '%s' at line %llu", show(t, n).c_str(), (unsigned long long)tokenLine), tokenLine, tokenOffset);
        return;
      case ExpectLoop:
        if (ieq(t, n, "loop")) { state = ExpectVertexOrEndloop; return; }
        fail(Code::AsciiSyntax, format("expected 'loop' but found '%s' at line %llu", show(t, n).c_str(), (unsigned long long)tokenLine), tokenLine, tokenOffset);
        return;
      case ExpectVertexOrEndloop:
        if (ieq(t, n, "vertex")) {
          if (vertexCount == 3) {
            fail(Code::AsciiSyntax, format("facet at line %llu has more than 3 vertices (line %llu)", (unsigned long long)facetLine, (unsigned long long)tokenLine), tokenLine, tokenOffset);
            return;
          }
          state = VertexNums;
          numIndex = 0;
          return;
        }
        if (ieq(t, n, "endloop")) {
          if (vertexCount != 3) {
            fail(Code::AsciiSyntax, format("facet at line %llu has %d vertices, expected 3 (line %llu)", (unsigned long long)facetLine, vertexCount, (unsigned long long)tokenLine), tokenLine, tokenOffset);
            return;
          }
          state = SkipLine;
          afterSkip = ExpectEndfacet;
          return;
        }
        fail(Code::AsciiSyntax, format("expected 'vertex' or 'endloop' but found '%s' at line %llu", show(t, n).c_str(), (unsigned long long)tokenLine), tokenLine, tokenOffset);
        return;
      case ExpectEndfacet:
        if (ieq(t, n, "endfacet")) {
          if (!b.add(normal, verts, 0, facetOffset, facetLine)) return;
          state = SkipLine;
          afterSkip = ExpectFacetOrEnd;
          return;
        }
        fail(Code::AsciiSyntax, format("expected 'endfacet' but found '%s' at line %llu", show(t, n).c_str(), (unsigned long long)tokenLine), tokenLine, tokenOffset);
        return;
      case SolidName:
      case SkipLine:
        return;  // not reached: handled by the line scanner
    }
  }

  // A number of the current facet (in state NormalNums or VertexNums).
  void putNumber(float v) {
    if (state == NormalNums) {
      normal[numIndex] = v;
      if (++numIndex == 3) state = ExpectOuter;
      return;
    }
    verts[vertexCount * 3 + numIndex] = v;
    if (++numIndex == 3) { ++vertexCount; state = ExpectVertexOrEndloop; }
  }

  bool number(const char* t, size_t n, float& out) {
    if (n > kMaxNumberChars) {
      fail(Code::AsciiSyntax, format("number longer than %zu characters at line %llu", kMaxNumberChars, (unsigned long long)tokenLine), tokenLine, tokenOffset);
      return false;
    }
    if (parseFloat(t, n, out)) return true;
    fail(Code::AsciiSyntax, format("malformed number '%s' at line %llu", show(t, n).c_str(), (unsigned long long)tokenLine), tokenLine, tokenOffset);
    return false;
  }

  // Skips whitespace in [q, end), counting lines in ln: CR, LF and CRLF each end one (cr:
  // the byte before q was a CR). Returns the first other byte, or end.
  static inline const uint8_t* skipBlanks(const uint8_t* q, const uint8_t* end, uint64_t& ln, bool& cr) {
    for (; q < end && isSpace(*q); ++q) {
      ln += (*q == '\r') | ((*q == '\n') & !cr);
      cr = *q == '\r';
    }
    return q;
  }

  // The end of the token at i: the first byte <= 0x20 or 0x7F (whitespace or a bad byte),
  // or n. 8 bytes per step while they last, then one at a time.
  static size_t tokenEnd(const uint8_t* p, size_t i, size_t n) {
    for (; i + 8 <= n; i += 8)
      if (uint64_t stops = tokenStops(load8(p + i))) return i + (unsigned(__builtin_ctzll(stops)) >> 3);
    while (i < n && p[i] > 0x20 && p[i] != 0x7f) ++i;
    return i;
  }

  // Fast path for a whole facet in the chunk, written the usual way:
  //   facet normal N N N  outer loop  vertex N N N (3 times)  endloop  endfacet
  // with whitespace between the tokens and only blanks after endloop and endfacet on their
  // lines. Parses p[i, n) (at least kFastFacetRoom bytes, 'facet' at i) to the end of the
  // line of 'endfacet' and adds the triangle, leaving the state exactly as the token
  // machine would; returns the position reached. Returns 0 and changes nothing when the
  // text differs in any way (another keyword, a number off the fast path, a bad byte, too
  // near the end of the chunk...): the token machine then reads the facet.
  static constexpr size_t kFastFacetRoom = 256;
  size_t fastFacet(const uint8_t* p, size_t i, size_t n, uint64_t base) {
    const uint8_t* end = p + n - 16;  // every token starts before end: 16 bytes of slack
    const uint8_t* q = p + i;
    uint64_t ln = line;
    // The whitespace after a token (sawCR is false at a token).
    auto blanks = [&](const uint8_t* from) {
      if (*from == ' ' && !isSpace(from[1])) {  // the usual single space
        q = from + 1;
        return q < end;
      }
      bool cr = false;
      q = skipBlanks(from, end, ln, cr);
      return q < end;
    };
    // A keyword, then the whitespace after it.
    auto word = [&](const Keyword& kw) { return keywordAt(q, kw) && blanks(q + kw.len); };
    // A number, then the whitespace after it.
    auto number = [&](float& v) {
      const char* e = parseDecimal(reinterpret_cast<const char*>(q), reinterpret_cast<const char*>(end), v);
      return e && isSpace(uint8_t(*e)) && blanks(reinterpret_cast<const uint8_t*>(e));
    };
    // The rest of a line after a keyword, as state SkipLine reads it: blanks and text, no
    // control bytes. Leaves q at the line end.
    auto restOfLine = [&]() {
      for (; q < end && *q != '\n' && *q != '\r'; ++q)
        if (*q < 0x20 && *q != '\t' && *q != '\v' && *q != '\f') return false;
      return q < end;
    };
    const uint8_t* facetAt = q;
    uint64_t facetLn = ln;
    float nv[3], vv[9];
    if (!blanks(q + kFacet.len) || !word(kNormal) || !number(nv[0]) || !number(nv[1]) || !number(nv[2]) || !word(kOuter) ||
        !word(kLoop))
      return 0;
    for (int c = 0; c < 3; ++c)
      if (!word(kVertex) || !number(vv[3 * c]) || !number(vv[3 * c + 1]) || !number(vv[3 * c + 2])) return 0;
    if (!keywordAt(q, kEndloop)) return 0;
    q += kEndloop.len;
    if (!restOfLine() || !blanks(q) || !keywordAt(q, kEndfacet)) return 0;
    const uint8_t* endAt = q;
    uint64_t endLn = ln;
    q += kEndfacet.len;
    if (!restOfLine()) return 0;
    // Commit: the state after the 'endfacet' token and the rest of its line.
    line = endLn;
    sawCR = false;
    facetLine = facetLn;
    facetOffset = base + size_t(facetAt - p);
    tokenLine = endLn;
    tokenOffset = base + size_t(endAt - p);
    std::memcpy(normal, nv, sizeof nv);
    std::memcpy(verts, vv, sizeof vv);
    vertexCount = 3;
    numIndex = 3;
    state = ExpectEndfacet;
    if (!b.add(normal, verts, 0, facetOffset, facetLine)) return size_t(endAt - p) + kEndfacet.len;  // as token()
    state = ExpectFacetOrEnd;
    afterSkip = ExpectFacetOrEnd;
    return size_t(q - p);
  }

  void feed(const uint8_t* p, size_t n) {
    size_t i = 0;
    // An optional UTF-8 byte-order mark at offset 0.
    while (!bomChecked && i < n) {
      static const uint8_t kBom[3] = {0xEF, 0xBB, 0xBF};
      if (p[i] == kBom[bomHave]) {
        ++bomHave; ++i; ++offset;
        if (bomHave == 3) bomChecked = true;
      } else {
        if (bomHave > 0) { decided = true; isSolid = false; return; }  // a broken BOM
        bomChecked = true;
      }
    }
    const uint64_t base = offset - i;  // the offset of p[0]
    offset = base + scan(p, i, n, base);
  }

  // Parses p[i, n); returns where it stopped (n, or the place of an error).
  size_t scan(const uint8_t* p, size_t i, size_t n, uint64_t base) {
    while (i < n && !dead()) {
      if (state == SolidName || state == SkipLine) {
        size_t j = i;
        while (j < n && p[j] != '\n' && p[j] != '\r') {
          if (p[j] < 0x20 && p[j] != '\t' && p[j] != '\v' && p[j] != '\f') { badByte(p[j], base + j); return i; }
          ++j;
        }
        if (state == SolidName) {
          size_t from = i;
          if (name.empty())  // leading blanks are not part of the name
            while (from < j && (p[from] == ' ' || p[from] == '\t' || p[from] == '\v' || p[from] == '\f')) ++from;
          size_t room = kMaxNameBytes + 1 > name.size() ? kMaxNameBytes + 1 - name.size() : 0;
          name.append(reinterpret_cast<const char*>(p + from), std::min(room, j - from));
        }
        i = j;
        if (i < n) {  // end of line reached
          if (state == SolidName) {
            openSolid();
            state = ExpectFacetOrEnd;
          } else {
            state = afterSkip;
          }
        }
        continue;
      }
      if (inToken) {  // continue a token carried over from the previous chunk
        size_t j = tokenEnd(p, i, n);
        if (j < n && !isSpace(p[j])) { badByte(p[j], base + j); return i; }
        size_t room = kMaxCarry > carry.size() ? kMaxCarry - carry.size() : 0;
        carry.append(reinterpret_cast<const char*>(p + i), std::min(room, j - i));
        i = j;
        if (i < n) endCarry();
        continue;
      }
      i = size_t(skipBlanks(p + i, p + n, line, sawCR) - p);
      if (i == n) break;
      sawCR = false;
      if (state == ExpectFacetOrEnd && n - i >= kFastFacetRoom && keywordAt(p + i, kFacet)) {
        // Whole facets at once while they read the usual way. After a miss, leave a few
        // facets (twice as many after each further miss) to the token machine.
        if (fastWait > 0) {
          --fastWait;
        } else if (size_t j = fastFacet(p, i, n, base)) {
          fastBackoff = 0;
          i = j;
          continue;
        } else {
          fastBackoff = std::min<uint32_t>(std::max<uint32_t>(1, fastBackoff * 2), 1024);
          fastWait = fastBackoff;
        }
      }
      size_t j = tokenEnd(p, i, n);
      if (j < n && !isSpace(p[j])) { badByte(p[j], base + j); return i; }  // a control byte (j may be i)
      tokenOffset = base + i;
      tokenLine = line;
      const char* t = reinterpret_cast<const char*>(p + i);
      if (j == n) {  // the token may continue in the next chunk
        inToken = true;
        carry.assign(t, std::min(j - i, kMaxCarry));
        return n;
      }
      token(t, j - i);
      i = j;
    }
    return i;
  }

  void endCarry() {
    inToken = false;
    token(carry.data(), carry.size());
    carry.clear();
  }

  void badByte(uint8_t c, uint64_t at) {
    if (!decided) { decided = true; isSolid = false; return; }
    binaryLooking = true;
    fail(Code::AsciiSyntax, format("unexpected byte 0x%02X at offset %llu (line %llu): not ASCII STL text", c, (unsigned long long)at, (unsigned long long)line), line, at);
  }

  void openSolid() {
    std::string nm = trimmed(name.size() > kMaxNameBytes ? name.substr(0, kMaxNameBytes) : name);
    if (name.size() > kMaxNameBytes) {
      // Cut at a UTF-8 character boundary.
      while (!nm.empty() && (static_cast<unsigned char>(nm.back()) & 0xC0) == 0x80) nm.pop_back();
      if (!nm.empty() && static_cast<unsigned char>(nm.back()) >= 0xC0) nm.pop_back();
      b.addWarning(Code::NameTruncated, format("solid name at line %llu is longer than %zu bytes and was cut", (unsigned long long)nameLine, kMaxNameBytes), kNoOffset, nameLine);
    }
    b.beginSolid(std::move(nm), nullptr);
    name.clear();
  }

  // Outcome at end of input.
  Status end() {
    if (b.failed()) return b.error;
    if (inToken) {
      endCarry();
      if (b.failed()) return b.error;
    }
    State s = state == SkipLine ? afterSkip : state;
    switch (s) {
      case ExpectSolid:
        return Status{};  // after endsolid (or between solids)
      case SolidName:
        openSolid();
        [[fallthrough]];
      case ExpectFacetOrEnd:
        b.endSolid();
        b.addWarning(Code::MissingEndsolid,
                     format("the file ends after line %llu without 'endsolid'", (unsigned long long)tokenLine), offset, tokenLine);
        return Status{};
      default:
        return makeStatus(Code::UnexpectedEnd,
                          format("the file ends after line %llu inside the facet that starts at line %llu",
                              (unsigned long long)tokenLine, (unsigned long long)facetLine),
                          offset, tokenLine);
    }
  }
};

}  // namespace

// ---------------------------------------------------------------------------
struct Reader::Impl {
  ReadOptions opt;
  BinaryParser* bin = nullptr;
  AsciiParser* ascii = nullptr;
  uint64_t total = 0;
  Status sticky;
  bool finished = false;

  explicit Impl(const ReadOptions& o) : opt(o) { start(); }
  ~Impl() { clear(); }
  void clear() {
    delete bin; bin = nullptr;
    delete ascii; ascii = nullptr;
  }
  void start() {
    clear();
    bin = new (std::nothrow) BinaryParser(opt);
    ascii = new (std::nothrow) AsciiParser(opt);
    total = 0;
    sticky = Status{};
    finished = false;
    if (!bin || !ascii) sticky = oom("the reader");
  }

  bool binaryDead() const { return bin == nullptr || bin->b.failed(); }
  bool asciiDead() const { return ascii == nullptr || ascii->dead(); }

  // The detection rule. atEnd: all input has arrived.
  Status decide(bool atEnd, Mesh* out) {
    Status bs;
    BinaryParser::End be = BinaryParser::End::Error;
    if (bin) {
      if (atEnd) be = bin->end(bs);
      else bs = bin->b.error;
    }
    // The first token may still be pending at the end ("solid" and nothing else).
    if (atEnd && ascii && !ascii->decided && ascii->inToken && !ascii->dead()) ascii->endCarry();
    bool solidFile = ascii && ascii->decided && ascii->isSolid;
    auto takeBinary = [&](bool trailing) -> Status {
      if (trailing) {
        uint64_t extra = bin->offset - bin->partStart;
        bin->b.addWarning(Code::TrailingBytes,
                          format("%llu extra byte%s after the last triangle at offset %llu were ignored",
                              (unsigned long long)extra, extra == 1 ? "" : "s", (unsigned long long)bin->partStart),
                          bin->partStart);
      }
      bin->b.mesh.format = Format::Binary;
      return finishBuilder(bin->b, out);
    };
    if (atEnd && be == BinaryParser::End::Exact) return takeBinary(false);
    if (solidFile) {
      Status as = atEnd ? ascii->end() : ascii->b.error;
      if (as.ok()) {
        ascii->b.mesh.format = Format::Ascii;
        return finishBuilder(ascii->b, out);
      }
      if (atEnd && be == BinaryParser::End::Trailing) return takeBinary(true);
      if (ascii->binaryLooking && !bs.ok()) return bs;
      return as;
    }
    if (atEnd && total == 0) return makeStatus(Code::Empty, "the file is empty (0 bytes)", 0);
    if (atEnd && be == BinaryParser::End::TooShort)
      return makeStatus(Code::NotStl,
                        format("the file has %llu bytes: too short for a binary STL (84-byte minimum) and it does not start with 'solid'",
                            (unsigned long long)total),
                        0);
    if (atEnd && be == BinaryParser::End::Trailing) return takeBinary(true);
    return bs;
  }

  Status finishBuilder(Builder& b, Mesh* out) {
    b.endSolid();
    if (!b.decodeColors()) return oom("the colour array");
    b.releaseWeld();
    if (out) *out = std::move(b.mesh);
    return Status{};
  }
};

Reader::Reader(const ReadOptions& options) : impl_(new Impl(options)) {}
Reader::~Reader() { delete impl_; }
uint64_t Reader::bytesRead() const { return impl_->total; }
void Reader::reset() { impl_->start(); }

Status Reader::feed(const uint8_t* data, size_t size) {
  Impl& m = *impl_;
  if (m.finished) return makeStatus(Code::InvalidArgument, "feed() after finish(); call reset() first");
  if (!m.sticky.ok()) return m.sticky;
  if (m.opt.maxBytes && m.total + size > m.opt.maxBytes) {
    m.sticky = makeStatus(Code::TooLarge, format("the input is larger than maxBytes (%llu)", (unsigned long long)m.opt.maxBytes), m.opt.maxBytes);
    m.clear();
    return m.sticky;
  }
  m.total += size;
  if (!m.binaryDead()) {
    m.bin->feed(data, size);
    if (m.bin->b.failed()) m.bin->b.dropArrays();  // keep its status
  }
  if (!m.asciiDead()) {
    m.ascii->feed(data, size);
    if (m.asciiDead() && m.ascii->decided && !m.ascii->isSolid) {
      delete m.ascii;  // not an ASCII file: free it now
      m.ascii = nullptr;
    }
  }
  if (m.binaryDead() && m.asciiDead()) {
    m.sticky = m.decide(false, nullptr);
    if (m.sticky.ok()) m.sticky = makeStatus(Code::NotStl, "the input is not STL");
    m.clear();
    return m.sticky;
  }
  return Status{};
}

Status Reader::finish(Mesh& out) {
  Impl& m = *impl_;
  if (m.finished) return makeStatus(Code::InvalidArgument, "finish() called twice; call reset() first");
  m.finished = true;
  if (!m.sticky.ok()) return m.sticky;
  Status s = m.decide(true, &out);
  m.clear();
  if (!s.ok()) m.sticky = s;
  return s;
}

Status readStl(const uint8_t* data, size_t size, Mesh& out, const ReadOptions& options) {
  ReadOptions o = options;
  if (o.sizeHint == 0) o.sizeHint = size;
  Reader r(o);
  Status s = r.feed(data, size);
  if (!s.ok()) return s;
  return r.finish(out);
}

}  // namespace stltopo
