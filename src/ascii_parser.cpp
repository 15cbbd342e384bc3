#include "ascii_parser.h"

#include "float_parse.h"

namespace stltopo::detail {

namespace {

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
  uint64_t del = (low + kOnes) & ~w & kHigh;                       // low + 1 == 0x80 iff low == 0x7F
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

}  // namespace

inline void AsciiParser::fail(Code c, std::string msg, uint64_t atLine, uint64_t atOffset) {
  if (!b.failed()) b.error = Status::error(c, std::move(msg), atOffset, atLine);
}

inline bool AsciiParser::ieq(const char* t, size_t n, const char* kw) {
  size_t k = std::strlen(kw);
  if (n != k) return false;
  for (size_t i = 0; i < n; ++i)
    if ((t[i] | 0x20) != kw[i]) return false;
  return true;
}

inline bool AsciiParser::iprefix(const char* t, size_t n, const char* kw) {
  size_t k = std::strlen(kw);
  if (n < k) return false;
  for (size_t i = 0; i < k; ++i)
    if ((t[i] | 0x20) != kw[i]) return false;
  return true;
}

inline std::string AsciiParser::show(const char* t, size_t n) {
  std::string s(t, std::min<size_t>(n, 40));
  for (char& c : s)
    if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) c = '?';
  if (n > 40) s += "...";
  return s;
}

inline void AsciiParser::unexpected(const char* expected, const char* t, size_t n) {
  fail(Code::AsciiSyntax,
       format("expected %s but found '%s' at line %llu", expected, show(t, n).c_str(), (unsigned long long)tokenLine),
       tokenLine, tokenOffset);
}

inline void AsciiParser::token(const char* t, size_t n) {
  switch (state) {
    case ExpectSolid:
      if (iprefix(t, n, "solid")) {
        if (!decided) {
          decided = true;
          isSolid = true;
        }
        name.assign(t + 5, std::min(n - 5, kMaxNameBytes + 1));
        nameCut = false;
        nameLine = tokenLine;
        state = SolidName;
        return;
      }
      if (!decided) {
        decided = true;
        isSolid = false;
        return;
      }
      unexpected("'solid'", t, n);
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
      unexpected("'facet' or 'endsolid'", t, n);
      return;
    case AfterFacet:
      if (ieq(t, n, "normal")) {
        state = NormalNums;
        numIndex = 0;
        return;
      }
      if (ieq(t, n, "outer")) {
        state = ExpectLoop;
        return;
      }
      unexpected("'normal' or 'outer' after 'facet'", t, n);
      return;
    case NormalNums:
    case VertexNums: {
      float v;
      if (number(t, n, v)) putNumber(v);
      return;
    }
    case ExpectOuter:
      if (ieq(t, n, "outer")) {
        state = ExpectLoop;
        return;
      }
      unexpected("'outer'", t, n);
      return;
    case ExpectLoop:
      if (ieq(t, n, "loop")) {
        state = ExpectVertexOrEndloop;
        return;
      }
      unexpected("'loop'", t, n);
      return;
    case ExpectVertexOrEndloop:
      if (ieq(t, n, "vertex")) {
        if (vertexCount == 3) {
          fail(Code::AsciiSyntax,
               format("facet at line %llu has more than 3 vertices (line %llu)", (unsigned long long)facetLine,
                      (unsigned long long)tokenLine),
               tokenLine, tokenOffset);
          return;
        }
        state = VertexNums;
        numIndex = 0;
        return;
      }
      if (ieq(t, n, "endloop")) {
        if (vertexCount != 3) {
          fail(Code::AsciiSyntax,
               format("facet at line %llu has %d vertices, expected 3 (line %llu)", (unsigned long long)facetLine,
                      vertexCount, (unsigned long long)tokenLine),
               tokenLine, tokenOffset);
          return;
        }
        state = SkipLine;
        afterSkip = ExpectEndfacet;
        return;
      }
      unexpected("'vertex' or 'endloop'", t, n);
      return;
    case ExpectEndfacet:
      if (ieq(t, n, "endfacet")) {
        if (!b.add(normal, verts, 0, facetOffset, facetLine)) return;
        state = SkipLine;
        afterSkip = ExpectFacetOrEnd;
        return;
      }
      unexpected("'endfacet'", t, n);
      return;
    case SolidName:
    case SkipLine: return;  // not reached: handled by the line scanner
  }
}

inline void AsciiParser::putNumber(float v) {
  if (state == NormalNums) {
    normal[numIndex] = v;
    if (++numIndex == 3) state = ExpectOuter;
    return;
  }
  verts[vertexCount * 3 + numIndex] = v;
  if (++numIndex == 3) {
    ++vertexCount;
    state = ExpectVertexOrEndloop;
  }
}

inline bool AsciiParser::number(const char* t, size_t n, float& out) {
  if (n > kMaxNumberChars) {
    fail(Code::AsciiSyntax,
         format("number longer than %zu characters at line %llu", kMaxNumberChars, (unsigned long long)tokenLine),
         tokenLine, tokenOffset);
    return false;
  }
  if (parseFloat(t, n, out)) return true;
  fail(Code::AsciiSyntax,
       format("malformed number '%s' at line %llu", show(t, n).c_str(), (unsigned long long)tokenLine), tokenLine,
       tokenOffset);
  return false;
}

inline const uint8_t* AsciiParser::skipBlanks(const uint8_t* q, const uint8_t* end, uint64_t& ln, bool& cr) {
  for (; q < end && isSpace(*q); ++q) {
    ln += (*q == '\r') | ((*q == '\n') & !cr);
    cr = *q == '\r';
  }
  return q;
}

inline size_t AsciiParser::tokenEnd(const uint8_t* p, size_t i, size_t n) {
  for (; i + 8 <= n; i += 8)
    if (uint64_t stops = tokenStops(load8(p + i))) return i + (unsigned(__builtin_ctzll(stops)) >> 3);
  while (i < n && p[i] > 0x20 && p[i] != 0x7f) ++i;
  return i;
}

inline size_t AsciiParser::fastFacet(const uint8_t* p, size_t i, size_t n, uint64_t base) {
  const uint8_t* end = p + n - 16;  // every token starts before end: 16 bytes of slack
  const uint8_t* q = p + i;
  uint64_t ln = line;
  // The helpers below are always inlined: left to itself, clang keeps some of them out of
  // line in the wasm build, which made ASCII loads 8% slower there (bench/PROFILE.md).
  // The whitespace after a token (sawCR is false at a token).
  auto blanks = [&](const uint8_t* from) __attribute__((always_inline)) {
    if (*from == ' ' && !isSpace(from[1])) {  // the usual single space
      q = from + 1;
      return q < end;
    }
    bool cr = false;
    q = skipBlanks(from, end, ln, cr);
    return q < end;
  };
  // A keyword, then the whitespace after it.
  auto word = [&](const Keyword& kw) __attribute__((always_inline)) { return keywordAt(q, kw) && blanks(q + kw.len); };
  // A number, then the whitespace after it.
  auto number = [&](float& v) __attribute__((always_inline)) {
    const char* e = parseDecimal(reinterpret_cast<const char*>(q), reinterpret_cast<const char*>(end), v);
    return e && isSpace(uint8_t(*e)) && blanks(reinterpret_cast<const uint8_t*>(e));
  };
  // The rest of a line after a keyword, as state SkipLine reads it: blanks and text, no
  // control bytes. Leaves q at the line end.
  auto restOfLine = [&]() __attribute__((always_inline)) {
    for (; q < end && *q != '\n' && *q != '\r'; ++q)
      if (*q < 0x20 && *q != '\t' && *q != '\v' && *q != '\f') return false;
    return q < end;
  };
  const uint8_t* facetAt = q;
  uint64_t facetLn = ln;
  float nv[3], vv[9];
  if (!blanks(q + kFacet.len) || !word(kNormal) || !number(nv[0]) || !number(nv[1]) || !number(nv[2]) ||
      !word(kOuter) || !word(kLoop))
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

void AsciiParser::feed(const uint8_t* p, size_t n) {
  size_t i = 0;
  // An optional UTF-8 byte-order mark at offset 0.
  while (!bomChecked && i < n) {
    static const uint8_t kBom[3] = {0xEF, 0xBB, 0xBF};
    if (p[i] == kBom[bomHave]) {
      ++bomHave;
      ++i;
      ++offset;
      if (bomHave == 3) bomChecked = true;
    } else {
      if (bomHave > 0) {
        decided = true;
        isSolid = false;
        return;
      }  // a broken BOM
      bomChecked = true;
    }
  }
  const uint64_t base = offset - i;  // the offset of p[0]
  offset = base + scan(p, i, n, base);
}

inline size_t AsciiParser::scan(const uint8_t* p, size_t i, size_t n, uint64_t base) {
  while (i < n && !dead()) {
    if (state == SolidName || state == SkipLine) {
      size_t j = i;
      while (j < n && p[j] != '\n' && p[j] != '\r') {
        if (p[j] < 0x20 && p[j] != '\t' && p[j] != '\v' && p[j] != '\f') {
          badByte(p[j], base + j);
          return i;
        }
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
      if (j < n && !isSpace(p[j])) {
        badByte(p[j], base + j);
        return i;
      }
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
    if (j < n && !isSpace(p[j])) {
      badByte(p[j], base + j);
      return i;
    }  // a control byte (j may be i)
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

void AsciiParser::endCarry() {
  inToken = false;
  token(carry.data(), carry.size());
  carry.clear();
}

inline void AsciiParser::badByte(uint8_t c, uint64_t at) {
  if (!decided) {
    decided = true;
    isSolid = false;
    return;
  }
  binaryLooking = true;
  fail(Code::AsciiSyntax,
       format("unexpected byte 0x%02X at offset %llu (line %llu): not ASCII STL text", c, (unsigned long long)at,
              (unsigned long long)line),
       line, at);
}

inline void AsciiParser::openSolid() {
  const char* nb = name.data();
  const char* ne = nb + std::min(name.size(), kMaxNameBytes);
  trim(nb, ne);
  if (name.size() > kMaxNameBytes) {
    // Cut at a UTF-8 character boundary.
    while (ne > nb && (static_cast<unsigned char>(ne[-1]) & 0xC0) == 0x80) --ne;
    if (ne > nb && static_cast<unsigned char>(ne[-1]) >= 0xC0) --ne;
    if (!b.addWarning(Code::NameTruncated,
                      format("solid name at line %llu is longer than %zu bytes and was cut",
                             (unsigned long long)nameLine, kMaxNameBytes),
                      kNoOffset, nameLine))
      return;
  }
  if (!b.beginSolid(nb, size_t(ne - nb), nullptr)) return;
  name.clear();
}

Status AsciiParser::end() {
  if (b.failed()) return b.error;
  if (inToken) {
    endCarry();
    if (b.failed()) return b.error;
  }
  State s = state == SkipLine ? afterSkip : state;
  switch (s) {
    case ExpectSolid: return Status{};  // after endsolid (or between solids)
    case SolidName: openSolid(); [[fallthrough]];
    case ExpectFacetOrEnd:
      b.endSolid();
      b.addWarning(Code::MissingEndsolid,
                   format("the file ends after line %llu without 'endsolid'", (unsigned long long)tokenLine), offset,
                   tokenLine);
      return Status{};
    default:
      return Status::error(Code::UnexpectedEnd,
                           format("the file ends after line %llu inside the facet that starts at line %llu",
                                  (unsigned long long)tokenLine, (unsigned long long)facetLine),
                           offset, tokenLine);
  }
}

}  // namespace stltopo::detail
