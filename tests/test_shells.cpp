// Shells and defects: the per-shell report and the defect lists on hand-built meshes
// (two cubes one inside out, a flipped face, a soup, a bowtie, a non-manifold fin, two
// cubes sharing an edge) and on every fixture, where a brute-force count from the
// triangles alone (maps of edges, no half-edges) is the judge.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <numeric>
#include <random>
#include <set>

#if !defined(STLTOPO_WASM_TESTS)
#include <sys/wait.h>
#endif

#include "stl_gen.h"
#include "stltopo/geometry.h"
#include "stltopo/report.h"
#include "stltopo/shells.h"

using namespace stltopo;

namespace {

// Edge-connected components of the non-degenerate triangles (corners welded by
// vertexWeld), numbered by their lowest triangle id; kInvalid for degenerate triangles.
std::vector<uint32_t> triangleShellOf(const Mesh& m, const Topology& t) {
  const uint32_t nt = m.nTriangles();
  std::vector<uint32_t> parent(nt);
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  auto corner = [&](uint32_t tri, int c) { return t.vertexWeld[m.triangles[3 * size_t(tri) + c]]; };
  std::map<std::pair<uint32_t, uint32_t>, uint32_t> firstOnEdge;
  std::vector<bool> degenerate(nt);
  for (uint32_t tri = 0; tri < nt; ++tri) {
    uint32_t v[3] = {corner(tri, 0), corner(tri, 1), corner(tri, 2)};
    degenerate[tri] = v[0] == v[1] || v[1] == v[2] || v[2] == v[0];
    if (degenerate[tri]) continue;
    for (int c = 0; c < 3; ++c) {
      auto key = std::minmax(v[c], v[(c + 1) % 3]);
      auto [it, inserted] = firstOnEdge.try_emplace(key, tri);
      if (inserted) continue;
      uint32_t a = find(it->second), b = find(tri);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  }
  std::vector<uint32_t> shell(nt, kInvalid), idOfRoot(nt, kInvalid);
  uint32_t n = 0;
  for (uint32_t tri = 0; tri < nt; ++tri) {
    if (degenerate[tri]) continue;
    uint32_t r = find(tri);
    if (idOfRoot[r] == kInvalid) idOfRoot[r] = n++;
    shell[tri] = idOfRoot[r];
  }
  return shell;
}

struct Analyzed {
  Mesh mesh;
  Topology topo;
  std::vector<uint32_t> triangleShell;
  Array<Shell> shells;
  Defects defects;
};

// Reads `bytes`, builds the full topology with triangleShell, checks triangleShell
// against an independent union-find and validate(), builds the shells and defects, and
// checks that the report-only topology (no prev, no face) gives the same report.
void analyze(const std::string& bytes, Analyzed& a, double tolerance = 0) {
  Status s = gen::read(bytes, a.mesh);
  ASSERT_TRUE(s.ok()) << s.message;
  TopologyOptions o;
  o.tolerance = tolerance;
  o.triangleShell = true;
  ASSERT_TRUE(buildTopology(a.mesh, a.topo, o).ok());
  a.triangleShell = triangleShellOf(a.mesh, a.topo);
  ASSERT_EQ(std::vector<uint32_t>(a.topo.triangleShell.begin(), a.topo.triangleShell.end()), a.triangleShell);
  s = validate(a.mesh, a.topo);
  ASSERT_TRUE(s.ok()) << s.message;
  s = findShellsAndDefects(a.mesh, a.topo, &a.shells, &a.defects);
  ASSERT_TRUE(s.ok()) << s.message;
  ASSERT_EQ(a.shells.size(), a.topo.nShells);
  o.prevAndFace = false;
  Topology lean;
  ASSERT_TRUE(buildTopology(a.mesh, lean, o).ok());
  Array<Shell> leanShells;
  Defects leanDefects;
  ASSERT_TRUE(findShellsAndDefects(a.mesh, lean, &leanShells, &leanDefects).ok());
  EXPECT_EQ(shellListJson(leanShells), shellListJson(a.shells));
  EXPECT_EQ(defectsJson(a.mesh, lean, leanDefects, 1000), defectsJson(a.mesh, a.topo, a.defects, 1000));
}

void analyze(const gen::Soup& soup, Analyzed& a) { analyze(gen::binary(soup), a); }

gen::Soup flipped(gen::Soup s) {
  for (auto& f : s.f) std::swap(f[1], f[2]);
  return s;
}

// A fragment of the JSON must appear as is.
#define EXPECT_HAS(text, fragment) EXPECT_NE((text).find(fragment), std::string::npos) << (text)

}  // namespace

TEST(Shells, TwoCubesOneInsideOutAreOutwardAndInward) {
  gen::Soup s = gen::cube();
  gen::append(s, flipped(gen::cube(3, 0, 0, 2)));
  Analyzed a;
  analyze(s, a);
  ASSERT_EQ(a.shells.size(), 2u);
  for (const Shell& sh : a.shells) {
    EXPECT_EQ(sh.triangles, 12u);
    EXPECT_EQ(sh.vertices, 8u);
    EXPECT_EQ(sh.edges, 18u);
    EXPECT_EQ(sh.eulerCharacteristic(), 2);
    EXPECT_TRUE(sh.closed());
    EXPECT_TRUE(sh.manifold());
    EXPECT_TRUE(sh.consistent());
    EXPECT_TRUE(sh.hasGenus());
    EXPECT_EQ(sh.genus(), 0);
  }
  EXPECT_EQ(a.shells[0].orientation(), Orientation::Outward);
  EXPECT_DOUBLE_EQ(a.shells[0].volume, 1);
  EXPECT_DOUBLE_EQ(a.shells[0].area, 6);
  EXPECT_EQ(a.shells[1].orientation(), Orientation::Inward);
  EXPECT_DOUBLE_EQ(a.shells[1].volume, -8);
  EXPECT_EQ(a.shells[1].firstTriangle, 12u);
  EXPECT_EQ(a.shells[1].bboxMin[0], 3);
  EXPECT_EQ(a.shells[1].bboxMax[0], 5);
  std::string j = shellListJson(a.shells);
  EXPECT_EQ(j.substr(0, 13), "\"shellList\":[");
  EXPECT_HAS(j,
             "{\"id\":1,\"triangles\":12,\"vertices\":8,\"edges\":18,\"boundaryEdges\":0,\"nonManifoldEdges\":0,"
             "\"inconsistentEdges\":0,\"nonManifoldVertices\":0,\"holes\":0,\"seams\":0,\"eulerCharacteristic\":2,"
             "\"genus\":0,\"closed\":true,\"manifold\":true,\"consistent\":true,\"orientation\":\"inward\",\"solid\":0,"
             "\"bbox\":{\"min\":[3,0,0],\"max\":[5,2,2]},\"area\":");
  std::string d = defectsJson(a.mesh, a.topo, a.defects, 1000);
  EXPECT_EQ(d,
            "\"defects\":{\"holes\":{\"count\":0,\"items\":[]},\"seams\":{\"count\":0,\"items\":[]},"
            "\"nonManifoldEdges\":{\"count\":0,\"items\":[]},\"inconsistentEdges\":{\"count\":0,\"items\":[]},"
            "\"nonManifoldVertices\":{\"count\":0,\"items\":[]},\"degenerateTriangles\":{\"count\":0,\"items\":[]},"
            "\"zeroAreaTriangles\":{\"count\":0,\"items\":[]},\"duplicateTriangles\":{\"count\":0,\"items\":[]},"
            "\"selfIntersections\":null}");
  EXPECT_EQ(defectsText(a.mesh, a.topo, a.defects, 5), "");
}

TEST(Shells, CubeWithOneFlippedFaceIsInconsistentWithThreeLocatedEdges) {
  gen::Soup s = gen::cube();
  std::swap(s.f[5][1], s.f[5][2]);
  Analyzed a;
  analyze(s, a);
  ASSERT_EQ(a.shells.size(), 1u);
  const Shell& sh = a.shells[0];
  EXPECT_EQ(sh.inconsistentEdges, 3u);
  EXPECT_EQ(sh.boundaryEdges, 0u);
  EXPECT_EQ(sh.edges, 18u);
  EXPECT_EQ(sh.seams, 2u);
  EXPECT_FALSE(sh.closed());
  EXPECT_FALSE(sh.consistent());
  EXPECT_FALSE(sh.hasGenus());
  EXPECT_EQ(sh.orientation(), Orientation::Inconsistent);
  ASSERT_EQ(a.defects.inconsistentEdgeVertices.size(), 6u);
  // Each inconsistent edge joins the flipped triangle 5 and one of its neighbours.
  std::set<std::pair<uint32_t, uint32_t>> pairs;
  for (size_t i = 0; i < 3; ++i) {
    uint32_t x = a.defects.inconsistentEdgeVertices[2 * i], y = a.defects.inconsistentEdgeVertices[2 * i + 1];
    EXPECT_LT(x, y);
    if (i > 0)
      EXPECT_LT(
          std::make_pair(a.defects.inconsistentEdgeVertices[2 * i - 2], a.defects.inconsistentEdgeVertices[2 * i - 1]),
          std::make_pair(x, y));
    uint32_t t0 = a.defects.inconsistentEdgeTriangles[2 * i], t1 = a.defects.inconsistentEdgeTriangles[2 * i + 1];
    EXPECT_LT(t0, t1);
    EXPECT_TRUE(t0 == 5 || t1 == 5);
    pairs.insert({x, y});
  }
  EXPECT_EQ(pairs.size(), 3u);
  std::string j = shellListJson(a.shells);
  // Its corners are pinched: the flipped triangle's fan is cut off from the rest at each of
  // them (two vnext cycles), as in the whole report.
  EXPECT_EQ(sh.nonManifoldVertices, 3u);
  EXPECT_EQ(a.topo.nNonManifoldVertices, 3u);
  EXPECT_HAS(
      j, "\"genus\":null,\"closed\":false,\"manifold\":false,\"consistent\":false,\"orientation\":\"inconsistent\"");
  std::string d = defectsJson(a.mesh, a.topo, a.defects, 1000);
  EXPECT_HAS(d, "\"seams\":{\"count\":2,\"items\":[{\"id\":0,\"edges\":3,");
  EXPECT_HAS(d, "\"inconsistentEdges\":{\"count\":3,\"items\":[{\"vertices\":[");
  // Every side of the seams is cut, so cutEdges repeats the loop.
  EXPECT_HAS(d, "\"shell\":0,\"cutEdges\":[[");
  std::string text = defectsText(a.mesh, a.topo, a.defects, 5);
  EXPECT_HAS(text, "  seam 0: 3 edges (3 cut), perimeter ");
  EXPECT_HAS(text, "  inconsistent edge ");
}

TEST(Shells, SoupOfSeparateTrianglesIsOneOpenShellPerTriangle) {
  gen::Soup s;
  for (int i = 0; i < 3; ++i) {
    uint32_t b = uint32_t(s.v.size());
    s.v.push_back({float(2 * i), 0, 0});
    s.v.push_back({float(2 * i + 1), 0, 0});
    s.v.push_back({float(2 * i), 1, 0});
    s.f.push_back({b, b + 1, b + 2});
  }
  Analyzed a;
  analyze(s, a);
  ASSERT_EQ(a.shells.size(), 3u);
  for (uint32_t i = 0; i < 3; ++i) {
    const Shell& sh = a.shells[i];
    EXPECT_EQ(sh.firstTriangle, i);
    EXPECT_EQ(sh.triangles, 1u);
    EXPECT_EQ(sh.vertices, 3u);
    EXPECT_EQ(sh.edges, 3u);
    EXPECT_EQ(sh.boundaryEdges, 3u);
    EXPECT_EQ(sh.holes, 1u);
    EXPECT_EQ(sh.eulerCharacteristic(), 1);
    EXPECT_TRUE(sh.consistent());
    EXPECT_TRUE(sh.manifold());
    EXPECT_EQ(sh.orientation(), Orientation::Open);
    EXPECT_EQ(sh.volume, 0);
    EXPECT_EQ(sh.area, 0.5);
    EXPECT_EQ(a.defects.loopShell[i], i);
  }
  std::string d = defectsJson(a.mesh, a.topo, a.defects, 2);
  // Cut at 2 items, the count says 3; a hole's vertex list is cut at 2, "edges" is 3.
  EXPECT_HAS(d,
             "\"holes\":{\"count\":3,\"items\":[{\"id\":0,\"edges\":3,\"perimeter\":3.414213562373095,"
             "\"vertices\":[1,0],\"bbox\":{\"min\":[0,0,0],\"max\":[1,1,0]},\"shell\":0},{\"id\":1,");
  EXPECT_HAS(d, "\"shell\":1}]},\"seams\"");
  std::string text = defectsText(a.mesh, a.topo, a.defects, 2);
  EXPECT_HAS(text, "  hole 0: 3 edges, perimeter 3.41421356, shell 0, bbox [0, 0, 0] .. [1, 1, 0]\n");
  EXPECT_HAS(text, "    ... and 1 more holes\n");
}

TEST(Shells, BowtieIsTwoManifoldShellsAroundANonManifoldVertex) {
  gen::Soup s;
  s.v = {{0, 0, 0}, {1, 1, 0}, {1, -1, 0}, {-1, 1, 0}, {-1, -1, 0}};
  s.f = {{0, 2, 1}, {0, 3, 4}};
  Analyzed a;
  analyze(s, a);
  ASSERT_EQ(a.shells.size(), 2u);
  for (const Shell& sh : a.shells) {
    EXPECT_EQ(sh.vertices, 3u);  // the pinch vertex counts in both
    EXPECT_EQ(sh.nonManifoldVertices, 0u);
    EXPECT_TRUE(sh.manifold());
    EXPECT_EQ(sh.holes, 1u);
  }
  EXPECT_EQ(a.topo.nNonManifoldVertices, 1u);
  ASSERT_EQ(a.defects.nonManifoldVertices.size(), 1u);
  EXPECT_EQ(a.defects.nonManifoldVertices[0], 0u);
  EXPECT_EQ(a.defects.nonManifoldVertexCycles[0], 2u);
  std::string d = defectsJson(a.mesh, a.topo, a.defects, 1000);
  EXPECT_HAS(d, "\"nonManifoldVertices\":{\"count\":1,\"items\":[{\"vertex\":0,\"position\":[0,0,0],\"cycles\":2}]}");
  EXPECT_HAS(defectsText(a.mesh, a.topo, a.defects, 5), "  non-manifold vertex 0 at [0, 0, 0]: 2 vertex cycles\n");
}

TEST(Shells, TwoHolesTouchingAtAVertexMakeTheirShellNonManifold) {
  // The torus of test_topology's fan-rule case: two removed quads meet at one vertex.
  gen::Soup s = gen::torus(8, 6, {1 * 6 + 1, 2 * 6 + 2});
  Analyzed a;
  analyze(s, a);
  ASSERT_EQ(a.shells.size(), 1u);
  EXPECT_EQ(a.topo.nNonManifoldVertices, 1u);
  EXPECT_EQ(a.shells[0].nonManifoldVertices, 1u);
  EXPECT_FALSE(a.shells[0].manifold());
  EXPECT_EQ(a.shells[0].vertices, 48u);
}

TEST(Shells, NonManifoldFinListsItsEdgeWithEveryTriangle) {
  gen::Soup s = gen::cube();
  s.v.push_back({0.5f, 0.5f, 3});
  s.f.push_back({4, 5, 8});
  Analyzed a;
  analyze(s, a);
  ASSERT_EQ(a.shells.size(), 1u);
  const Shell& sh = a.shells[0];
  EXPECT_EQ(sh.nonManifoldEdges, 1u);
  EXPECT_EQ(sh.boundaryEdges, 2u);
  EXPECT_EQ(sh.edges, 20u);
  EXPECT_EQ(sh.vertices, 9u);
  EXPECT_FALSE(sh.manifold());
  EXPECT_FALSE(sh.closed());
  EXPECT_EQ(sh.orientation(), Orientation::Open);
  ASSERT_EQ(a.defects.nonManifoldEdgeVertices.size(), 2u);
  ASSERT_EQ(a.defects.nonManifoldEdgeOffsets.size(), 2u);
  uint32_t v4 = a.mesh.triangles[3 * 12], v5 = a.mesh.triangles[3 * 12 + 1];
  EXPECT_EQ(a.defects.nonManifoldEdgeVertices[0], std::min(v4, v5));
  EXPECT_EQ(a.defects.nonManifoldEdgeVertices[1], std::max(v4, v5));
  std::vector<uint32_t> tris(a.defects.nonManifoldEdgeTriangles.begin(), a.defects.nonManifoldEdgeTriangles.end());
  ASSERT_EQ(tris.size(), 3u);
  EXPECT_EQ(tris[2], 12u);
  EXPECT_TRUE(std::is_sorted(tris.begin(), tris.end()));
  std::string d = defectsJson(a.mesh, a.topo, a.defects, 1000);
  EXPECT_HAS(d, "\"nonManifoldEdges\":{\"count\":1,\"items\":[{\"vertices\":[" + std::to_string(std::min(v4, v5)) +
                    "," + std::to_string(std::max(v4, v5)) + "],\"positions\":[[");
  EXPECT_HAS(d, "\"triangles\":[" + std::to_string(tris[0]) + "," + std::to_string(tris[1]) + ",12]}]}");
  EXPECT_HAS(d, "\"seams\":{\"count\":1,");
}

TEST(Shells, TwoCubesSharingAnEdgeAreOneOutwardShellThatIsNotClosed) {
  gen::Soup s = gen::cube();
  gen::append(s, gen::cube(1, 1, 0));
  Analyzed a;
  analyze(s, a);
  ASSERT_EQ(a.shells.size(), 1u);
  const Shell& sh = a.shells[0];
  EXPECT_EQ(sh.triangles, 24u);
  EXPECT_EQ(sh.vertices, 14u);
  EXPECT_EQ(sh.edges, 35u);
  EXPECT_EQ(sh.nonManifoldEdges, 1u);
  EXPECT_EQ(sh.boundaryEdges, 0u);
  EXPECT_EQ(sh.nonManifoldVertices, 2u);
  EXPECT_FALSE(sh.closed());
  EXPECT_FALSE(sh.manifold());
  EXPECT_FALSE(sh.hasGenus());
  EXPECT_TRUE(sh.consistent());
  EXPECT_EQ(sh.orientation(), Orientation::Outward);
  EXPECT_DOUBLE_EQ(sh.volume, 2);
  std::string d = defectsJson(a.mesh, a.topo, a.defects, 1000);
  EXPECT_HAS(d, "\"positions\":[[1,1,0],[1,1,1]],\"triangles\":[");
  EXPECT_HAS(d, "\"nonManifoldVertices\":{\"count\":2,");
  ASSERT_EQ(a.defects.nonManifoldEdgeOffsets.size(), 2u);
  EXPECT_EQ(a.defects.nonManifoldEdgeOffsets[1], 4u);
  EXPECT_EQ(a.defects.nonManifoldVertexCycles[0], 2u);
}

TEST(Shells, TwoCubesTouchingAtACornerAreTwoClosedManifoldShells) {
  gen::Soup s = gen::cube();
  gen::append(s, gen::cube(1, 1, 1));
  Analyzed a;
  analyze(s, a);
  ASSERT_EQ(a.shells.size(), 2u);
  for (const Shell& sh : a.shells) {
    EXPECT_TRUE(sh.closed());
    EXPECT_TRUE(sh.manifold());  // on its own; the mesh as a whole is not
    EXPECT_EQ(sh.eulerCharacteristic(), 2);
    EXPECT_EQ(sh.genus(), 0);
    EXPECT_EQ(sh.orientation(), Orientation::Outward);
  }
  EXPECT_FALSE(a.topo.manifold());
  ASSERT_EQ(a.defects.nonManifoldVertices.size(), 1u);
  EXPECT_EQ(a.defects.nonManifoldVertexCycles[0], 2u);
}

TEST(Shells, FlatPillowIsClosedAndFlat) {
  gen::Soup s;
  s.v = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  s.f = {{0, 1, 2}, {0, 2, 1}};
  Analyzed a;
  analyze(s, a);
  ASSERT_EQ(a.shells.size(), 1u);
  EXPECT_TRUE(a.shells[0].closed());
  EXPECT_EQ(a.shells[0].volume, 0);
  EXPECT_EQ(a.shells[0].orientation(), Orientation::Flat);
}

TEST(Shells, AFlatPillowOfTwoTriangulationsIsFlatThoughItsRoundedVolumeIsNot) {
  // A rectangle in the plane z = c, its top split along one diagonal and its bottom along the
  // other: the exact volume is 0, the sum of the rounded tetrahedra often is not.
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1000, 1000);
  int roundedNonZero = 0;
  for (int i = 0; i < 40; ++i) {
    const float z = u(rng), x0 = std::min(u(rng), 0.0f), x1 = std::max(u(rng), 1.0f), y0 = std::min(u(rng), 0.0f),
                y1 = std::max(u(rng), 1.0f);
    gen::Soup s;
    s.v = {{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}};
    s.f = {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {1, 3, 2}};
    Analyzed a;
    analyze(s, a);
    ASSERT_EQ(a.shells.size(), 1u);
    ASSERT_TRUE(a.shells[0].closed());
    EXPECT_EQ(a.shells[0].volumeSign, 0) << i;
    EXPECT_EQ(a.shells[0].orientation(), Orientation::Flat) << i << " volume " << a.shells[0].volume;
    roundedNonZero += a.shells[0].volume != 0;
  }
  EXPECT_GT(roundedNonZero, 0);  // the cases a rounded sign gets wrong
}

// Tetrahedra far from the origin (corners near 2^22, integers: exact floats) whose fourth
// corner is on, or one unit off, the plane of the other three: the exact volume is 0 or
// tiny, and the rounded sum of their origin tetrahedra is off by far more. The orientation
// follows the exact sign, computed here in 128-bit integers.
TEST(Shells, OrientationIsTheExactSignOfTheVolume) {
  std::mt19937_64 rng(11);
  auto near = [&](int64_t c) { return c + int64_t(rng() % 64) - 32; };
  int wrongWhenRounded = 0, flat = 0;
  for (int i = 0; i < 3000; ++i) {
    const int64_t o[3] = {(int64_t(1) << 22) + int64_t(rng() % 4096), (int64_t(1) << 22) - int64_t(rng() % 4096),
                          int64_t(rng() % (int64_t(1) << 23)) - (int64_t(1) << 22)};
    int64_t p[4][3];
    for (int k = 0; k < 3; ++k) p[0][k] = o[k];
    for (int v = 1; v < 3; ++v)
      for (int k = 0; k < 3; ++k) p[v][k] = near(o[k]);
    // the fourth: an integer combination of the others' offsets, moved by -1, 0 or 1
    const int64_t sa = int64_t(rng() % 5) - 2, sb = int64_t(rng() % 5) - 2;
    for (int k = 0; k < 3; ++k) p[3][k] = o[k] + sa * (p[1][k] - o[k]) + sb * (p[2][k] - o[k]);
    p[3][rng() % 3] += int64_t(rng() % 3) - 1;
    gen::Soup s;
    for (auto& q : p) s.v.push_back({float(q[0]), float(q[1]), float(q[2])});
    s.f = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}};
    __int128 six = 0;  // the sum of det(a, b, c) over the faces
    for (auto& f : s.f) {
      const int64_t* a = p[f[0]];
      const int64_t* b = p[f[1]];
      const int64_t* c = p[f[2]];
      six += __int128(a[0]) * (__int128(b[1]) * c[2] - __int128(b[2]) * c[1]) -
             __int128(a[1]) * (__int128(b[0]) * c[2] - __int128(b[2]) * c[0]) +
             __int128(a[2]) * (__int128(b[0]) * c[1] - __int128(b[1]) * c[0]);
    }
    const int want = six > 0 ? 1 : six < 0 ? -1 : 0;
    Analyzed a;
    analyze(s, a);
    ASSERT_FALSE(HasFatalFailure()) << i;
    const Array<Shell>& shells = a.shells;
    if (shells.size() != 1 || !shells[0].closed()) continue;  // corners that coincide
    flat += want == 0;
    wrongWhenRounded += (shells[0].volume > 0 ? 1 : shells[0].volume < 0 ? -1 : 0) != want;
    ASSERT_EQ(shells[0].volumeSign, want) << i;
    ASSERT_EQ(shells[0].orientation(), want > 0 ? Orientation::Outward : want < 0 ? Orientation::Inward : Orientation::Flat);
  }
  EXPECT_GT(flat, 0);
  EXPECT_GT(wrongWhenRounded, 0);
}

TEST(Shells, DegenerateTrianglesSayWhichCornersCoincide) {
  gen::Soup s = gen::cube();
  s.f.push_back({0, 0, 1});  // corners 0 and 1
  s.f.push_back({0, 1, 1});  // 1 and 2
  s.f.push_back({1, 0, 1});  // 2 and 0
  s.f.push_back({2, 2, 2});  // all three
  Analyzed a;
  analyze(s, a);
  ASSERT_EQ(a.defects.degenerateTriangles.size(), 4u);
  const uint8_t masks[4] = {1, 2, 4, 7};
  for (uint32_t i = 0; i < 4; ++i) {
    EXPECT_EQ(a.defects.degenerateTriangles[i], 12 + i);
    EXPECT_EQ(a.defects.degenerateCorners[i], masks[i]);
    EXPECT_EQ(a.triangleShell[12 + i], kInvalid);
  }
  EXPECT_EQ(a.shells[0].triangles, 12u);
  std::string d = defectsJson(a.mesh, a.topo, a.defects, 1000);
  EXPECT_HAS(d,
             "\"degenerateTriangles\":{\"count\":4,\"items\":[{\"triangle\":12,\"corners\":[0,1]},"
             "{\"triangle\":13,\"corners\":[1,2]},{\"triangle\":14,\"corners\":[0,2]},"
             "{\"triangle\":15,\"corners\":[0,1,2]}]}");
  std::string text = defectsText(a.mesh, a.topo, a.defects, 5);
  EXPECT_HAS(text, "  degenerate triangle 13: corners 1 and 2 coincide at [1, 0, 0]\n");
  EXPECT_HAS(text, "  degenerate triangle 15: corners 0, 1 and 2 coincide at [0, 1, 0]\n");
}

TEST(Shells, ShellsKnowTheirSolidOrSayMixed) {
  gen::Soup a = gen::cube(), b = gen::cube(3, 0, 0);
  gen::Soup half1 = a, half2 = a;
  half1.f.resize(6);
  half2.f.erase(half2.f.begin(), half2.f.begin() + 6);
  std::string bytes = gen::ascii(b, "one") + gen::ascii(half1, "two") + gen::ascii(half2, "three");
  Analyzed x;
  analyze(bytes, x);
  ASSERT_EQ(x.mesh.solids.size(), 3u);
  ASSERT_EQ(x.shells.size(), 2u);
  EXPECT_EQ(x.shells[0].solid, 0u);
  EXPECT_EQ(x.shells[1].solid, kMixedSolid);
  std::string j = shellListJson(x.shells);
  EXPECT_HAS(j, "\"solid\":0,");
  EXPECT_HAS(j, "\"solid\":\"mixed\",");
}

TEST(Shells, ToleranceWeldCountsTheWeldedVertices) {
  gen::Soup s = gen::cube();
  // A crack: the +z side's triangles use a copy of corner 7 moved by 1e-4.
  s.v.push_back({s.v[7][0] + 1e-4f, s.v[7][1], s.v[7][2]});
  for (int t = 2; t < 4; ++t)
    for (auto& c : s.f[t])
      if (c == 7) c = 8;
  Analyzed exact, welded;
  analyze(gen::binary(s), exact);
  analyze(gen::binary(s), welded, 1e-3);
  ASSERT_EQ(welded.shells.size(), 1u);
  EXPECT_TRUE(welded.shells[0].closed());
  EXPECT_EQ(welded.shells[0].vertices, 8u);
  EXPECT_FALSE(exact.shells[0].closed());
}

// The report in pieces (what `info --json` prints of a triangle soup, a shell a triangle),
// JSON and text: the pieces joined are the report, each but the last holds at least
// kReportPiece bytes and at most one list item more, and the shell list in ranges is the list.
TEST(Shells, ReportInPiecesIsTheReportAndTheShellRangesAreTheList) {
  gen::Soup s;
  // 5000 pairs of triangles: the second of each crosses the first (an intersection each),
  // and no two pairs share a corner: 10,000 shells and holes, 5000 crossing pairs (the text
  // report's shell lines alone are some 1.4 MB).
  for (int i = 0; i < 5000; ++i) {
    const float x = float(3 * (i % 60)), y = float(3 * (i / 60));
    const uint32_t b = uint32_t(s.v.size());
    s.v.push_back({x, y, 0});
    s.v.push_back({x + 2, y, 0});
    s.v.push_back({x, y + 2, 0});
    s.v.push_back({x + 0.5f, y + 0.5f, -1});
    s.v.push_back({x + 0.5f, y + 0.5f, 1});
    s.v.push_back({x + 0.6f, y + 1.5f, 0.5f});
    s.f.push_back({b, b + 1, b + 2});
    s.f.push_back({b + 3, b + 4, b + 5});
  }
  Analyzed a;
  analyze(s, a);
  ASSERT_EQ(a.shells.size(), 10000u);
  GeometryReport geo;
  ASSERT_TRUE(analyzeGeometry(a.mesh, a.topo, geo, IntersectionOptions{}, true).ok());
  ASSERT_EQ(geo.intersections.nPairs(), 5000u);
  for (int withGeometry = 0; withGeometry < 2; ++withGeometry) {
    ReportExtras x;
    x.shells = withGeometry ? &geo.shells : &a.shells;
    x.defects = &a.defects;
    x.maxDefects = 100000;
    if (withGeometry) {
      x.checks = &geo.checks;
      x.intersections = &geo.intersections;
      x.nesting = &geo.nesting;
      x.solid = geo.solid;
    }
    // The pieces joined; every piece but the last holds a piece's bytes and a list item at most.
    const auto join = [](const std::vector<std::string>& pieces, const char* what) {
      std::string joined;
      for (size_t i = 0; i < pieces.size(); ++i) {
        joined += pieces[i];
        if (i + 1 == pieces.size()) break;
        EXPECT_GE(pieces[i].size(), kReportPiece) << what << " piece " << i;
        EXPECT_LT(pieces[i].size(), kReportPiece + 4096) << what << " piece " << i;
      }
      return joined;
    };
    const std::string whole = infoJson("soup.stl", a.mesh, &a.topo, x);
    std::vector<std::string> pieces;
    infoJson([&](const char* d, size_t n) { pieces.emplace_back(d, n); }, "soup.stl", a.mesh, &a.topo, x);
    ASSERT_GE(pieces.size(), 3u) << whole.size();
    const std::string joined = join(pieces, "JSON");
    EXPECT_TRUE(joined == whole) << joined.size() << " bytes joined, " << whole.size() << " whole";
    if (withGeometry) EXPECT_NE(whole.find("\"selfIntersections\":{\"count\":5000,"), std::string::npos);
    // The text report likewise: a line a shell, handed on as the lines are written.
    const std::string text = infoText("soup.stl", a.mesh, &a.topo, x);
    std::vector<std::string> lines;
    infoText([&](const char* d, size_t n) { lines.emplace_back(d, n); }, "soup.stl", a.mesh, &a.topo, x);
    ASSERT_GE(lines.size(), 2u) << text.size();
    const std::string joinedText = join(lines, "text");
    EXPECT_TRUE(joinedText == text) << joinedText.size() << " bytes joined, " << text.size() << " whole";
  }
  for (const Array<Shell>* list : {&a.shells, &geo.shells}) {
    const ShellNesting* nest = list == &geo.shells ? &geo.nesting : nullptr;
    const std::string whole = shellListJson(*list, nest);
    std::string joined = "\"shellList\":[";
    for (size_t first = 0; first < list->size(); first += 1000) {
      const std::string r = shellRangeJson(*list, nest, first, 1000);
      ASSERT_GE(r.size(), 2u);
      EXPECT_EQ(r.front(), '[');
      EXPECT_EQ(r.back(), ']');
      if (first) joined += ',';
      joined += r.substr(1, r.size() - 2);
    }
    EXPECT_TRUE(joined + "]" == whole) << joined.size() << " bytes joined, " << whole.size() << " whole";
    EXPECT_EQ(shellRangeJson(*list, nest, 9999, 1000), "[" + whole.substr(whole.rfind(",{\"id\":9999,") + 1));
    EXPECT_EQ(shellRangeJson(*list, nest, 10000, 10), "[]");
    EXPECT_EQ(shellRangeJson(*list, nest, 11000, 10), "[]");
  }
  EXPECT_NE(shellListJson(geo.shells, &geo.nesting).find("\"intersectsShells\":[1]"), std::string::npos);
}

TEST(Shells, RejectsATriangleShellThatDoesNotFit) {
  gen::Soup s = gen::cube();
  gen::append(s, gen::cube(3, 0, 0));
  Analyzed a;
  analyze(s, a);
  Array<uint32_t>& ts = a.topo.triangleShell;
  Array<Shell> shells;
  std::swap(ts[0], ts[12]);  // not numbered by the lowest triangle id
  EXPECT_EQ(findShellsAndDefects(a.mesh, a.topo, &shells, nullptr).code, Code::InvalidArgument);
  EXPECT_TRUE(shells.empty());
  Status v = validate(a.mesh, a.topo);
  EXPECT_EQ(v.code, Code::Invalid);
  EXPECT_NE(v.message.find("triangleShell differs from the shells"), std::string::npos) << v.message;
  std::swap(ts[0], ts[12]);
  ts[3] = 7;  // out of range
  EXPECT_EQ(findShellsAndDefects(a.mesh, a.topo, &shells, nullptr).code, Code::InvalidArgument);
  ts[3] = 0;
  // The module keeps working after a refused call.
  EXPECT_TRUE(findShellsAndDefects(a.mesh, a.topo, &shells, nullptr).ok());
  EXPECT_EQ(shells.size(), 2u);
  // Without TopologyOptions::triangleShell there is nothing to report from.
  Topology plain;
  ASSERT_TRUE(buildTopology(a.mesh, plain).ok());
  EXPECT_TRUE(plain.triangleShell.empty());
  EXPECT_EQ(plain.nShells, 2u);
  EXPECT_EQ(findShellsAndDefects(a.mesh, plain, &shells, nullptr).code, Code::InvalidArgument);
}

// ---------------------------------------------------------------------------
// Every fixture, against a brute-force count from the triangles.

namespace {

struct BruteShell {
  uint32_t triangles = 0, edges = 0, boundary = 0, nonManifold = 0, inconsistent = 0;
  std::set<uint32_t> vertices;
  double volume = 0;
};

std::vector<BruteShell> bruteForce(const Mesh& m, const Topology& t, const std::vector<uint32_t>& shellOf) {
  std::vector<BruteShell> out(t.nShells);
  // Per undirected edge: the sides in each direction.
  std::map<std::pair<uint32_t, uint32_t>, std::pair<int, int>> sides;
  std::map<std::pair<uint32_t, uint32_t>, uint32_t> edgeShell;
  for (uint32_t tri = 0; tri < m.nTriangles(); ++tri) {
    if (shellOf[tri] == kInvalid) continue;
    BruteShell& b = out[shellOf[tri]];
    ++b.triangles;
    const float* p[3];
    for (int c = 0; c < 3; ++c) {
      uint32_t u = t.vertexWeld[m.triangles[3 * size_t(tri) + c]],
               w = t.vertexWeld[m.triangles[3 * size_t(tri) + (c + 1) % 3]];
      b.vertices.insert(u);
      auto& d = sides[std::minmax(u, w)];
      (u < w ? d.first : d.second) += 1;
      edgeShell[std::minmax(u, w)] = shellOf[tri];
      p[c] = m.positions.data() + 3 * size_t(m.triangles[3 * size_t(tri) + c]);
    }
    b.volume += (double(p[0][0]) * (double(p[1][1]) * p[2][2] - double(p[1][2]) * p[2][1]) -
                 double(p[0][1]) * (double(p[1][0]) * p[2][2] - double(p[1][2]) * p[2][0]) +
                 double(p[0][2]) * (double(p[1][0]) * p[2][1] - double(p[1][1]) * p[2][0])) /
                6.0;
  }
  for (auto& [key, d] : sides) {
    BruteShell& b = out[edgeShell[key]];
    ++b.edges;
    int n = d.first + d.second;
    if (n == 1)
      ++b.boundary;
    else if (n == 2 && (d.first == 0 || d.second == 0))
      ++b.inconsistent;
    else if (n > 2)
      ++b.nonManifold;
  }
  return out;
}

}  // namespace

TEST(Shells, EveryFixtureAgreesWithABruteForceCountAndTheWholeReport) {
  uint32_t checked = 0;
  for (const std::string& path : gen::fixtureFiles()) {
    SCOPED_TRACE(path);
    Analyzed a;
    if (!gen::read(gen::readFile(path), a.mesh).ok()) continue;
    analyze(gen::readFile(path), a);
    ++checked;
    const Topology& t = a.topo;
    std::vector<BruteShell> brute = bruteForce(a.mesh, t, a.triangleShell);
    uint64_t tris = 0, edges = 0, bnd = 0, nme = 0, inc = 0, holes = 0, seams = 0;
    for (uint32_t i = 0; i < t.nShells; ++i) {
      const Shell& sh = a.shells[i];
      const BruteShell& b = brute[i];
      ASSERT_EQ(sh.triangles, b.triangles) << "shell " << i;
      ASSERT_EQ(sh.vertices, b.vertices.size()) << "shell " << i;
      ASSERT_EQ(sh.edges, b.edges) << "shell " << i;
      ASSERT_EQ(sh.boundaryEdges, b.boundary) << "shell " << i;
      ASSERT_EQ(sh.nonManifoldEdges, b.nonManifold) << "shell " << i;
      ASSERT_EQ(sh.inconsistentEdges, b.inconsistent) << "shell " << i;
      ASSERT_EQ(sh.volume, b.volume) << "shell " << i;
      ASSERT_LE(sh.nonManifoldVertices, sh.vertices);
      tris += sh.triangles;
      edges += sh.edges;
      bnd += sh.boundaryEdges;
      nme += sh.nonManifoldEdges;
      inc += sh.inconsistentEdges;
      holes += sh.holes;
      seams += sh.seams;
    }
    EXPECT_EQ(tris, t.nTriangles - t.nDegenerate);
    EXPECT_EQ(edges, t.nEdges);
    EXPECT_EQ(bnd, t.nBoundaryEdges);
    EXPECT_EQ(nme, t.nNonManifoldEdges);
    EXPECT_EQ(inc, t.nInconsistentEdges);
    EXPECT_EQ(holes, t.nHoles);
    EXPECT_EQ(seams, t.nSeams);
    EXPECT_EQ(a.defects.nonManifoldEdgeVertices.size(), 2 * size_t(t.nNonManifoldEdges));
    EXPECT_EQ(a.defects.inconsistentEdgeVertices.size(), 2 * size_t(t.nInconsistentEdges));
    EXPECT_EQ(a.defects.nonManifoldVertices.size(), t.nNonManifoldVertices);
    EXPECT_EQ(a.defects.degenerateTriangles.size(), t.nDegenerate);
    for (uint32_t v = 0, i = 0; v < t.nVertices; ++v)
      if (t.vertexNonManifold[v]) ASSERT_EQ(a.defects.nonManifoldVertices[i++], v);
    for (uint32_t c : a.defects.nonManifoldVertexCycles) ASSERT_GE(c, 2u);
  }
  EXPECT_GE(checked, 70u);
}

// ---------------------------------------------------------------------------
// The CLI: `info --shells --defects [--max-defects N]`, `split` (a subprocess: not in wasm).
#if defined(STLTOPO_CLI) && !defined(STLTOPO_WASM_TESTS)

namespace {

// Runs the CLI with `args`; returns the exit status and stdout.
int cli(const std::string& args, std::string& out) {
  std::string cmd = std::string("'") + STLTOPO_CLI + "' " + args + " 2>/dev/null";
  FILE* p = ::popen(cmd.c_str(), "r");
  if (!p) return -1;
  out.clear();
  char buf[4096];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  int rc = ::pclose(p);
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

}  // namespace

TEST(ShellsCli, JsonAddsTheShellListAndTheDefectsOnlyWhenAsked) {
  const std::string f = std::string("'") + STLTOPO_FIXTURES + "/mikedh_trimesh/models/shared.STL'";
  std::string plain, both, cut;
  ASSERT_EQ(cli("info --json " + f, plain), 0);
  ASSERT_EQ(cli("info --json --shells --defects " + f, both), 0);
  ASSERT_EQ(cli("info --json --defects --max-defects 0 " + f, cut), 0);
  EXPECT_EQ(plain.find("shellList"), std::string::npos);
  EXPECT_EQ(plain.find("\"defects\""), std::string::npos);
  // The same object with the two keys last.
  ASSERT_GT(both.size(), plain.size());
  EXPECT_EQ(both.substr(0, plain.size() - 2), plain.substr(0, plain.size() - 2));
  EXPECT_HAS(both, ",\"shellList\":[{\"id\":0,\"triangles\":24,");
  EXPECT_HAS(both, "\"orientation\":\"outward\"");
  EXPECT_HAS(both,
             "\"nonManifoldEdges\":{\"count\":1,\"items\":[{\"vertices\":[0,2],\"positions\":[[0.5,0.5,0.5],"
             "[0.5,0.5,-0.5]],\"triangles\":[0,1,21,23]}]}");
  EXPECT_EQ(cut.find("shellList"), std::string::npos);
  EXPECT_HAS(cut, "\"nonManifoldEdges\":{\"count\":1,\"items\":[]}");
  std::string text;
  ASSERT_EQ(cli("info --shells --defects " + f, text), 0);
  EXPECT_HAS(text, "  shell 0: 24 triangles, not closed, non-manifold, outward, volume 2");
  EXPECT_HAS(text, "  non-manifold edge 0-2: [0.5, 0.5, 0.5] - [0.5, 0.5, -0.5], 4 triangles: 0 1 21 23\n");
}

TEST(ShellsCli, UsageErrors) {
  const std::string f = std::string("'") + STLTOPO_FIXTURES + "/mikedh_trimesh/models/shared.STL'";
  std::string out;
  EXPECT_EQ(cli("info --shells --no-topology " + f, out), 2);
  EXPECT_EQ(cli("info --defects --no-topology " + f, out), 2);
  EXPECT_EQ(cli("info --defects --max-defects -1 " + f, out), 2);
  EXPECT_EQ(cli("info --defects --max-defects x " + f, out), 2);
  EXPECT_EQ(cli("info --defects --max-defects", out), 2);
}

#endif

// ---------------------------------------------------------------------------
// extractShell: each shell as a mesh of its own.

TEST(ExtractShell, EveryShellOfEveryFixtureReportsAsItDidInItsMesh) {
  uint32_t checked = 0;
  for (const std::string& path : gen::fixtureFiles()) {
    SCOPED_TRACE(path);
    std::string bytes = gen::readFile(path);
    Analyzed a;
    if (!gen::read(bytes, a.mesh).ok()) continue;
    analyze(bytes, a);
    for (uint32_t s = 0; s < a.shells.size(); ++s) {
      Mesh m;
      ASSERT_TRUE(extractShell(a.mesh, a.topo, s, m).ok());
      const Shell& sh = a.shells[s];
      ASSERT_EQ(m.nTriangles(), sh.triangles);
      ASSERT_EQ(m.nVertices(), sh.vertices);
      ASSERT_EQ(m.attributes.size(), sh.triangles);
      ASSERT_EQ(m.colorConvention, a.mesh.colorConvention);
      ASSERT_EQ(m.colors.size(), a.mesh.colors.empty() ? 0 : 3 * size_t(sh.triangles));
      EXPECT_EQ(m.area, sh.area);
      EXPECT_EQ(m.volume, sh.volume);
      for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(m.bboxMin[k], sh.bboxMin[k]);
        EXPECT_EQ(m.bboxMax[k], sh.bboxMax[k]);
      }
      uint32_t inSolids = 0;
      for (const Solid& so : m.solids) inSolids += so.triangleCount;
      EXPECT_EQ(inSolids, sh.triangles);
      if (sh.solid < a.mesh.solids.size()) {
        ASSERT_EQ(m.solids.size(), 1u);
        EXPECT_EQ(m.solids[0].name, a.mesh.solids[sh.solid].name);
      }
      // On its own it is one shell with the same report (its vertices are its own now).
      Topology t;
      TopologyOptions o;
      o.triangleShell = true;
      ASSERT_TRUE(buildTopology(m, t, o).ok());
      ASSERT_TRUE(validate(m, t).ok());
      Array<Shell> own;
      ASSERT_TRUE(findShellsAndDefects(m, t, &own, nullptr).ok());
      ASSERT_EQ(own.size(), 1u);
      own[0].solid = sh.solid;
      Array<Shell> one;
      ASSERT_TRUE(one.push_back(sh));
      EXPECT_EQ(shellListJson(own), shellListJson(one)) << "shell " << s;
      ++checked;
    }
  }
  EXPECT_GE(checked, 300u);
}

TEST(ExtractShell, KeepsAttributesColoursAndSolidsAndRefusesBadShells) {
  gen::Soup s = gen::cube(), b = gen::cube(3, 0, 0);
  gen::append(s, b);
  s.attr.assign(24, 0);
  for (int t = 12; t < 24; ++t) s.attr[t] = uint16_t(0x8000 | (t << 5));  // VisCAM colours on the second cube
  Analyzed a;
  analyze(gen::binary(s), a);
  ASSERT_EQ(a.mesh.colorConvention, ColorConvention::VisCam);
  Mesh m;
  ASSERT_TRUE(extractShell(a.mesh, a.topo, 1, m).ok());
  ASSERT_EQ(m.nTriangles(), 12u);
  EXPECT_EQ(m.nVertices(), 8u);
  for (uint32_t t = 0; t < 12; ++t) {
    EXPECT_EQ(m.attributes[t], a.mesh.attributes[12 + t]);
    EXPECT_EQ(m.colorValid[t], a.mesh.colorValid[12 + t]);
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(m.colors[3 * t + k], a.mesh.colors[3 * (12 + t) + k]);
      // The same corner positions, through the compacted ids.
      for (int i = 0; i < 3; ++i)
        EXPECT_EQ(m.positions[3 * m.triangles[3 * t + k] + i],
                  a.mesh.positions[3 * a.mesh.triangles[3 * (12 + t) + k] + i]);
    }
  }
  // Ids by first appearance: the first triangle's corners are 0, 1, 2.
  EXPECT_EQ(m.triangles[0], 0u);
  EXPECT_EQ(m.triangles[1], 1u);
  EXPECT_EQ(m.triangles[2], 2u);
  EXPECT_EQ(extractShell(a.mesh, a.topo, 2, m).code, Code::InvalidArgument);
  Topology plain;
  ASSERT_TRUE(buildTopology(a.mesh, plain).ok());
  EXPECT_EQ(extractShell(a.mesh, plain, 0, m).code, Code::InvalidArgument);
  EXPECT_TRUE(extractShell(a.mesh, a.topo, 0, m).ok());
}

#if defined(STLTOPO_CLI) && !defined(STLTOPO_WASM_TESTS)
TEST(ShellsCli, SplitWritesOneFilePerShellThatReadsBackAsThatShell) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("stltopo-split-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const std::string in = gen::fixturePath("mikedh_trimesh/models/multibody.stl");
  std::string out;
  ASSERT_EQ(cli("split --binary '" + in + "' '" + dir.string() + "'", out), 0);
  Analyzed whole;
  analyze(gen::readFile(in), whole);
  ASSERT_EQ(whole.shells.size(), 2u);
  size_t lines = 0;
  for (size_t p = 0; (p = out.find('\n', p)) != std::string::npos; ++p) ++lines;
  EXPECT_EQ(lines, 2u);
  for (uint32_t k = 0; k < 2; ++k) {
    const std::string file = (dir / ("multibody-shell-" + std::to_string(k) + ".stl")).string();
    EXPECT_HAS(out, splitLineJson(file, whole.shells[k], k));
    Analyzed part;
    analyze(gen::readFile(file), part);
    EXPECT_EQ(part.mesh.format, Format::Binary);
    ASSERT_EQ(part.shells.size(), 1u);
    EXPECT_EQ(part.shells[0].triangles, whole.shells[k].triangles);
    EXPECT_EQ(part.shells[0].inconsistentEdges, whole.shells[k].inconsistentEdges);
    EXPECT_EQ(part.shells[0].volume, whole.shells[k].volume);
    ASSERT_EQ(part.mesh.solids.size(), 1u);
    EXPECT_EQ(part.mesh.solids[0].name, whole.mesh.solids[k].name);  // each body is one solid
  }
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator{}), 2);
  // A bad input writes nothing; OUTDIR that is a file is a write-failed; usage errors.
  fs::remove_all(dir);
  EXPECT_EQ(cli("split '" + std::string(STLTOPO_FIXTURES) +
                    "/wolph_numpy-stl/tests/tmp/test_args_False_0/binary.stl' '" + dir.string() + "'",
                out),
            1);
  EXPECT_FALSE(fs::exists(dir));
  EXPECT_EQ(cli("split '" + in + "' '" + in + "'", out), 1);
  EXPECT_EQ(cli("split '" + in + "'", out), 2);
  EXPECT_EQ(cli("split '" + in + "' '" + dir.string() + "' --colors none", out), 2);
  fs::remove_all(dir);
}
#endif
