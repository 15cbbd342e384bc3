// Fuzz target: edit sequences on an EditableMesh. Input: [base][base parameters][edit bytes].
//   base % 4 == 0: a torus grid, [n][m][hole mask] (3..10 x 3..10 quads, up to 8 quads left out)
//   base % 4 == 1: two cubes sharing a side (non-manifold edges)
//   base % 4 == 2: two cubes touching at a corner (a non-manifold vertex)
//   base % 4 == 3: [length lo][length hi][STL bytes] read with readStl (a read error ends the
//                  input); base & 4 builds the topology with a tolerance of 0.01.
// The remaining bytes choose up to 64 edits (tests/edit_check.h RandomEditor: each choice of a
// number below n takes 1 byte, or 2 or 4 when n is larger). After every edit: a refused
// edit changed nothing and carries its code; a done edit leaves validate() holding and a
// topology equal, array by array, to buildTopology of the compacted mesh, and stats(),
// loops() and infoJson() equal to that build's.
#include "../edit_check.h"
#include "fuzz_common.h"

using namespace stltopo;

namespace {
struct BytePick {
  const uint8_t* p;
  size_t n;
  bool exhausted = false;
  uint32_t byte() {
    if (n == 0) {
      exhausted = true;
      return 0;
    }
    --n;
    return *p++;
  }
  uint32_t operator()(uint32_t bound) {
    if (bound <= 1) return 0;
    uint32_t v = byte();
    if (bound > 256) v |= byte() << 8;
    if (bound > 65536) v |= (byte() << 16) | (byte() << 24);
    return v % bound;
  }
};
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  BytePick pick{data, size};
  const uint32_t base = pick.byte();
  Mesh m;
  TopologyOptions o;
  switch (base % 4) {
    case 0: {
      int n = 3 + int(pick.byte() % 8), k = 3 + int(pick.byte() % 8);
      uint32_t mask = pick.byte();
      std::vector<int> skip;
      for (int i = 0; i < 8; ++i)
        if (mask & (1u << i)) skip.push_back((i * 7) % (n * k));
      Status s = gen::read(gen::binary(gen::torus(n, k, skip)), m);
      FUZZ_CHECK(s.ok());
      break;
    }
    case 1:
    case 2: {
      gen::Soup two = gen::cube();
      gen::append(two, base % 4 == 1 ? gen::cube(1, 0, 0) : gen::cube(1, 1, 1));
      Status s = gen::read(gen::binary(two), m);
      FUZZ_CHECK(s.ok());
      break;
    }
    default: {
      size_t len = pick.byte();
      len |= size_t(pick.byte()) << 8;
      len = std::min(len, pick.n);
      Status s = readStl(pick.p, len, m);
      pick.p += len;
      pick.n -= len;
      if (!s.ok()) return 0;
      if (base & 4) o.tolerance = 0.01;
      break;
    }
  }
  EditableMesh em;
  Status s = em.init(m, o);
  FUZZ_CHECK(s.ok());
  std::string d = editcheck::differenceFromRebuild(em);
  if (!d.empty()) {
    std::fprintf(stderr, "before any edit: %s\n", d.c_str());
    FUZZ_CHECK(d.empty());
  }
  editcheck::RandomEditor<BytePick> ed(em, pick);
  for (int i = 0; i < 64 && !pick.exhausted; ++i) {
    std::string what;
    d = ed.step(what);
    if (!d.empty()) {
      std::fprintf(stderr, "edit %d (%s): %s\n", i, what.c_str(), d.c_str());
      FUZZ_CHECK(d.empty());
    }
  }
  return 0;
}
