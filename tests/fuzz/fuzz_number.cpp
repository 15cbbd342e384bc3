// Fuzz target 4: ASCII numbers, differential against the C library. The input is split
// into up to 9 number tokens (runs of digits, letters and . + -, so hex floats, inf and nan
// too; every other byte separates them; missing tokens are "0"). They become the vertex coordinates of the first facet
// of an ASCII STL that has a second facet after it, so the first facet takes the reader's whole-facet fast path when
// read whole and the token state machine when fed 1 byte at a time. Both reads must agree with strtof_l in the "C"
// locale, bit for bit:
//   - every token that strtof reads entirely, to a finite float: the file reads, and
//     each corner's position is that float (the weld merges -0 and +0, so a corner that
//     reuses an earlier vertex compares equal as a float; a new vertex keeps the bits);
//   - a token strtof does not read entirely, or one longer than kMaxNumberChars:
//     ascii-syntax at line 3 (the first malformed token's vertex line);
//   - otherwise, when a token reads as NaN or +-Inf (1e999 too): non-finite for triangle 0.
// The report's double formatting too, differential against printing: for each token that
// strtod_l reads to a finite double, for that double scaled into the exact path's range, and
// for the input's first 8 bytes as a double, shortestDouble gives the text of the search by
// printing from 1 digit.
#include <locale.h>
#include <clocale>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "float_format.h"
#include "fuzz_common.h"

using namespace stltopo;

namespace {

locale_t cLocale() {
  static locale_t c = newlocale(LC_ALL_MASK, "C", nullptr);
  return c;
}

bool numberByte(uint8_t c) {
  return (c >= '0' && c <= '9') || ((c | 0x20) >= 'a' && (c | 0x20) <= 'z') || c == '.' || c == '+' || c == '-';
}

enum class Expect { Ok, Syntax, NonFinite };

void checkShortestDouble(double x) {
  if (std::isfinite(x)) FUZZ_CHECK(stltopo::detail::shortestDouble(x) == stltopo::detail::shortestByPrinting(x, false));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<std::string> tok;
  for (size_t i = 0; i < size && tok.size() < 9;) {
    if (!numberByte(data[i])) {
      ++i;
      continue;
    }
    size_t j = i;
    while (j < size && numberByte(data[j])) ++j;
    tok.emplace_back(reinterpret_cast<const char*>(data + i), j - i);
    i = j;
  }
  while (tok.size() < 9) tok.push_back("0");

  for (const std::string& t : tok) {
    const double x = strtod_l(t.c_str(), nullptr, cLocale());
    checkShortestDouble(x);
    int e = 0;
    const double m = std::frexp(x, &e);  // the same mantissa at 2^-53 to 2^162
    checkShortestDouble(std::ldexp(m, (e % 216 + 216) % 216 - 53));
  }
  if (size >= 8) {
    double x;
    std::memcpy(&x, data, 8);
    checkShortestDouble(x);
  }

  Expect expect = Expect::Ok;
  float want[9];
  for (int k = 0; k < 9 && expect == Expect::Ok; ++k) {
    const std::string& t = tok[k];
    char* end = nullptr;
    want[k] = strtof_l(t.c_str(), &end, cLocale());
    if (t.size() > kMaxNumberChars || end != t.c_str() + t.size()) expect = Expect::Syntax;
  }
  if (expect == Expect::Ok)
    for (float w : want)
      if (!std::isfinite(w)) expect = Expect::NonFinite;

  std::string s = "solid fuzz\nfacet normal 0 0 0\nouter loop\n";
  for (int c = 0; c < 3; ++c) s += "vertex " + tok[3 * c] + " " + tok[3 * c + 1] + " " + tok[3 * c + 2] + "\n";
  s += "endloop\nendfacet\n";
  // A second facet, so that the first one is followed by enough bytes for the fast path.
  s += "facet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n  vertex 0 1 0\n endloop\nendfacet\n";
  s += "endsolid fuzz\n" + std::string(300, ' ') + "\n";
  const auto* p = reinterpret_cast<const uint8_t*>(s.data());

  Mesh whole;
  Status sw = readStl(p, s.size(), whole);
  Mesh bytewise;
  Reader r;
  Status sb;
  for (size_t i = 0; i < s.size() && sb.ok(); ++i) sb = r.feed(p + i, 1);
  if (sb.ok()) sb = r.finish(bytewise);
  FUZZ_CHECK(fuzz::sameStatus(sw, sb));

  switch (expect) {
    case Expect::Syntax:
      FUZZ_CHECK(sw.code == Code::AsciiSyntax);
      FUZZ_CHECK(sw.line >= 4 && sw.line <= 6);
      return 0;
    case Expect::NonFinite:
      FUZZ_CHECK(sw.code == Code::NonFinite);
      FUZZ_CHECK(sw.triangle == 0);
      return 0;
    case Expect::Ok: break;
  }
  if (!sw.ok()) std::fprintf(stderr, "%s\n", sw.message.c_str());
  FUZZ_CHECK(sw.ok());
  fuzz::checkSameMesh(whole, bytewise);
  FUZZ_CHECK(whole.format == Format::Ascii && whole.nTriangles() == 2);
  uint32_t fresh = 0;  // vertex ids are given in first-appearance order
  for (int c = 0; c < 3; ++c) {
    uint32_t v = whole.triangles[c];
    const float* q = whole.positions.data() + size_t(v) * 3;
    for (int k = 0; k < 3; ++k) {
      FUZZ_CHECK(q[k] == want[3 * c + k]);
      if (v == fresh) FUZZ_CHECK(std::memcmp(&q[k], &want[3 * c + k], sizeof(float)) == 0);
    }
    if (v == fresh) ++fresh;
  }
  return 0;
}
