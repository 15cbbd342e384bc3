// Fuzz target 5: writing. Whatever reads is written as binary and as ASCII STL (stored
// normals), in small chunks, and read back: the same positions (bit for bit), triangles,
// solids and normals; binary also the same attribute words and colours, and names where the
// header can hold them; writing the read-back mesh again gives the same bytes.
#include "fuzz_common.h"

#include "stltopo/write.h"

using namespace stltopo;

namespace {

bool append(void* user, const uint8_t* data, size_t size) {
  static_cast<std::string*>(user)->append(reinterpret_cast<const char*>(data), size);
  return true;
}

std::string written(const Mesh& m, Format f) {
  WriteOptions o;
  o.format = f;
  o.chunkBytes = kMinChunkBytes;
  std::string out;
  Status s = writeStl(m, append, &out, o);
  FUZZ_CHECK(s.ok());
  return out;
}

// A name the format carries as it is: no byte it cuts at, short enough, trimmed, and in
// binary no COLOR= the reader would see.
bool keepsName(const std::string& n, Format f) {
  for (unsigned char c : n)
    if (c == 0 || (f == Format::Ascii && c < 0x20 && c != '\t' && c != '\v' && c != '\f')) return false;
  if (f == Format::Binary && (n.size() > 69 || n.find("COLOR=") != std::string::npos)) return false;
  return n.size() <= kMaxNameBytes;
}

bool sameNormals(const Array<float>& a, const Array<float>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (!(std::isnan(a[i]) && std::isnan(b[i])) && std::memcmp(&a[i], &b[i], 4) != 0) return false;
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  ReadOptions o;
  o.keepNormals = true;
  Mesh m;
  if (!readStl(data, size, m, o).ok()) return 0;
  for (Format f : {Format::Binary, Format::Ascii}) {
    std::string bytes = written(m, f);
    Mesh back;
    Status s = readStl(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), back, o);
    FUZZ_CHECK(s.ok());
    FUZZ_CHECK(back.format == f);
    FUZZ_CHECK(fuzz::sameArray(m.positions, back.positions));
    FUZZ_CHECK(fuzz::sameArray(m.triangles, back.triangles));
    FUZZ_CHECK(f == Format::Binary ? fuzz::sameArray(m.normals, back.normals) : sameNormals(m.normals, back.normals));
    if (f == Format::Binary) {
      FUZZ_CHECK(fuzz::sameArray(m.attributes, back.attributes));
      FUZZ_CHECK(m.colorConvention == back.colorConvention);
      FUZZ_CHECK(fuzz::sameArray(m.colors, back.colors));
      FUZZ_CHECK(fuzz::sameArray(m.colorValid, back.colorValid));
    }
    FUZZ_CHECK(m.solids.size() == back.solids.size());
    for (size_t i = 0; i < m.solids.size(); ++i) {
      FUZZ_CHECK(m.solids[i].firstTriangle == back.solids[i].firstTriangle);
      FUZZ_CHECK(m.solids[i].triangleCount == back.solids[i].triangleCount);
      if (keepsName(m.solids[i].name, f)) FUZZ_CHECK(m.solids[i].name == back.solids[i].name);
    }
    FUZZ_CHECK(written(back, f) == bytes);
  }
  return 0;
}
