// Meshes from indexed triangle lists: the same mesh and topology as reading, the welds,
// and a coded error for every kind of bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "stl_gen.h"
#include "stltopo.h"

#ifndef STLTOPO_FIXTURES
#error "STLTOPO_FIXTURES must name the tests/fixtures directory"
#endif

namespace {

using gen::sameArray;
using stltopo::Code;
using stltopo::IndexedMesh;
using stltopo::Mesh;
using stltopo::Topology;

IndexedMesh viewOf(const Mesh& m, bool withAttributes = true) {
  IndexedMesh in;
  in.positions = m.positions.data();
  in.positionsLength = m.positions.size();
  in.triangles = m.triangles.data();
  in.trianglesLength = m.triangles.size();
  if (withAttributes) in.attributes = m.attributes.data();
  in.solids = m.solids.data();
  in.nSolids = m.solids.size();
  return in;
}

// The topology arrays and counts of two meshes agree.
void expectSameTopology(const Mesh& a, const Mesh& b, const std::string& what) {
  Topology ta, tb;
  ASSERT_TRUE(stltopo::buildTopology(a, ta).ok()) << what;
  ASSERT_TRUE(stltopo::buildTopology(b, tb).ok()) << what;
  EXPECT_TRUE(stltopo::validate(b, tb).ok()) << what;
#define SAME(f) EXPECT_TRUE(sameArray(ta.f, tb.f)) << what << ": " #f;
  SAME(next)
  SAME(prev) SAME(vert) SAME(face) SAME(pairKind) SAME(triangleHalfedge) SAME(vertexHalfedge) SAME(loopHalfedge)
      SAME(loopOffsets) SAME(loopHalfedges) SAME(loopIsSeam) SAME(triangleDegenerate) SAME(vertexNonManifold)
#undef SAME
      // The report's topology part (format, normals and warnings come from the file).
      std::string ja = stltopo::infoJson("f", a, &ta),
                  jb = stltopo::infoJson("f", b, &tb);
  EXPECT_EQ(ja.substr(ja.find("\"edges\"")), jb.substr(jb.find("\"edges\""))) << what;
  EXPECT_EQ(ja.substr(ja.find("\"bbox\""), ja.find("\"warnings\"") - ja.find("\"bbox\"")),
            jb.substr(jb.find("\"bbox\""), jb.find("\"warnings\"") - jb.find("\"bbox\"")))
      << what;
}

TEST(FromIndexed, EveryFixtureGivesTheMeshAndTopologyOfReading) {
  size_t n = 0;
  for (const std::string& f : gen::fixtureFiles()) {
    Mesh read;
    if (!gen::read(gen::readFile(f), read).ok()) continue;
    ++n;
    // The read mesh's own arrays, and the unwelded soup (one vertex per corner).
    std::vector<float> soup;
    std::vector<uint32_t> corners;
    for (uint32_t c = 0; c < read.triangles.size(); ++c) {
      const float* p = read.positions.data() + 3 * size_t(read.triangles[c]);
      soup.insert(soup.end(), p, p + 3);
      corners.push_back(c);
    }
    bool magics = read.colorConvention == stltopo::ColorConvention::Magics;  // needs its header
    for (int variant = 0; variant < 2; ++variant) {
      IndexedMesh in = viewOf(read);
      if (variant == 1) {
        in.positions = soup.data();
        in.positionsLength = soup.size();
        in.triangles = corners.data();
        in.trianglesLength = corners.size();
      }
      Mesh m;
      stltopo::Array<uint32_t> map;
      ASSERT_TRUE(stltopo::meshFromIndexed(in, m, &map).ok()) << f;
      std::string what = f + (variant ? " (soup)" : " (indexed)");
      EXPECT_TRUE(sameArray(read.positions, m.positions)) << what;
      EXPECT_TRUE(sameArray(read.triangles, m.triangles)) << what;
      EXPECT_TRUE(sameArray(read.attributes, m.attributes)) << what;
      if (!magics) {
        EXPECT_EQ(read.colorConvention, m.colorConvention) << what;
        EXPECT_TRUE(sameArray(read.colors, m.colors)) << what;
      }
      EXPECT_EQ(read.area, m.area) << what;
      EXPECT_EQ(read.volume, m.volume) << what;
      ASSERT_EQ(read.solids.size(), m.solids.size()) << what;
      for (size_t s = 0; s < m.solids.size(); ++s) {
        EXPECT_EQ(read.solids[s].name, m.solids[s].name);
        EXPECT_EQ(read.solids[s].triangleCount, m.solids[s].triangleCount);
      }
      // The map takes each caller vertex to its welded vertex.
      ASSERT_EQ(map.size(), in.positionsLength / 3);
      for (size_t c = 0; c < in.trianglesLength; ++c) EXPECT_EQ(map[in.triangles[c]], m.triangles[c]) << what;
      if (!magics) expectSameTopology(read, m, what);
    }
  }
  EXPECT_GE(n, 50u);
}

// A cube as renderers index it: 4 vertices per side (24), so that every side has its own
// normals and UVs; the sides share positions but no vertex ids.
Mesh seamCube(stltopo::Weld weld, stltopo::Array<uint32_t>* map = nullptr) {
  gen::Soup c = gen::cube();
  std::vector<float> pos;
  std::vector<uint32_t> tri;
  for (size_t t = 0; t < c.f.size(); t += 2) {  // two triangles per side
    uint32_t base = uint32_t(pos.size() / 3);
    std::vector<uint32_t> local;
    for (size_t k = t; k < t + 2; ++k)
      for (uint32_t v : c.f[k]) {
        auto at = std::find(local.begin(), local.end(), v);
        if (at == local.end()) {
          local.push_back(v);
          pos.insert(pos.end(), c.v[v].begin(), c.v[v].end());
          at = local.end() - 1;
        }
        tri.push_back(base + uint32_t(at - local.begin()));
      }
  }
  EXPECT_EQ(pos.size(), 24u * 3);
  IndexedMesh in;
  in.positions = pos.data();
  in.positionsLength = pos.size();
  in.triangles = tri.data();
  in.trianglesLength = tri.size();
  stltopo::IndexedOptions o;
  o.weld = weld;
  Mesh m;
  EXPECT_TRUE(stltopo::meshFromIndexed(in, m, map, o).ok());
  return m;
}

TEST(FromIndexed, ExactWeldClosesRendererSeamsAndNoneKeepsThem) {
  stltopo::Array<uint32_t> map;
  Mesh welded = seamCube(stltopo::Weld::Exact, &map);
  Topology t;
  ASSERT_TRUE(stltopo::buildTopology(welded, t).ok());
  EXPECT_EQ(welded.nVertices(), 8u);
  EXPECT_TRUE(t.watertight());
  EXPECT_EQ(t.nHoles, 0u);
  ASSERT_EQ(map.size(), 24u);
  for (uint32_t v : map) EXPECT_LT(v, 8u);

  Mesh kept = seamCube(stltopo::Weld::None, &map);
  ASSERT_TRUE(stltopo::buildTopology(kept, t).ok());
  EXPECT_EQ(kept.nVertices(), 24u);
  EXPECT_EQ(t.nHoles, 6u);  // each side a square with its own boundary
  EXPECT_EQ(t.nShells, 6u);
  EXPECT_TRUE(stltopo::validate(kept, t).ok());
  for (uint32_t v = 0; v < 24; ++v) EXPECT_EQ(map[v], v);
  // The tolerance weld works on it as on a file.
  stltopo::TopologyOptions tol;
  tol.tolerance = 1e-6;
  ASSERT_TRUE(stltopo::buildTopology(kept, t, tol).ok());
  EXPECT_TRUE(t.watertight());
}

TEST(FromIndexed, ColoursBecomeVisCamWordsAndWriteOut) {
  Mesh cube;
  ASSERT_TRUE(gen::read(gen::binary(gen::cube()), cube).ok());
  std::vector<uint8_t> rgb, valid;
  for (int t = 0; t < 12; ++t) {
    rgb.insert(rgb.end(), {uint8_t(t * 20), uint8_t(255 - t), 7});
    valid.push_back(t != 4);
  }
  IndexedMesh in = viewOf(cube, false);
  in.colors = rgb.data();
  in.colorValid = valid.data();
  Mesh m;
  ASSERT_TRUE(stltopo::meshFromIndexed(in, m).ok());
  EXPECT_EQ(m.colorConvention, stltopo::ColorConvention::VisCam);
  EXPECT_TRUE(std::equal(rgb.begin(), rgb.end(), m.colors.begin()));
  EXPECT_EQ(m.attributes[4], 0u);
  std::string bytes;
  ASSERT_TRUE(stltopo::writeStl(
                  m,
                  [](void* u, const uint8_t* d, size_t n) {
                    static_cast<std::string*>(u)->append(reinterpret_cast<const char*>(d), n);
                    return true;
                  },
                  &bytes)
                  .ok());
  Mesh back;
  ASSERT_TRUE(gen::read(bytes, back).ok());
  EXPECT_TRUE(sameArray(m.attributes, back.attributes));
  EXPECT_TRUE(sameArray(m.positions, back.positions));
  EXPECT_TRUE(sameArray(m.triangles, back.triangles));
  for (int t = 0; t < 12; ++t) {
    EXPECT_EQ(back.colorValid[t], valid[t]);
    if (valid[t])  // 5 bits per channel
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(back.colors[3 * t + c], rgb[3 * t + c], 4) << t;
  }
}

TEST(FromIndexed, BadInputGivesCodedErrorsAndLeavesOutUntouched) {
  Mesh cube;
  ASSERT_TRUE(gen::read(gen::binary(gen::cube()), cube).ok());
  std::vector<float> pos(cube.positions.begin(), cube.positions.end());
  std::vector<uint32_t> tri(cube.triangles.begin(), cube.triangles.end());
  auto attempt = [&](IndexedMesh in) {
    Mesh out;
    out.area = 42;
    stltopo::Array<uint32_t> map;
    (void)map.assign(3, 7);
    stltopo::Status s = stltopo::meshFromIndexed(in, out, &map);
    EXPECT_EQ(out.area, 42);
    EXPECT_EQ(map.size(), 3u);
    EXPECT_NE(s.message.find(stltopo::codeName(s.code)), std::string::npos);
    return s;
  };
  IndexedMesh good;
  good.positions = pos.data();
  good.positionsLength = pos.size();
  good.triangles = tri.data();
  good.trianglesLength = tri.size();

  IndexedMesh in = good;
  in.trianglesLength -= 1;
  EXPECT_EQ(attempt(in).code, Code::InvalidArgument);
  in = good;
  in.positionsLength -= 2;
  EXPECT_EQ(attempt(in).code, Code::InvalidArgument);

  tri[3 * 7 + 1] = 8;
  stltopo::Status s = attempt(good);
  EXPECT_EQ(s.code, Code::InvalidIndex);
  EXPECT_EQ(s.triangle, 7u);
  tri[3 * 7 + 1] = cube.triangles[3 * 7 + 1];

  pos[3 * 5 + 2] = std::numeric_limits<float>::quiet_NaN();
  s = attempt(good);
  EXPECT_EQ(s.code, Code::NonFinite);
  EXPECT_EQ(s.element, 5u);
  pos[3 * 5 + 2] = std::numeric_limits<float>::infinity();
  EXPECT_EQ(attempt(good).element, 5u);
  pos[3 * 5 + 2] = cube.positions[3 * 5 + 2];

  // More than 2^32 - 2 elements: refused from the lengths alone, before any array is read
  // (a 32-bit size_t, as in wasm32, cannot hold such a length).
  if constexpr (sizeof(size_t) > 4) {
    in = good;
    in.trianglesLength = 3 * uint64_t(0xFFFFFFFFu);
    EXPECT_EQ(attempt(in).code, Code::TooLarge);
    in = good;
    in.positionsLength = 3 * uint64_t(0xFFFFFFFFu);
    EXPECT_EQ(attempt(in).code, Code::TooLarge);
  }

  std::vector<stltopo::Solid> solids = {{"a", 0, 8}, {"b", 6, 6}};
  in = good;
  in.solids = solids.data();
  in.nSolids = solids.size();
  s = attempt(in);
  EXPECT_EQ(s.code, Code::InvalidArgument);
  EXPECT_NE(s.message.find("overlaps"), std::string::npos) << s.message;
  solids = {{"a", 0, 6}, {"b", 6, 7}};
  s = attempt(in);
  EXPECT_EQ(s.code, Code::InvalidArgument);
  EXPECT_NE(s.message.find("runs past"), std::string::npos) << s.message;

  std::vector<uint16_t> attrs(12, 0);
  std::vector<uint8_t> rgb(36, 0);
  in = good;
  in.attributes = attrs.data();
  in.colors = rgb.data();
  EXPECT_EQ(attempt(in).code, Code::InvalidArgument);

  // Solids with gaps: the gaps become unnamed solids, as in writing.
  solids = {{"middle", 4, 4}};
  in = good;
  in.solids = solids.data();
  in.nSolids = 1;
  Mesh m;
  ASSERT_TRUE(stltopo::meshFromIndexed(in, m).ok());
  ASSERT_EQ(m.solids.size(), 3u);
  EXPECT_EQ(m.solids[1].name, "middle");
  EXPECT_EQ(m.solids[2].firstTriangle, 8u);
}

}  // namespace
