// STL writer (see stltopo/write.h). The mesh is checked once, cut into parts (one per
// solid, plus the stretches of triangles no solid covers), and each next() fills the
// chunk buffer with whole headers and records. The colour encodings are the exact inverse
// of the reader's decoding (Builder::decodeColors), so reading the output gives back the
// same attribute words and colours.
#include <bit>
#include <cmath>
#include <cstring>
#include <new>

#include "bit_cast.h"
#include "float_shortest.h"
#include "mesh_builder.h"
#include "solid_parts.h"
#include "stltopo/mesh.h"
#include "stltopo/status.h"
#include "stltopo/write.h"
#include "text_format.h"
#include "try_alloc.h"

namespace stltopo {
namespace {

using detail::format;

constexpr size_t kHeaderBytes = 84, kRecordBytes = 50;
// The longest ASCII facet: 12 numbers of at most kMaxFloatChars and the keywords.
constexpr size_t kMaxFacetBytes = 12 * (detail::kMaxFloatChars + 1) + 128;
// The longest ASCII solid line: "endsolid " + name + "\n".
constexpr size_t kMaxSolidLineBytes = kMaxNameBytes + 16;
static_assert(kMinChunkBytes >= kMaxSolidLineBytes + kMaxFacetBytes, "a chunk holds any line");

// The binary header: COLOR= and its 4 bytes at this offset when the name leaves room.
constexpr size_t kColorAt = 70;
constexpr char kColorTag[] = "COLOR=";

using Part = detail::SolidPart;  // one binary part or one solid block

// How the attribute words are written.
enum class Words : uint8_t {
  Raw,       // the mesh's words
  Zero,      // colours dropped
  ToVisCam,  // 0x8000 | r << 10 | g << 5 | b for a coloured triangle, else 0
  ToMagics,  // r | g << 5 | b << 10 for a coloured triangle, else 0x8000 (the default)
};

// The reader's decoding is Builder::c5(); to5() is its inverse.
using detail::Builder;

inline bool blank(unsigned char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

// A name as written: a view into Mesh::solids or WriteOptions::name (no allocation).
struct Name {
  const char* p = "";
  size_t n = 0;
  Name prefix(size_t k) const { return Name{p, k < n ? k : n}; }
};

// name cut before the first byte the format cannot carry and to at most max bytes (at a
// UTF-8 character boundary), then trimmed as the reader trims.
Name safeName(Name name, bool ascii, size_t max) {
  size_t n = 0;
  for (; n < name.n && n < max; ++n) {
    unsigned char c = static_cast<unsigned char>(name.p[n]);
    if (c == 0 || (ascii && c < 0x20 && c != '\t' && c != '\v' && c != '\f')) break;
  }
  if (n == max && n < name.n)
    while (n > 0 && (static_cast<unsigned char>(name.p[n]) & 0xC0) == 0x80) --n;  // inside a character
  size_t b = 0;
  while (b < n && blank(static_cast<unsigned char>(name.p[b]))) ++b;
  while (n > b && blank(static_cast<unsigned char>(name.p[n - 1]))) --n;
  return Name{name.p + b, n - b};
}

constexpr size_t kNoTag = ~size_t(0);

// The first "COLOR=" that the reader would find in a header starting with name.
size_t colorTagIn(Name name) {
  for (size_t i = 0; i + 6 <= name.n && i + 10 <= 80; ++i)
    if (std::memcmp(name.p + i, kColorTag, 6) == 0) return i;
  return kNoTag;
}

inline void putU32(uint8_t* p, uint32_t v) {
  if constexpr (std::endian::native == std::endian::big) v = __builtin_bswap32(v);
  std::memcpy(p, &v, 4);
}
inline void putU16(uint8_t* p, uint16_t v) {
  if constexpr (std::endian::native == std::endian::big) v = __builtin_bswap16(v);
  std::memcpy(p, &v, 2);
}
inline void putF32(uint8_t* p, float f) { putU32(p, detail::bitCast<uint32_t>(f)); }

inline char* put(char* o, const char* s, size_t n) {
  std::memcpy(o, s, n);
  return o + n;
}
template <size_t N>
inline char* put(char* o, const char (&s)[N]) {
  return put(o, s, N - 1);
}

}  // namespace

struct StlWriter::Impl {
  const Mesh& mesh;
  WriteOptions opt;
  bool ascii;
  Words words = Words::Raw;
  ColorConvention outColors = ColorConvention::None;  // the convention the output carries
  bool checked = false;
  Status error;  // sticky
  Array<Part> parts;
  Array<uint8_t> buf;
  size_t used = 0;
  uint64_t written = 0;
  // Position in the file.
  size_t part = 0;
  enum class Phase : uint8_t { Header, Body, Footer } phase = Phase::Header;
  uint32_t next = 0;  // next triangle of the part
  Name partName;      // the current part's name as written (ASCII)

  Impl(const Mesh& m, const WriteOptions& o) : mesh(m), opt(o), ascii(o.format == Format::Ascii) {
    if (opt.chunkBytes < kMinChunkBytes) opt.chunkBytes = kMinChunkBytes;
  }

  Status check() {
    const uint64_t nv = mesh.positions.size() / 3, nt3 = mesh.triangles.size();
    if (mesh.positions.size() % 3 != 0 || nt3 % 3 != 0)
      return Status::error(Code::InvalidArgument,
                           format("positions (%zu) and triangles (%zu) must hold 3 values per element",
                                  mesh.positions.size(), mesh.triangles.size()));
    const uint64_t nt = nt3 / 3;
    if (nt > 0xFFFFFFFFull)
      return Status::error(Code::TooLarge,
                           format("%llu triangles: an STL file holds at most 2^32 - 1", (unsigned long long)nt));
    auto lengthIs = [](size_t have, uint64_t want) { return have == 0 || have == want; };
    if (!lengthIs(mesh.attributes.size(), nt) || !lengthIs(mesh.normals.size(), 3 * nt))
      return Status::error(
          Code::InvalidArgument,
          format("attributes (%zu) and normals (%zu) must be empty or hold 1 and 3 values per triangle (%llu)",
                 mesh.attributes.size(), mesh.normals.size(), (unsigned long long)nt));
    if (mesh.colorConvention != ColorConvention::None && (mesh.colors.size() != 3 * nt || mesh.colorValid.size() != nt))
      return Status::error(Code::InvalidArgument,
                           format("colors (%zu) and colorValid (%zu) must hold 3 and 1 values per triangle (%llu)",
                                  mesh.colors.size(), mesh.colorValid.size(), (unsigned long long)nt));
    const uint32_t* tri = mesh.triangles.data();
    for (uint64_t t = 0; t < nt; ++t)
      for (int c = 0; c < 3; ++c)
        if (tri[3 * t + c] >= nv)
          return Status::error(Code::InvalidIndex,
                               format("triangle %llu corner %d is vertex %u, but the mesh has %llu vertices",
                                      (unsigned long long)t, c, tri[3 * t + c], (unsigned long long)nv),
                               kNoOffset, 0, uint32_t(t));
    Status ps = detail::solidParts(mesh.solids.data(), mesh.solids.size(), nt, parts);
    if (!ps.ok()) return ps;
    if (!buf.resize(opt.chunkBytes)) return detail::oom(kBuffers);
    // The attribute words.
    ColorConvention in = mesh.colorConvention;
    ColorConvention want = opt.colors == WriteColors::None     ? ColorConvention::None
                           : opt.colors == WriteColors::VisCam ? ColorConvention::VisCam
                           : opt.colors == WriteColors::Magics ? ColorConvention::Magics
                                                               : in;
    if (ascii || in == ColorConvention::None || want == in) {
      words = Words::Raw;
      outColors = ascii ? ColorConvention::None : in;
    } else {
      words = want == ColorConvention::None     ? Words::Zero
              : want == ColorConvention::VisCam ? Words::ToVisCam
                                                : Words::ToMagics;
      outColors = want;
    }
    return Status{};
  }

  static constexpr const char* kBuffers = "the writer's buffers";  // what out-of-memory names

  uint16_t word(uint32_t t) const {
    switch (words) {
      case Words::Raw: return mesh.attributes.empty() ? 0 : mesh.attributes[t];
      case Words::Zero: return 0;
      case Words::ToVisCam: {
        if (!mesh.colorValid[t]) return 0;
        return Builder::visCamWord(mesh.colors.data() + 3 * size_t(t));
      }
      case Words::ToMagics: {
        if (!mesh.colorValid[t]) return 0x8000u;
        const uint8_t* c = mesh.colors.data() + 3 * size_t(t);
        return uint16_t(Builder::to5(c[0]) | Builder::to5(c[1]) << 5 | Builder::to5(c[2]) << 10);
      }
    }
    return 0;
  }

  Name nameOf(const Part& p) const {
    if (opt.name) return Name{opt.name->data(), opt.name->size()};
    if (p.solid == kInvalid) return Name{};
    const std::string& s = mesh.solids[p.solid].name;
    return Name{s.data(), s.size()};
  }

  // The 84 bytes that start binary part p.
  void binaryHeader(const Part& p, uint8_t* h) {
    std::memset(h, 0, kHeaderBytes);
    Name name = safeName(nameOf(p), false, 80);
    bool colorHeader = false;
    uint8_t rgb[3] = {opt.defaultColor[0], opt.defaultColor[1], opt.defaultColor[2]};
    if (outColors == ColorConvention::Magics) {
      // A part carries COLOR= unless the mesh's own Magics words say it had none (it has
      // triangles and none is coloured). The default colour is that of a triangle whose
      // word says "default", when one does.
      bool anyColored = false, usesDefault = false;
      for (uint32_t t = p.first; t < p.first + p.count; ++t) {
        anyColored |= mesh.colorValid[t] != 0;
        if (!usesDefault && (word(t) & 0x8000u)) {
          usesDefault = true;
          if (mesh.colorValid[t]) std::memcpy(rgb, mesh.colors.data() + 3 * size_t(t), 3);
        }
      }
      colorHeader = words == Words::ToMagics || p.count == 0 || anyColored;
      size_t i = colorTagIn(name);
      if (colorHeader && i != kNoTag && i + 9 <= name.n && (!usesDefault || std::memcmp(name.p + i + 6, rgb, 3) == 0)) {
        colorHeader = false;  // the name's own COLOR= already says it
      } else if (i != kNoTag) {
        name = safeName(name.prefix(i), false, 80);
      }
      if (colorHeader && name.n > kColorAt - 1) name = safeName(name, false, kColorAt - 1);
    } else if (size_t i = colorTagIn(name); i != kNoTag) {
      name = safeName(name.prefix(i), false, 80);  // else the reader would see Magics colours
    }
    std::memcpy(h, name.p, name.n);
    if (colorHeader) {
      std::memcpy(h + kColorAt, kColorTag, 6);
      std::memcpy(h + kColorAt + 6, rgb, 3);
      h[kColorAt + 9] = 0xFF;
    }
    putU32(h + 80, p.count);
  }

  void normalOf(uint32_t t, float n[3]) const {
    if (opt.storedNormals && !mesh.normals.empty()) {
      std::memcpy(n, mesh.normals.data() + 3 * size_t(t), 3 * sizeof(float));
      return;
    }
    const uint32_t* c = mesh.triangles.data() + 3 * size_t(t);
    const float *a = mesh.positions.data() + 3 * size_t(c[0]), *b = mesh.positions.data() + 3 * size_t(c[1]),
                *d = mesh.positions.data() + 3 * size_t(c[2]);
    double ux = double(b[0]) - a[0], uy = double(b[1]) - a[1], uz = double(b[2]) - a[2];
    double wx = double(d[0]) - a[0], wy = double(d[1]) - a[1], wz = double(d[2]) - a[2];
    double nx = uy * wz - uz * wy, ny = uz * wx - ux * wz, nz = ux * wy - uy * wx;
    double len = std::sqrt(nx * nx + ny * ny + nz * nz);
    if (!(len > 0)) {
      n[0] = n[1] = n[2] = 0;
      return;
    }
    n[0] = float(nx / len) + 0.0f;  // + 0: no "-0" in ASCII for an axis-aligned normal
    n[1] = float(ny / len) + 0.0f;
    n[2] = float(nz / len) + 0.0f;
  }

  void binaryRecord(uint32_t t, uint8_t* r) const {
    float n[3];
    normalOf(t, n);
    for (int k = 0; k < 3; ++k) putF32(r + 4 * k, n[k]);
    const uint32_t* c = mesh.triangles.data() + 3 * size_t(t);
    for (int v = 0; v < 3; ++v) {
      const float* p = mesh.positions.data() + 3 * size_t(c[v]);
      for (int k = 0; k < 3; ++k) putF32(r + 12 + 12 * v + 4 * k, p[k]);
    }
    putU16(r + 48, word(t));
  }

  static char* numbers(char* o, const float* v) {
    o += detail::formatShortestHere(v[0], o);
    *o++ = ' ';
    o += detail::formatShortestHere(v[1], o);
    *o++ = ' ';
    o += detail::formatShortestHere(v[2], o);
    *o++ = '\n';
    return o;
  }

  char* asciiFacet(uint32_t t, char* o) const {
    float n[3];
    normalOf(t, n);
    o = put(o, "  facet normal ");
    o = numbers(o, n);
    o = put(o, "    outer loop\n");
    const uint32_t* c = mesh.triangles.data() + 3 * size_t(t);
    for (int v = 0; v < 3; ++v) {
      o = put(o, "      vertex ");
      o = numbers(o, mesh.positions.data() + 3 * size_t(c[v]));
    }
    return put(o, "    endloop\n  endfacet\n");
  }

  // Fills the buffer with whole headers, records and lines while they fit.
  void fill() {
    uint8_t* b = buf.data();
    const size_t cap = buf.size();
    while (part < parts.size()) {
      const Part& p = parts[part];
      if (phase == Phase::Header) {
        if (cap - used < (ascii ? kMaxSolidLineBytes : kHeaderBytes)) return;
        if (ascii) {
          partName = safeName(nameOf(p), true, kMaxNameBytes);
          char* o = put(reinterpret_cast<char*>(b + used), "solid");
          if (partName.n > 0) {
            *o++ = ' ';
            o = put(o, partName.p, partName.n);
          }
          *o++ = '\n';
          used = size_t(reinterpret_cast<uint8_t*>(o) - b);
        } else {
          binaryHeader(p, b + used);
          used += kHeaderBytes;
        }
        phase = Phase::Body;
        next = p.first;
      }
      if (phase == Phase::Body) {
        const uint32_t end = p.first + p.count;
        if (ascii) {
          char* o = reinterpret_cast<char*>(b + used);
          char* limit = reinterpret_cast<char*>(b + cap - kMaxFacetBytes);
          for (; next < end && o <= limit; ++next) o = asciiFacet(next, o);
          used = size_t(reinterpret_cast<uint8_t*>(o) - b);
        } else {
          uint32_t fit = uint32_t((cap - used) / kRecordBytes);
          uint32_t take = end - next < fit ? end - next : fit;
          for (uint32_t k = 0; k < take; ++k, ++next, used += kRecordBytes) binaryRecord(next, b + used);
        }
        if (next < end) return;
        phase = Phase::Footer;
      }
      if (ascii) {
        if (cap - used < kMaxSolidLineBytes) return;
        char* o = put(reinterpret_cast<char*>(b + used), "endsolid");
        if (partName.n > 0) {
          *o++ = ' ';
          o = put(o, partName.p, partName.n);
        }
        *o++ = '\n';
        used = size_t(reinterpret_cast<uint8_t*>(o) - b);
      }
      ++part;
      phase = Phase::Header;
    }
  }
};

StlWriter::StlWriter(const Mesh& mesh, const WriteOptions& options) : impl_(new (std::nothrow) Impl(mesh, options)) {}
StlWriter::~StlWriter() { delete impl_; }
uint64_t StlWriter::bytesWritten() const { return impl_ ? impl_->written : 0; }

Status StlWriter::next(const uint8_t*& data, size_t& size) {
  data = nullptr;
  size = 0;
  if (!impl_) return detail::oom(Impl::kBuffers);
  Impl& w = *impl_;
  if (!w.error.ok()) return w.error;
  if (!w.checked) {
    w.checked = true;
    w.error = w.check();
    if (!w.error.ok()) {
      w.parts.release();
      w.buf.release();
      return w.error;
    }
  }
  w.used = 0;
  w.fill();
  data = w.buf.data();
  size = w.used;
  w.written += w.used;
  if (size == 0) w.buf.release();  // done
  return Status{};
}

Status writeStl(const Mesh& mesh, WriteSink sink, void* user, const WriteOptions& options) {
  StlWriter w(mesh, options);
  for (;;) {
    const uint8_t* data;
    size_t size;
    Status s = w.next(data, size);
    if (!s.ok() || size == 0) return s;
    if (!sink(user, data, size))
      return Status::error(Code::WriteFailed,
                           format("the output refused the %zu bytes at offset %llu", size,
                                  (unsigned long long)(w.bytesWritten() - size)),
                           w.bytesWritten() - size);
  }
}

}  // namespace stltopo
