// The ASCII STL parser: a token state machine that survives any chunking, with a fast
// path for whole facets written the usual way. Feeds a Builder.
#pragma once

#include <string>

#include "mesh_builder.h"

namespace stltopo::detail {

// ASCII parser: a token state machine that survives any chunking.
struct AsciiParser {
  enum State : uint8_t {
    ExpectSolid,
    SolidName,
    ExpectFacetOrEnd,
    AfterFacet,
    NormalNums,
    ExpectOuter,
    ExpectLoop,
    ExpectVertexOrEndloop,
    VertexNums,
    ExpectEndfacet,
    SkipLine,
  };
  Builder b;
  State state = ExpectSolid;
  State afterSkip = ExpectSolid;
  bool isSolid = false;        // first token began with "solid"
  bool decided = false;        // we know whether the file starts with "solid"
  bool binaryLooking = false;  // died on a control byte
  bool sawCR = false;
  uint64_t line = 1;
  uint64_t offset = 0;
  uint64_t tokenOffset = 0, tokenLine = 1;
  std::string carry;  // a token split across chunks
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
  // Reserves carry and name at their limits, so that the parser never allocates while it
  // reads. False when that fails (then the parser must not be fed).
  bool reserveBuffers() { return tryReserve(carry, kMaxCarry) && tryReserve(name, kMaxNameBytes + 1); }

  bool dead() const { return b.failed() || (decided && !isSolid); }

  void fail(Code c, std::string msg, uint64_t atLine, uint64_t atOffset);

  static bool ieq(const char* t, size_t n, const char* kw);
  static bool iprefix(const char* t, size_t n, const char* kw);

  std::string show(const char* t, size_t n);

  // ascii-syntax at the current token: "expected <expected> but found '<token>' at line N".
  void unexpected(const char* expected, const char* t, size_t n);
  void token(const char* t, size_t n);

  // A number of the current facet (in state NormalNums or VertexNums).
  void putNumber(float v);

  bool number(const char* t, size_t n, float& out);

  // Skips whitespace in [q, end), counting lines in ln: CR, LF and CRLF each end one (cr:
  // the byte before q was a CR). Returns the first other byte, or end.
  static inline const uint8_t* skipBlanks(const uint8_t* q, const uint8_t* end, uint64_t& ln, bool& cr);

  // The end of the token at i: the first byte <= 0x20 or 0x7F (whitespace or a bad byte),
  // or n. 8 bytes per step while they last, then one at a time.
  static size_t tokenEnd(const uint8_t* p, size_t i, size_t n);

  // Fast path for a whole facet in the chunk, written the usual way:
  //   facet normal N N N  outer loop  vertex N N N (3 times)  endloop  endfacet
  // with whitespace between the tokens and only blanks after endloop and endfacet on their
  // lines. Parses p[i, n) (at least kFastFacetRoom bytes, 'facet' at i) to the end of the
  // line of 'endfacet' and adds the triangle, leaving the state exactly as the token
  // machine would; returns the position reached. Returns 0 and changes nothing when the
  // text differs in any way (another keyword, a number off the fast path, a bad byte, too
  // near the end of the chunk...): the token machine then reads the facet.
  static constexpr size_t kFastFacetRoom = 256;
  size_t fastFacet(const uint8_t* p, size_t i, size_t n, uint64_t base);

  void feed(const uint8_t* p, size_t n);

  // Parses p[i, n); returns where it stopped (n, or the place of an error).
  size_t scan(const uint8_t* p, size_t i, size_t n, uint64_t base);

  void endCarry();

  void badByte(uint8_t c, uint64_t at);

  void openSolid();

  // Outcome at end of input.
  Status end();
};
}  // namespace stltopo::detail
