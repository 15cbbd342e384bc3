// The exact geometric checks (stltopo/geometry.h): hand-built cases with their expected
// pairs, and a randomized cross-check against an independent brute force in exact integer
// arithmetic (separating axes), on small meshes on an integer grid where coincidences
// (shared corners, collinear and coplanar corners, touching sides) are frequent.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <random>
#include <set>
#include <tuple>

#include "geometry_detail.h"  // private (src/): the pair test, compared below
#include "predicates.h"       // private (src/): the exact stages, compared below
#include "stl_gen.h"
#include "stltopo/stltopo.h"

namespace {

using gen::Soup;

// The same zero-area list and duplicate groups, array for array.
bool sameChecks(const stltopo::TriangleChecks& a, const stltopo::TriangleChecks& b) {
  return gen::sameArray(a.duplicateTriangles, b.duplicateTriangles) &&
         gen::sameArray(a.duplicateOffsets, b.duplicateOffsets) &&
         gen::sameArray(a.duplicateOrientation, b.duplicateOrientation) && gen::sameArray(a.zeroArea, b.zeroArea);
}

struct Result {
  stltopo::Mesh mesh;
  stltopo::Topology topo;
  stltopo::GeometryReport geo;
};

// (withoutList: also without the shell list, checked against it; the tests that count the
// certificates' work over one pass turn it off.)
void analyze(const Soup& soup, Result& r, const stltopo::IntersectionOptions& o = {}, bool withoutList = true) {
  ASSERT_TRUE(gen::read(gen::binary(soup), r.mesh).ok());
  stltopo::TopologyOptions to;
  to.triangleShell = true;
  ASSERT_TRUE(stltopo::buildTopology(r.mesh, r.topo, to).ok());
  stltopo::Status s = stltopo::analyzeGeometry(r.mesh, r.topo, r.geo, o);
  ASSERT_TRUE(s.ok()) << s.message;
  if (!withoutList) return;
  // Without the shell list: the same `solid`, and no shells or nesting.
  stltopo::GeometryReport lean;
  s = stltopo::analyzeGeometry(r.mesh, r.topo, lean, o, false);
  ASSERT_TRUE(s.ok()) << s.message;
  EXPECT_EQ(lean.solid, r.geo.solid);
  EXPECT_TRUE(lean.shells.empty() && lean.nesting.depth.empty());
  EXPECT_EQ(lean.intersections.nPairs(), r.geo.intersections.nPairs());
}

// Pairs as "i j kind" strings, ordered.
std::vector<std::string> pairsOf(const stltopo::Intersections& x) {
  std::vector<std::string> v;
  for (size_t i = 0; i < x.nPairs(); ++i)
    v.push_back(std::to_string(x.pairs[2 * i]) + " " + std::to_string(x.pairs[2 * i + 1]) + " " +
                stltopo::intersectionKindName(stltopo::IntersectionKind(x.kinds[i])));
  return v;
}

Soup cubeSoup(float x, float y, float z, float s, bool inward = false) {
  Soup c = gen::cube(x, y, z, s);
  if (inward)
    for (auto& f : c.f) std::swap(f[1], f[2]);
  return c;
}

Soup join(const Soup& a, const Soup& b) {
  Soup s = a;
  gen::append(s, b);
  return s;
}

Soup tris(const std::vector<std::array<std::array<float, 3>, 3>>& list) {
  Soup s;
  for (auto& t : list) {
    uint32_t base = uint32_t(s.v.size());
    for (auto& p : t) s.v.push_back(p);
    s.f.push_back({base, base + 1, base + 2});
  }
  return s;
}

Soup tetra(std::array<float, 3> a, std::array<float, 3> b, std::array<float, 3> c, std::array<float, 3> d) {
  // (a, b, c) counter-clockwise seen from below, d above: outward faces.
  Soup s;
  s.v = {a, b, c, d};
  s.f = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  return s;
}

TEST(Geometry, CleanCubeAndTorusHaveNoPairs) {
  Result r;
  analyze(cubeSoup(0, 0, 0, 10), r);
  EXPECT_EQ(r.geo.intersections.nPairs(), 0u);
  EXPECT_TRUE(r.geo.intersections.complete);
  EXPECT_TRUE(r.geo.solid);
  // A fine torus: every triangle has many neighbours sharing a corner or a side.
  Result t;
  analyze(gen::torus(64, 32), t);
  EXPECT_EQ(t.geo.intersections.nPairs(), 0u);
  EXPECT_EQ(t.geo.checks.zeroArea.size(), 0u);
  EXPECT_EQ(t.geo.checks.nDuplicateTriangles, 0u);
  EXPECT_TRUE(t.geo.solid);
  ASSERT_EQ(t.geo.nesting.depth.size(), 1u);
  EXPECT_EQ(t.geo.nesting.depth[0], 0u);
}

TEST(Geometry, OverlappingCubesCross) {
  Result r;
  analyze(join(cubeSoup(0, 0, 0, 20), cubeSoup(10, 10, 10, 20)), r);
  const auto& x = r.geo.intersections;
  EXPECT_GT(x.nPairs(), 0u);
  EXPECT_EQ(x.nCrossing + x.nTouching + x.nCoplanar, x.nPairs());
  EXPECT_GT(x.nCrossing, 0u);
  for (size_t i = 0; i < x.nPairs(); ++i) EXPECT_NE(x.pairs[2 * i] / 12, x.pairs[2 * i + 1] / 12);  // across the cubes
  EXPECT_TRUE(r.topo.watertight());
  EXPECT_FALSE(r.geo.solid);
  ASSERT_EQ(r.geo.nesting.intersectsOffsets.size(), 3u);
  EXPECT_EQ(r.geo.nesting.intersectsShells[0], 1u);
  EXPECT_EQ(r.geo.nesting.depth[0], stltopo::kInvalid);  // overlapping: no nesting
  // Each point lies in both cubes' boxes.
  for (size_t i = 0; i < x.nPairs(); ++i)
    for (int c = 0; c < 3; ++c) {
      EXPECT_GE(x.points[3 * i + c], 10.0);
      EXPECT_LE(x.points[3 * i + c], 20.0);
    }
}

TEST(Geometry, CavityAndNestedBody) {
  Result cav;
  analyze(join(cubeSoup(0, 0, 0, 30), cubeSoup(10, 10, 10, 10, true)), cav);
  EXPECT_EQ(cav.geo.intersections.nPairs(), 0u);
  EXPECT_EQ(cav.geo.nesting.parent[1], 0u);
  EXPECT_EQ(cav.geo.nesting.depth[1], 1u);
  EXPECT_EQ(cav.geo.nesting.parent[0], stltopo::kInvalid);
  EXPECT_EQ(cav.geo.shells[1].orientation(), stltopo::Orientation::Inward);
  EXPECT_TRUE(cav.geo.solid);  // a proper cavity
  Result nest;
  analyze(join(cubeSoup(0, 0, 0, 30), cubeSoup(10, 10, 10, 10)), nest);
  EXPECT_EQ(nest.geo.nesting.depth[1], 1u);
  EXPECT_FALSE(nest.geo.solid);  // an outward body inside another: ambiguous
  // Three levels: a body in the cavity of a body.
  Result three;
  analyze(join(join(cubeSoup(0, 0, 0, 30), cubeSoup(5, 5, 5, 20, true)), cubeSoup(10, 10, 10, 10)), three);
  EXPECT_EQ(three.geo.nesting.parent[2], 1u);
  EXPECT_EQ(three.geo.nesting.depth[2], 2u);
  EXPECT_TRUE(three.geo.solid);
  // Side by side: neither contains the other.
  Result side;
  analyze(join(cubeSoup(0, 0, 0, 10), cubeSoup(20, 0, 0, 10)), side);
  EXPECT_EQ(side.geo.nesting.depth[0], 0u);
  EXPECT_EQ(side.geo.nesting.depth[1], 0u);
  EXPECT_TRUE(side.geo.solid);
}

// Two tetrahedra that share a corner, both in a cube. They are not nested in each other (the
// shared vertex is not strictly inside either), but each lies in the cube. The ray from a shell's
// first corner starts at the shared vertex, on the other tetrahedron's faces: that tie must not
// void the cube's answer (it did, leaving depth 0: random_nesting.py, seed 4).
TEST(Geometry, ShellsSharingACornerStillNestInAThird) {
  const std::array<float, 3> p = {15, 15, 15};
  auto at = [&](float x, float y, float z) { return std::array<float, 3>{p[0] + x, p[1] + y, p[2] + z}; };
  Result r;
  analyze(join(join(cubeSoup(0, 0, 0, 30), tetra(p, at(0, 1, 0), at(1, 0, 0), at(0, 0, 1))),
               tetra(p, at(-1, 0, 0), at(0, -1, 0), at(0, 0, -1))),
          r);
  EXPECT_EQ(r.geo.intersections.nPairs(), 0u);
  ASSERT_EQ(r.geo.shells.size(), 3u);
  for (uint32_t s : {1u, 2u}) {
    EXPECT_EQ(r.geo.nesting.parent[s], 0u) << "shell " << s;
    EXPECT_EQ(r.geo.nesting.depth[s], 1u) << "shell " << s;
  }
  EXPECT_EQ(r.geo.nesting.depth[0], 0u);
  EXPECT_FALSE(r.geo.solid);  // the shared corner is a non-manifold vertex
  // Moved so that the shared corner is the second tetrahedron's last corner instead: the same.
  Result q;
  analyze(join(join(cubeSoup(0, 0, 0, 30), tetra(p, at(0, 1, 0), at(1, 0, 0), at(0, 0, 1))),
               tetra(at(-1, 0, 0), at(0, -1, 0), at(0, 0, -1), p)),
          q);
  for (uint32_t s : {1u, 2u}) EXPECT_EQ(q.geo.nesting.depth[s], 1u) << "shell " << s;
}

TEST(Geometry, CubesTouchingAlongAFaceWithOtherDiagonals) {
  // The second cube's shared face is split along the other diagonal: coplanar overlaps.
  Soup b = cubeSoup(10, 0, 0, 10);
  // face x = 10 of cube b is {0, 4, 6, 2} -> triangles (0,4,6), (0,6,2); flip the diagonal.
  for (auto& f : b.f) {
    std::set<uint32_t> s(f.begin(), f.end());
    if (s == std::set<uint32_t>{0, 4, 6})
      f = {0, 4, 2};
    else if (s == std::set<uint32_t>{0, 6, 2})
      f = {4, 6, 2};
  }
  Result r;
  analyze(join(cubeSoup(0, 0, 0, 10), b), r);
  EXPECT_EQ(r.geo.intersections.nCoplanar, 4u);  // each of the two triangles overlaps both
  EXPECT_FALSE(r.geo.solid);
}

TEST(Geometry, CornerPushedThroughAFace) {
  // A tetrahedron whose apex goes through the opposite face of a cube.
  Result r;
  analyze(join(cubeSoup(0, 0, 0, 10), tetra({2, 2, 5}, {8, 2, 5}, {5, 8, 5}, {5, 4, 14})), r);
  EXPECT_GT(r.geo.intersections.nCrossing, 0u);
}

// The triangle checks on a large file in no spatial order, against a brute force: in wasm
// such a file takes the checks' blocked loop (triangle_checks.cpp), natively the plain one.
// A torus with holes, plus duplicates (same and opposite winding, groups of three, two-sided
// sheets whose edges are interior), exactly collinear triangles, degenerate ones and fins
// (edges of three sides), shuffled.
TEST(Geometry, TriangleChecksOfAScatteredFileAreTheBruteForceOnes) {
  Soup soup = gen::torus(300, 150, {7, 4000, 22222});
  const uint32_t nTorus = uint32_t(soup.f.size());
  std::mt19937 rng(42);
  for (int k = 0; k < 200; ++k) {
    const auto f = soup.f[rng() % nTorus];
    soup.f.push_back(k % 2 ? f : std::array<uint32_t, 3>{f[0], f[2], f[1]});
    if (k % 50 == 0) soup.f.push_back({f[1], f[2], f[0]});  // a third member
  }
  for (int k = 1; k <= 100; ++k) {  // exactly collinear: (k, 2k, 3k) (2k, 4k, 6k) (5k, 10k, 15k)
    const uint32_t b = uint32_t(soup.v.size());
    for (float m : {1.0f, 2.0f, 5.0f}) soup.v.push_back({m * k, 2 * m * k, 3 * m * k});
    soup.f.push_back({b, b + 1, b + 2});
    if (k % 10 == 0) soup.f.push_back({b + 2, b, b + 1});  // a zero-area duplicate too
  }
  for (int k = 0; k < 50; ++k) {
    const auto f = soup.f[rng() % nTorus];
    soup.f.push_back({f[0], f[0], f[1]});  // degenerate
    const uint32_t b = uint32_t(soup.v.size());
    soup.v.push_back({100.0f + k, -50.0f, 7.0f});
    soup.f.push_back({f[0], f[1], b});  // a fin: a third side on the edge f[0] f[1]
  }
  for (int k = 0; k < 30; ++k) {  // a two-sided sheet: a duplicate pair whose edges are interior
    const uint32_t b = uint32_t(soup.v.size());
    soup.v.push_back({-100.0f - k, 0.0f, 0.0f});
    soup.v.push_back({-100.0f - k, 1.0f, 0.0f});
    soup.v.push_back({-100.0f - k, 0.0f, 1.0f});
    soup.f.push_back({b, b + 1, b + 2});
    soup.f.push_back({b, b + 2, b + 1});
  }
  std::shuffle(soup.f.begin(), soup.f.end(), rng);
  stltopo::Mesh mesh;
  ASSERT_TRUE(gen::read(gen::binary(soup), mesh).ok());
  stltopo::Topology topo;
  ASSERT_TRUE(stltopo::buildTopology(mesh, topo).ok());
  const uint32_t nt = mesh.nTriangles();
  // The brute force: zero-area triangles are the collinear ones added (the torus has none),
  // found by their corners' positions; duplicate groups by the sorted corner ids.
  std::vector<uint32_t> zeroArea;
  std::map<std::array<uint32_t, 3>, std::vector<uint32_t>> bySet;
  for (uint32_t t = 0; t < nt; ++t) {
    std::array<uint32_t, 3> v{mesh.triangles[3 * t], mesh.triangles[3 * t + 1], mesh.triangles[3 * t + 2]};
    if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) continue;
    const float* p = mesh.positions.data() + 3 * size_t(v[0]);
    if (p[1] == 2 * p[0] && p[2] == 3 * p[0] && p[0] >= 1) zeroArea.push_back(t);
    std::sort(v.begin(), v.end());
    bySet[v].push_back(t);
  }
  ASSERT_EQ(zeroArea.size(), 110u);
  std::vector<std::vector<uint32_t>> groups;
  for (auto& [set, members] : bySet)
    if (members.size() > 1) groups.push_back(members);
  std::sort(groups.begin(), groups.end());  // by their lowest triangle
  ASSERT_GE(groups.size(), 230u);
  const stltopo::Topology* topologies[] = {&topo, nullptr};
  for (const stltopo::Topology* tp : topologies) {
    for (unsigned threads : {1u, 2u}) {
      stltopo::TriangleChecks checks;
      ASSERT_TRUE(stltopo::checkTriangles(mesh, tp, checks, threads).ok());
      EXPECT_EQ(std::vector<uint32_t>(checks.zeroArea.begin(), checks.zeroArea.end()), zeroArea);
      ASSERT_EQ(checks.nDuplicateGroups(), groups.size());
      uint32_t extra = 0;
      for (size_t g = 0; g < groups.size(); ++g) {
        const uint32_t* b = checks.duplicateTriangles.data() + checks.duplicateOffsets[g];
        const uint32_t* e = checks.duplicateTriangles.data() + checks.duplicateOffsets[g + 1];
        EXPECT_EQ(std::vector<uint32_t>(b, e), groups[g]) << "group " << g;
        extra += uint32_t(groups[g].size()) - 1;
        auto corners = [&](uint32_t t) {
          return std::array<uint32_t, 3>{mesh.triangles[3 * t], mesh.triangles[3 * t + 1], mesh.triangles[3 * t + 2]};
        };
        bool allSame = true;
        for (uint32_t t : groups[g]) {
          auto x = corners(groups[g][0]), y = corners(t);
          bool same = false;
          for (int r = 0; r < 3; ++r, std::rotate(y.begin(), y.begin() + 1, y.end())) same |= x == y;
          allSame &= same;
        }
        const auto want = allSame ? stltopo::DuplicateOrientation::Same
                          : groups[g].size() == 2 ? stltopo::DuplicateOrientation::Opposite
                                                  : stltopo::DuplicateOrientation::Mixed;
        EXPECT_EQ(checks.duplicateOrientation[g], uint8_t(want)) << "group " << g;
      }
      EXPECT_EQ(checks.nDuplicateTriangles, extra);
    }
  }
}

// The checks without the half-edges (a topology stripped of them, as `info --intersections`
// leaves it) hash the corners through the tolerance weld, as the topology's own test does:
// copies of torus triangles whose corners moved by less than the tolerance are duplicates
// only after the weld. With the raw corner ids (no topology) there are none.
TEST(Geometry, DuplicatesWithoutHalfedgesGoThroughTheToleranceWeld) {
  Soup soup = gen::torus(200, 100, {3, 50, 7});
  const uint32_t nTorus = uint32_t(soup.f.size());
  std::mt19937 rng(5);
  for (int k = 0; k < 300; ++k) {
    const auto f = soup.f[rng() % nTorus];
    const uint32_t b = uint32_t(soup.v.size());
    for (int i = 0; i < 3; ++i) {
      auto p = soup.v[f[i]];
      p[0] += 1e-5f * float(1 + k % 3);
      soup.v.push_back(p);
    }
    soup.f.push_back(k % 2 ? std::array<uint32_t, 3>{b, b + 1, b + 2} : std::array<uint32_t, 3>{b, b + 2, b + 1});
  }
  std::shuffle(soup.f.begin(), soup.f.end(), rng);
  stltopo::Mesh mesh;
  ASSERT_TRUE(gen::read(gen::binary(soup), mesh).ok());
  stltopo::TopologyOptions to;
  to.tolerance = 0.001;
  stltopo::Topology topo;
  ASSERT_TRUE(stltopo::buildTopology(mesh, topo, to).ok());
  stltopo::TriangleChecks full, stripped, raw;
  ASSERT_TRUE(stltopo::checkTriangles(mesh, &topo, full).ok());
  EXPECT_GE(full.nDuplicateGroups(), 250u);  // a few copies land on the same triangle
  EXPECT_EQ(full.nDuplicateTriangles, 300u);
  topo.next.release(), topo.prev.release(), topo.face.release();
  topo.triangleHalfedge.release(), topo.vertexHalfedge.release();
  ASSERT_TRUE(stltopo::checkTriangles(mesh, &topo, stripped).ok());
  EXPECT_TRUE(sameChecks(stripped, full));
  ASSERT_TRUE(stltopo::checkTriangles(mesh, nullptr, raw).ok());
  EXPECT_EQ(raw.nDuplicateGroups(), 0u);
}

TEST(Geometry, FoldOverTJunctionNeedleDuplicates) {
  Result fold;  // across the shared side (0,0,0)-(10,0,0), both on the same side
  analyze(tris({{{{0, 0, 0}, {10, 0, 0}, {0, 10, 0}}}, {{{10, 0, 0}, {0, 0, 0}, {3, 3, 0}}}}), fold);
  EXPECT_EQ(pairsOf(fold.geo.intersections), std::vector<std::string>{"0 1 coplanar"});
  Result flat;  // the same side, opposite sides: a clean fold
  analyze(tris({{{{0, 0, 0}, {10, 0, 0}, {0, 10, 0}}}, {{{10, 0, 0}, {0, 0, 0}, {3, -3, 0}}}}), flat);
  EXPECT_EQ(flat.geo.intersections.nPairs(), 0u);
  Result tj;  // a corner on another's side
  analyze(tris({{{{0, 0, 0}, {10, 0, 0}, {0, 10, 0}}}, {{{5, 0, 0}, {10, -5, 5}, {5, 0, 10}}}}), tj);
  EXPECT_EQ(pairsOf(tj.geo.intersections), std::vector<std::string>{"0 1 touching"});
  Result flatT;  // a T-junction in a flat region: coplanar, sharing only a segment
  analyze(tris({{{{0, 0, 0}, {10, 0, 0}, {0, 10, 0}}}, {{{2, 0, 0}, {8, 0, 0}, {5, -3, 0}}}}), flatT);
  EXPECT_EQ(pairsOf(flatT.geo.intersections), std::vector<std::string>{"0 1 touching"});
  Result needle;
  analyze(tris({{{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}},
                {{{0, 0, 0}, {1, 1, 0}, {0, 1, 0}}},
                {{{0, 0, 0}, {1, 1, 1}, {3, 3, 3}}}}),
          needle);
  ASSERT_EQ(needle.geo.checks.zeroArea.size(), 2u);
  EXPECT_EQ(needle.geo.checks.zeroArea[0], 0u);
  EXPECT_EQ(needle.geo.checks.zeroArea[1], 2u);
  EXPECT_EQ(needle.geo.intersections.nPairs(), 0u);  // zero-area triangles are in no pair
  Result dup;
  analyze(tris({{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}},
                {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}},
                {{{5, 5, 5}, {6, 5, 5}, {5, 6, 5}}},
                {{{5, 5, 5}, {5, 6, 5}, {6, 5, 5}}},
                {{{0, 0, 0}, {0, 1, 0}, {1, 0, 0}}}}),
          dup);
  const auto& c = dup.geo.checks;
  ASSERT_EQ(c.nDuplicateGroups(), 2u);
  EXPECT_EQ(c.nDuplicateTriangles, 3u);
  EXPECT_EQ(c.duplicateOrientation[0], uint8_t(stltopo::DuplicateOrientation::Mixed));
  EXPECT_EQ(c.duplicateOrientation[1], uint8_t(stltopo::DuplicateOrientation::Opposite));
  EXPECT_EQ(std::vector<uint32_t>(c.duplicateTriangles.begin(), c.duplicateTriangles.end()),
            (std::vector<uint32_t>{0, 1, 4, 2, 3}));
  EXPECT_EQ(dup.geo.intersections.nPairs(), 0u);  // members of one group are no pair
}

TEST(Geometry, InterpenetratingTetrahedra) {
  Result r;
  analyze(join(tetra({0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {0, 0, 4}), tetra({1, 1, 1}, {5, 1, 1}, {1, 5, 1}, {1, 1, 5})),
          r);
  EXPECT_GT(r.geo.intersections.nPairs(), 0u);
  EXPECT_EQ(r.geo.intersections.nPairs(), r.geo.intersections.nCrossing);
  EXPECT_FALSE(r.geo.solid);
}

TEST(Geometry, WorkLimitGivesALowerBound) {
  // A stack of coplanar overlapping triangles: every pair intersects.
  Soup s;
  for (int i = 0; i < 200; ++i) {
    uint32_t b = uint32_t(s.v.size());
    s.v.push_back({float(i) * 0.01f, 0, 0});
    s.v.push_back({10, float(i) * 0.01f + 1, 0});
    s.v.push_back({0, 10, 0});
    s.f.push_back({b, b + 1, b + 2});
  }
  Result full;
  analyze(s, full);
  EXPECT_TRUE(full.geo.intersections.complete);
  EXPECT_EQ(full.geo.intersections.nPairs(), 200u * 199 / 2);
  stltopo::IntersectionOptions o;
  o.maxPairs = 1000;
  Result cut;
  analyze(s, cut, o);
  EXPECT_FALSE(cut.geo.intersections.complete);
  EXPECT_EQ(cut.geo.intersections.nPairs(), 1000u);
  EXPECT_FALSE(cut.geo.solid);
  // Cancelling through the progress callback.
  stltopo::IntersectionOptions stop;
  stop.progress = [](void*, double) { return false; };
  stltopo::Intersections x;
  EXPECT_EQ(stltopo::findIntersections(full.mesh, full.topo, full.geo.checks, x, stop).code, stltopo::Code::Aborted);
}

// ---------------------------------------------------------------------------
// The independent brute force: integer points, separating axes, no shared code.

using P = std::array<int64_t, 3>;
P sub(P a, P b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
P cross(P a, P b) { return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; }
int64_t dot(P a, P b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
bool isZero(P a) { return a[0] == 0 && a[1] == 0 && a[2] == 0; }

// Whether the convex hulls of two point sets are disjoint: some axis separates them
// strictly (strict = false: the open interiors, touching allowed).
bool separated(const std::vector<P>& a, const std::vector<P>& b, const std::vector<P>& axes, bool strict) {
  for (const P& ax : axes) {
    if (isZero(ax)) continue;
    int64_t amin = INT64_MAX, amax = INT64_MIN, bmin = INT64_MAX, bmax = INT64_MIN;
    for (const P& p : a) amin = std::min(amin, dot(p, ax)), amax = std::max(amax, dot(p, ax));
    for (const P& p : b) bmin = std::min(bmin, dot(p, ax)), bmax = std::max(bmax, dot(p, ax));
    if (strict ? (amax < bmin || bmax < amin) : (amax <= bmin || bmax <= amin)) return true;
  }
  return false;
}

std::vector<P> edgesOf(const std::vector<P>& poly) {
  std::vector<P> e;
  for (size_t i = 0; i < poly.size(); ++i) e.push_back(sub(poly[(i + 1) % poly.size()], poly[i]));
  if (poly.size() == 2) e.resize(1);
  return e;
}

// Closed convex polygons (triangles or segments) in 3D: do they meet?
bool meet(const std::vector<P>& a, const std::vector<P>& b) {
  std::vector<P> axes;
  auto ea = edgesOf(a), eb = edgesOf(b);
  P na = a.size() == 3 ? cross(ea[0], sub(a[2], a[0])) : P{0, 0, 0};
  P nb = b.size() == 3 ? cross(eb[0], sub(b[2], b[0])) : P{0, 0, 0};
  axes.push_back(na);
  axes.push_back(nb);
  for (const P& x : ea)
    for (const P& y : eb) axes.push_back(cross(x, y));
  for (const P& x : ea) axes.push_back(cross(na, x)), axes.push_back(cross(nb, x));
  for (const P& y : eb) axes.push_back(cross(nb, y)), axes.push_back(cross(na, y));
  // Segment vs segment (none here) would need more; segments always meet a triangle here.
  return !separated(a, b, axes, true);
}

struct Brute {
  std::vector<uint32_t> zeroArea;
  std::vector<std::vector<uint32_t>> groups;  // duplicate groups of 2+, by lowest member
  std::set<std::tuple<uint32_t, uint32_t, std::string>> pairs;
};

Brute brute(const std::vector<std::array<P, 3>>& t) {
  Brute r;
  const size_t n = t.size();
  std::vector<bool> skip(n);
  std::map<std::set<P>, uint32_t> firstOfSet;
  std::vector<int64_t> group(n, -1);
  for (size_t i = 0; i < n; ++i) {
    const auto& x = t[i];
    if (x[0] == x[1] || x[1] == x[2] || x[0] == x[2]) {
      skip[i] = true;
      continue;
    }
    if (isZero(cross(sub(x[1], x[0]), sub(x[2], x[0])))) skip[i] = true, r.zeroArea.push_back(uint32_t(i));
    std::set<P> key(x.begin(), x.end());
    auto it = firstOfSet.emplace(key, uint32_t(i)).first;
    group[i] = it->second;
  }
  std::map<uint32_t, std::vector<uint32_t>> byFirst;
  for (size_t i = 0; i < n; ++i)
    if (group[i] >= 0) byFirst[uint32_t(group[i])].push_back(uint32_t(i));
  for (auto& [first, members] : byFirst)
    if (members.size() > 1) r.groups.push_back(members);
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 1; j < n; ++j) {
      if (skip[i] || skip[j] || group[i] == group[j]) continue;
      const auto &a = t[i], &b = t[j];
      std::vector<P> va(a.begin(), a.end()), vb(b.begin(), b.end());
      std::vector<int> sa, sb;
      for (int u = 0; u < 3; ++u)
        for (int v = 0; v < 3; ++v)
          if (a[u] == b[v]) sa.push_back(u), sb.push_back(v);
      bool hit;
      P na = cross(sub(a[1], a[0]), sub(a[2], a[0]));
      if (sa.empty()) {
        hit = meet(va, vb);
      } else if (sa.size() == 1) {
        std::vector<P> oa = {a[(sa[0] + 1) % 3], a[(sa[0] + 2) % 3]}, ob = {b[(sb[0] + 1) % 3], b[(sb[0] + 2) % 3]};
        hit = meet(oa, vb) || meet(ob, va);
      } else {
        const P& p = a[sa[0]];
        const P& q = a[sa[1]];
        const P& c = a[3 - sa[0] - sa[1]];
        const P& d = b[3 - sb[0] - sb[1]];
        hit = dot(na, sub(d, p)) == 0 && dot(cross(sub(q, p), sub(c, p)), cross(sub(q, p), sub(d, p))) > 0;
      }
      if (!hit) continue;
      P nb = cross(sub(b[1], b[0]), sub(b[2], b[0]));
      auto sides = [](const P& n, const P& o, const std::array<P, 3>& pts, int& pos, int& neg) {
        pos = neg = 0;
        for (const P& x : pts) {
          int64_t d = dot(n, sub(x, o));
          pos += d > 0;
          neg += d < 0;
        }
      };
      int bp, bn, ap, an;
      sides(na, a[0], b, bp, bn);
      sides(nb, b[0], a, ap, an);
      std::string kind;
      if (bp == 0 && bn == 0) {
        std::vector<P> axes;
        for (const P& e : edgesOf(va)) axes.push_back(cross(na, e));
        for (const P& e : edgesOf(vb)) axes.push_back(cross(na, e));
        kind = separated(va, vb, axes, false) ? "touching" : "coplanar";
      } else {
        kind = (ap && an && bp && bn) ? "crossing" : "touching";
      }
      r.pairs.insert({uint32_t(i), uint32_t(j), kind});
    }
  return r;
}

// The pass on a soup of the triangles t (corners on the integer grid): the mesh it read,
// the triangle checks, and the pairs found with their kind. ok is false (with a failure
// recorded) when a stage failed.
struct Passed {
  bool ok = false;
  stltopo::Mesh mesh;
  stltopo::TriangleChecks checks;
  std::set<std::tuple<uint32_t, uint32_t, std::string>> pairs;
};
void runPass(const std::vector<std::array<P, 3>>& t, Passed& out, unsigned threads = 1) {
  Soup soup;
  for (const auto& x : t) {
    uint32_t b = uint32_t(soup.v.size());
    for (auto& c : x) soup.v.push_back({float(c[0]), float(c[1]), float(c[2])});
    soup.f.push_back({b, b + 1, b + 2});
  }
  ASSERT_TRUE(gen::read(gen::binary(soup), out.mesh).ok());
  stltopo::Topology topo;
  ASSERT_TRUE(stltopo::buildTopology(out.mesh, topo).ok());
  ASSERT_TRUE(stltopo::checkTriangles(out.mesh, &topo, out.checks).ok());
  stltopo::Intersections x;
  stltopo::IntersectionOptions o;
  o.threads = threads;
  ASSERT_TRUE(stltopo::findIntersections(out.mesh, topo, out.checks, x, o).ok());
  for (size_t i = 0; i < x.nPairs(); ++i)
    out.pairs.insert(
        {x.pairs[2 * i], x.pairs[2 * i + 1], stltopo::intersectionKindName(stltopo::IntersectionKind(x.kinds[i]))});
  out.ok = true;
}

TEST(Geometry, RandomizedAgainstIntegerBruteForce) {
  std::mt19937 rng(12345);
  int withPairs = 0, total = 0;
  size_t dupGroups = 0;
  std::map<std::string, int> kinds;
  for (int round = 0; round < 3000; ++round) {
    const int grid = 2 + int(rng() % 4);  // coordinates 0..grid
    const int poolSize = 4 + int(rng() % 6);
    std::vector<P> pool;
    for (int i = 0; i < poolSize; ++i)
      pool.push_back({int64_t(rng() % (grid + 1)), int64_t(rng() % (grid + 1)), int64_t(rng() % (grid + 1))});
    const int nt = 2 + int(rng() % 7);
    std::vector<std::array<P, 3>> t;
    for (int i = 0; i < nt; ++i) {
      std::array<P, 3> x;
      for (auto& c : x) c = pool[rng() % pool.size()];
      t.push_back(x);
    }
    Brute want = brute(t);
    Passed run;
    runPass(t, run);
    ASSERT_TRUE(run.ok) << "round " << round;
    const stltopo::Mesh& mesh = run.mesh;
    const stltopo::TriangleChecks& checks = run.checks;
    const auto& got = run.pairs;
    ASSERT_EQ(std::vector<uint32_t>(checks.zeroArea.begin(), checks.zeroArea.end()), want.zeroArea)
        << "round " << round;
    ASSERT_EQ(got, want.pairs) << "round " << round;
    std::vector<std::vector<uint32_t>> groups;
    for (uint32_t g = 0; g < checks.nDuplicateGroups(); ++g)
      groups.emplace_back(checks.duplicateTriangles.data() + checks.duplicateOffsets[g],
                          checks.duplicateTriangles.data() + checks.duplicateOffsets[g + 1]);
    ASSERT_EQ(groups, want.groups) << "round " << round;
    // Without a topology (the sieve, then the exact table) the checks are the same.
    stltopo::TriangleChecks alone;
    ASSERT_TRUE(stltopo::checkTriangles(mesh, nullptr, alone).ok());
    ASSERT_TRUE(sameChecks(alone, checks)) << "round " << round;
    dupGroups += groups.size();
    ++total;
    withPairs += !got.empty();
    for (auto& p : got) ++kinds[std::get<2>(p)];
  }
  // The cases must exercise every kind, often.
  EXPECT_GT(withPairs, total / 4);
  EXPECT_GT(kinds["crossing"], 100);
  EXPECT_GT(kinds["touching"], 100);
  EXPECT_GT(kinds["coplanar"], 100);
  EXPECT_GT(dupGroups, 100u);
}

// Two triangles that share one corner and straddle each other's planes: they cross exactly
// when the lines where each meets the other's plane leave the shared corner the same way.
TEST(Geometry, SharedCornerStraddlesCrossOnlyWhenTheyLeaveTheCornerTheSameWay) {
  Result same, opposite, touching;
  analyze(tris({{{{0, 0, 0}, {4, 0, 0}, {0, 4, 0}}}, {{{0, 0, 0}, {1, 1, 2}, {1, 1, -2}}}}), same);
  EXPECT_EQ(pairsOf(same.geo.intersections), std::vector<std::string>({"0 1 crossing"}));
  analyze(tris({{{{0, 0, 0}, {4, 0, 0}, {0, 4, 0}}}, {{{0, 0, 0}, {-1, -1, 2}, {-1, -1, -2}}}}), opposite);
  EXPECT_EQ(pairsOf(opposite.geo.intersections), std::vector<std::string>{});
  // The far side of one ending exactly on the other's far side: still crossing (each has
  // corners strictly on both sides of the other's plane).
  analyze(tris({{{{0, 0, 0}, {4, 0, 0}, {0, 4, 0}}}, {{{0, 0, 0}, {2, 2, 2}, {2, 2, -2}}}}), touching);
  EXPECT_EQ(pairsOf(touching.geo.intersections), std::vector<std::string>({"0 1 crossing"}));
}

// The pass decides pairs that share corners (nearly every candidate pair of a mesh) by a few
// exact signs before the full pair test; it must agree with that test on every pair: on an
// integer grid (corners in the other's plane, on its sides) and with random coordinates
// (strict straddles), sharing a corner or a side, with the kind and the point of the full test.
TEST(Geometry, NeighbourPairsAgreeWithTheFullPairTest) {
  std::mt19937 rng(2024);
  std::map<std::string, int> seen;
  for (int round = 0; round < 20000; ++round) {
    const bool grid = round % 2 == 0;
    const bool side = round % 3 == 0;
    const bool flat = grid && round % 5 < 2;  // all in the plane z = 0
    auto coord = [&]() -> float { return grid ? float(int(rng() % 5) - 2) : float(int(rng() % 2001) - 1000) / 256.0f; };
    auto point = [&]() -> std::array<float, 3> { return {coord(), coord(), flat ? 0.0f : coord()}; };
    std::array<float, 3> s0 = point(), s1 = point(), a1 = point(), a2 = point(), b2 = point();
    // a = (s0, a1, a2), b = (s0, s1, b2) or, sharing the side s0 a1, (a1, s0, b2); the corner
    // order of b varies.
    std::array<std::array<float, 3>, 3> ta{{s0, a1, a2}};
    std::array<std::array<float, 3>, 3> tb =
        side ? std::array<std::array<float, 3>, 3>{{a1, s0, b2}} : std::array<std::array<float, 3>, 3>{{s0, s1, b2}};
    std::rotate(tb.begin(), tb.begin() + rng() % 3, tb.end());
    Soup soup = tris({ta, tb});
    stltopo::Mesh mesh;
    ASSERT_TRUE(gen::read(gen::binary(soup), mesh).ok());
    stltopo::Topology topo;
    ASSERT_TRUE(stltopo::buildTopology(mesh, topo).ok());
    stltopo::TriangleChecks checks;
    ASSERT_TRUE(stltopo::checkTriangles(mesh, &topo, checks).ok());
    if (!checks.zeroArea.empty() || topo.nDegenerate || checks.nDuplicateTriangles) continue;
    stltopo::Intersections x;
    ASSERT_TRUE(stltopo::findIntersections(mesh, topo, checks, x).ok());
    stltopo::geometry_detail::Tri t[2];
    for (int i = 0; i < 2; ++i)
      for (int c = 0; c < 3; ++c) {
        t[i].v[c] = mesh.triangles[3 * i + c];
        t[i].p[c] = mesh.positions.data() + 3 * size_t(t[i].v[c]);
      }
    int shared = 0;
    for (uint32_t u : t[0].v)
      for (uint32_t v : t[1].v) shared += u == v;
    double p01[3], p10[3];
    const int k01 = stltopo::geometry_detail::trianglePairTest(t[0], t[1], p01);
    const int k10 = stltopo::geometry_detail::trianglePairTest(t[1], t[0], p10);
    ASSERT_EQ(k01, k10) << "round " << round;
    ASSERT_EQ(x.nPairs(), k01 < 0 ? 0u : 1u) << "round " << round << ", sharing " << shared;
    if (k01 >= 0) {
      ASSERT_EQ(int(x.kinds[0]), k01) << "round " << round;
      const bool same01 = std::equal(p01, p01 + 3, x.points.data()), same10 = std::equal(p10, p10 + 3, x.points.data());
      ASSERT_TRUE(same01 || same10) << "round " << round;
    }
    ++seen[std::to_string(shared) +
           (k01 < 0 ? " apart" : std::string(" ") + stltopo::intersectionKindName(stltopo::IntersectionKind(k01)))];
  }
  // Every outcome, often: fold-overs across a side, and crossings, touchings, coplanar
  // overlaps and misses at a corner.
  for (const char* k : {"2 apart", "2 coplanar", "1 apart", "1 crossing", "1 touching", "1 coplanar"})
    EXPECT_GT(seen[k], 100) << k;
}

// Triangles with no shared corner whose corners lie off each other's planes (the pass's
// strict-straddle test) and, on a coarse grid, on them (the side-by-side test), against the
// integer brute force; kinds included.
TEST(Geometry, UnsharedPairsAgainstIntegerBruteForce) {
  std::mt19937 rng(777);
  std::map<std::string, int> kinds;
  for (int round = 0; round < 4000; ++round) {
    const int range = round % 4 == 0 ? 3 : 60;  // -range..range
    const int nt = 2 + int(rng() % 3);
    std::vector<std::array<P, 3>> t;
    for (int i = 0; i < nt; ++i) {
      std::array<P, 3> x;
      for (auto& c : x)
        for (auto& k : c) k = int64_t(rng() % (2 * range + 1)) - range;
      t.push_back(x);
    }
    Brute want = brute(t);
    Passed run;
    runPass(t, run);
    ASSERT_TRUE(run.ok) << "round " << round;
    const auto& got = run.pairs;
    ASSERT_EQ(got, want.pairs) << "round " << round;
    for (auto& g : got) ++kinds[std::get<2>(g)];
  }
  EXPECT_GT(kinds["crossing"], 500);
  EXPECT_GT(kinds["touching"], 30);
}

// ---------------------------------------------------------------------------
// Fan certificates: the pass skips the pairs that share a vertex whose closed fan projects
// along an axis as sectors winding once around it (geometry.cpp, certifyFans).

// A closed bipyramid: apexes t and b over the link polygon a[0..m): faces (t, a[i], a[i+1])
// (the first m) and (b, a[i+1], a[i]). Every vertex has one closed manifold fan when the
// points are distinct.
std::vector<std::array<P, 3>> bipyramid(P t, P b, const std::vector<P>& a) {
  std::vector<std::array<P, 3>> f;
  const size_t m = a.size();
  for (size_t i = 0; i < m; ++i) f.push_back({t, a[i], a[(i + 1) % m]});
  for (size_t i = 0; i < m; ++i) f.push_back({b, a[(i + 1) % m], a[i]});
  return f;
}

// The pass on triangles t (as runPass), and whether the vertex at point c is certified.
struct FanRun {
  Passed run;
  bool certified = false;
};
void runFan(const std::vector<std::array<P, 3>>& t, P c, FanRun& out) {
  runPass(t, out.run);
  ASSERT_TRUE(out.run.ok);
  stltopo::Topology topo;
  ASSERT_TRUE(stltopo::buildTopology(out.run.mesh, topo).ok());
  const stltopo::Mesh& mesh = out.run.mesh;
  uint32_t id = stltopo::kInvalid;
  for (uint32_t v = 0; v < mesh.nVertices(); ++v)
    if (mesh.positions[3 * v] == float(c[0]) && mesh.positions[3 * v + 1] == float(c[1]) &&
        mesh.positions[3 * v + 2] == float(c[2]))
      id = v;
  ASSERT_NE(id, stltopo::kInvalid);
  stltopo::Array<uint8_t> certified;
  ASSERT_TRUE(stltopo::geometry_detail::fanCertificatesForTesting(mesh, topo, out.run.checks, certified).ok());
  out.certified = certified[id] != 0;
}

// Whether some pair of `pairs` has both triangles at point c.
bool pairAt(const std::vector<std::array<P, 3>>& t, const std::set<std::tuple<uint32_t, uint32_t, std::string>>& pairs,
            P c) {
  auto has = [&](uint32_t i) { return t[i][0] == c || t[i][1] == c || t[i][2] == c; };
  for (auto& x : pairs)
    if (has(std::get<0>(x)) && has(std::get<1>(x))) return true;
  return false;
}

TEST(Geometry, FanCertificatesCoverACleanTorus) {
  // Without the patch certificates, which would skip the pairs inside whole nodes first.
  struct PatchesOff {
    PatchesOff() { stltopo::geometry_detail::setPatchCertificatesForTesting(false); }
    ~PatchesOff() { stltopo::geometry_detail::setPatchCertificatesForTesting(true); }
  } off;
  const uint64_t certified0 = stltopo::geometry_detail::fanCertifiedVerticesForTesting();
  const uint64_t skipped0 = stltopo::geometry_detail::fanSkippedPairsForTesting();
  Result t;
  analyze(gen::torus(64, 32), t, {}, false);
  EXPECT_EQ(t.geo.intersections.nPairs(), 0u);
  // Every vertex of the torus is certified, and the pass used them: nearly every candidate
  // pair of a clean mesh is a neighbour pair.
  EXPECT_EQ(stltopo::geometry_detail::fanCertifiedVerticesForTesting() - certified0, uint64_t(t.mesh.nVertices()));
  // Each triangle has 12 others at its corners (3 across its sides, 9 at corners only),
  // whose boxes all overlap its own: 6 pairs per triangle, all skipped.
  EXPECT_EQ(stltopo::geometry_detail::fanSkippedPairsForTesting() - skipped0, 6u * t.mesh.nTriangles());
  stltopo::Array<uint8_t> certified;
  ASSERT_TRUE(stltopo::geometry_detail::fanCertificatesForTesting(t.mesh, t.topo, t.geo.checks, certified).ok());
  for (uint32_t v = 0; v < t.mesh.nVertices(); ++v) ASSERT_EQ(certified[v], 1) << v;
  // With a hole (a quad left out: 4 boundary vertices), the others stay certified.
  const uint64_t certified1 = stltopo::geometry_detail::fanCertifiedVerticesForTesting();
  Result cut;
  analyze(gen::torus(64, 32, {5}), cut, {}, false);
  const uint64_t n = stltopo::geometry_detail::fanCertifiedVerticesForTesting() - certified1;
  EXPECT_EQ(n, uint64_t(cut.mesh.nVertices()) - 4);
}

// Fans that must not be certified, each with pairs that share its centre: the pass finds
// them all (the integer brute force decides).
TEST(Geometry, FanCertificatesRefuseFansThatOverlap) {
  const std::vector<P> star = {{10, 0, 0}, {-8, 6, 0}, {3, -10, 0}, {3, 10, 0}, {-8, -6, 0}};  // a pentagram
  struct Case {
    const char* name;
    P t, b;
    std::vector<P> link;
  };
  const std::vector<Case> cases = {
      // (1) holds, the link winds twice around the apex: opposite chords cross.
      {"cone over a pentagram", {0, 0, 3}, {0, 0, -3}, star},
      // (1) holds, the link winds twice in the fan's own plane: coplanar overlaps.
      {"flat pentagram", {0, 0, 0}, {0, 0, -3}, star},
      // Two fan triangles that share only the apex pass through each other.
      {"folded fan",
       {0, 0, 0},
       {0, 0, -20},
       {{10, 0, 0}, {0, 10, 0}, {-10, 0, 0}, {5, 5, 5}, {5, 5, -5}, {0, -10, 0}}},
      // Flat, folded over the side from the centre to (0, 10, 0).
      {"fold-over across a side", {0, 0, 0}, {0, 0, -5}, {{10, 0, 0}, {0, 10, 0}, {5, 5, 0}, {-10, -10, 0}, {10, -10, 0}}},
  };
  for (const Case& c : cases) {
    const auto t = bipyramid(c.t, c.b, c.link);
    Brute want = brute(t);
    ASSERT_TRUE(pairAt(t, want.pairs, c.t)) << c.name << ": the case must have a pair sharing its centre";
    FanRun f;
    runFan(t, c.t, f);
    EXPECT_FALSE(f.certified) << c.name;
    EXPECT_EQ(f.run.pairs, want.pairs) << c.name;
  }
  // A pinch: two closed fans at one vertex, one flat in z = 0, one in x = 0; each alone would
  // be certified, but the vertex has two cycles of sides (vertexNonManifold).
  {
    auto t = bipyramid({0, 0, 0}, {0, 0, -5}, {{10, 0, 0}, {0, 10, 0}, {-10, 0, 0}, {0, -10, 0}});
    const auto second = bipyramid({0, 0, 0}, {9, 0, 0}, {{0, 7, 7}, {0, -7, 7}, {0, -7, -7}, {0, 7, -7}});
    t.insert(t.end(), second.begin(), second.end());
    Brute want = brute(t);
    ASSERT_TRUE(pairAt(t, want.pairs, {0, 0, 0})) << "pinch";
    FanRun f;
    runFan(t, {0, 0, 0}, f);
    EXPECT_FALSE(f.certified) << "pinch";
    EXPECT_EQ(f.run.pairs, want.pairs) << "pinch";
  }
  // The same apexes over a convex link are certified, and nothing intersects.
  const auto clean = bipyramid({0, 0, 3}, {0, 0, -3}, {{10, 0, 0}, {3, 10, 0}, {-8, 6, 0}, {-8, -6, 0}, {3, -10, 0}});
  FanRun f;
  runFan(clean, {0, 0, 3}, f);
  EXPECT_TRUE(f.certified);
  EXPECT_TRUE(f.run.pairs.empty());
}

// Random bipyramids on a small integer grid (many folded, flat, star-shaped and clean fans)
// against the integer brute force: the certificates never hide a pair.
TEST(Geometry, FanCertificatesAgainstIntegerBruteForce) {
  std::mt19937 rng(4242);
  int certified = 0, refused = 0, withPairs = 0;
  for (int round = 0; round < 3000; ++round) {
    const int grid = 3 + int(rng() % 4);
    const int m = 3 + int(rng() % 6);
    std::set<P> used;
    auto point = [&](bool flat) {
      for (;;) {
        P p = {int64_t(rng() % (grid + 1)), int64_t(rng() % (grid + 1)), flat ? 0 : int64_t(rng() % (grid + 1))};
        if (used.insert(p).second) return p;
      }
    };
    const bool flat = round % 3 == 0;  // the apex and the link in one plane
    const bool sorted = round % 2 == 1;
    if (sorted) used.insert({grid / 2, grid / 2, flat ? 0 : grid / 2});
    const P t = sorted ? P{grid / 2, grid / 2, flat ? 0 : grid / 2} : point(flat);
    P b = point(false);
    std::vector<P> link;
    for (int i = 0; i < m; ++i) link.push_back(point(flat));
    // Half the rounds: the apex in the middle, the link sorted by angle around it (mostly
    // certifiable fans).
    if (sorted) {
      std::sort(link.begin(), link.end(), [&](const P& x, const P& y) {
        return std::atan2(double(x[1] - t[1]), double(x[0] - t[0])) < std::atan2(double(y[1] - t[1]), double(y[0] - t[0]));
      });
      b = {t[0], t[1], t[2] - 2 * grid - 1};
    }
    const auto tr = bipyramid(t, b, link);
    Brute want = brute(tr);
    FanRun f;
    runFan(tr, t, f);
    ASSERT_EQ(f.run.pairs, want.pairs) << "round " << round;
    if (f.certified) {
      ++certified;
      ASSERT_FALSE(pairAt(tr, want.pairs, t)) << "round " << round;
    } else {
      ++refused;
    }
    withPairs += !want.pairs.empty();
  }
  EXPECT_GT(certified, 300);
  EXPECT_GT(refused, 300);
  EXPECT_GT(withPairs, 300);
}

// ---------------------------------------------------------------------------
// Patch certificates (geometry.cpp, certifyPatches): hierarchy nodes whose triangles all
// face one way along an axis, and whose boundary, projected along it, is made of loops that
// do not cross, with the triangles covering each point at most once, are skipped by the
// join. With the smallest node tried lowered to 2 positions, small meshes exercise them.

struct PatchMinimum {
  explicit PatchMinimum(uint32_t n) { stltopo::geometry_detail::setPatchMinimumForTesting(n); }
  ~PatchMinimum() { stltopo::geometry_detail::setPatchMinimumForTesting(0); }
};
// The largest node tried top down within the budget, and the tasks' size as a multiple of it
// (1: larger nodes are tried only as unions of certified children; 0: the defaults).
struct PatchTaskSize {
  explicit PatchTaskSize(uint32_t n, uint32_t scale = 0) {
    stltopo::geometry_detail::setPatchTaskSizeForTesting(n, scale);
  }
  ~PatchTaskSize() { stltopo::geometry_detail::setPatchTaskSizeForTesting(0); }
};

// A height field over a g x g grid of points 3 apart (z random in [0, zr]), each cell cut by
// a random diagonal, every triangle counter-clockwise seen from above.
std::vector<std::array<P, 3>> heightField(std::mt19937& rng, int g, int zr) {
  std::vector<std::vector<P>> v(g, std::vector<P>(g));
  for (int i = 0; i < g; ++i)
    for (int j = 0; j < g; ++j) v[i][j] = {3 * i, 3 * j, zr ? int64_t(rng() % (zr + 1)) : 0};
  std::vector<std::array<P, 3>> t;
  for (int i = 0; i + 1 < g; ++i)
    for (int j = 0; j + 1 < g; ++j) {
      const P &a = v[i][j], &b = v[i + 1][j], &c = v[i + 1][j + 1], &d = v[i][j + 1];
      if (rng() % 2) {
        t.push_back({a, b, c});
        t.push_back({a, c, d});
      } else {
        t.push_back({a, b, d});
        t.push_back({b, c, d});
      }
    }
  return t;
}

// The pass over t finds no pair, and every position is in a certified patch.
void expectOnePatch(const std::vector<std::array<P, 3>>& t) {
  const uint64_t before = stltopo::geometry_detail::patchCertifiedPositionsForTesting();
  Passed run;
  runPass(t, run);
  ASSERT_TRUE(run.ok);
  EXPECT_TRUE(run.pairs.empty());
  EXPECT_EQ(stltopo::geometry_detail::patchCertifiedPositionsForTesting() - before, uint64_t(t.size()));
}

// A clean height field is one patch: no pair, and the join skips it whole.
TEST(Geometry, PatchCertificatesCoverAHeightField) {
  std::mt19937 rng(7);
  expectOnePatch(heightField(rng, 12, 5));  // 242 triangles
  // A clean torus of 8192 triangles: every position is in a certified node.
  const uint64_t before2 = stltopo::geometry_detail::patchCertifiedPositionsForTesting();
  Result torus;
  analyze(gen::torus(128, 32), torus, {}, false);
  EXPECT_EQ(torus.geo.intersections.nPairs(), 0u);
  EXPECT_EQ(stltopo::geometry_detail::patchCertifiedPositionsForTesting() - before2, uint64_t(torus.mesh.nTriangles()));
}

// A clean torus of 32,768 triangles, with tasks of 8192 positions (no node above them tried
// from its triangles): four tasks, each certified, and two unions above them (each half of
// the torus along its axis projects once; the whole torus does not), so that the join no
// longer tests the pairs between the quarters of a half. With the default tasks (one of
// 32,768 positions), the halves are certified from their triangles instead: the same
// positions and the same work, without a union.
TEST(Geometry, PatchUnionsCoverACleanTorus) {
  const auto soup = gen::torus(256, 64);
  uint64_t work[2];
  PatchTaskSize tasks(8192, 1);
  for (int unions = 0; unions < 2; ++unions) {
    stltopo::geometry_detail::setPatchUnionsForTesting(unions == 1);
    const uint64_t positions0 = stltopo::geometry_detail::patchCertifiedPositionsForTesting();
    const uint64_t unions0 = stltopo::geometry_detail::patchUnionsForTesting();
    Result r;
    analyze(soup, r, {}, false);
    EXPECT_EQ(r.geo.intersections.nPairs(), 0u);
    EXPECT_EQ(stltopo::geometry_detail::patchCertifiedPositionsForTesting() - positions0,
              uint64_t(r.mesh.nTriangles()));
    work[unions] = r.geo.intersections.work;
    EXPECT_EQ(stltopo::geometry_detail::patchUnionsForTesting() - unions0, unions ? 2u : 0u);
  }
  EXPECT_LT(work[1], work[0]);
  // On 4 threads, with the parts split down to single items (so that the unions below the top
  // run on several threads): the same unions and the same work.
  stltopo::setParallelGrainForTesting(1);
  const uint64_t unions1 = stltopo::geometry_detail::patchUnionsForTesting();
  stltopo::IntersectionOptions o;
  o.threads = 4;
  Result r;
  analyze(soup, r, o, false);
  stltopo::setParallelGrainForTesting(0);
  EXPECT_EQ(r.geo.intersections.nPairs(), 0u);
  EXPECT_EQ(stltopo::geometry_detail::patchUnionsForTesting() - unions1, 2u);
  EXPECT_EQ(r.geo.intersections.work, work[1]);
  // The default tasks: the two halves from their triangles.
  PatchTaskSize defaults(0);
  const uint64_t unions2 = stltopo::geometry_detail::patchUnionsForTesting();
  const uint64_t large2 = stltopo::geometry_detail::patchLargeNodesForTesting();
  const uint64_t positions2 = stltopo::geometry_detail::patchCertifiedPositionsForTesting();
  Result d;
  analyze(soup, d, {}, false);
  EXPECT_EQ(d.geo.intersections.nPairs(), 0u);
  EXPECT_EQ(stltopo::geometry_detail::patchUnionsForTesting() - unions2, 0u);
  EXPECT_EQ(stltopo::geometry_detail::patchLargeNodesForTesting() - large2, 2u);
  EXPECT_EQ(stltopo::geometry_detail::patchCertifiedPositionsForTesting() - positions2, uint64_t(d.mesh.nTriangles()));
  EXPECT_EQ(d.geo.intersections.work, work[1]);
}

// Nodes that must not be certified, each hiding pairs inside one node: a sheet crossing a
// flat field from inside it (two loops turning the same way, one inside the other: the
// triangles cover the inner region twice), a ramp that winds past its own start and comes
// down through it (its boundary crosses itself in projection), and a field with a flap
// folded back over it (a loop through a corner twice). The brute force decides.
TEST(Geometry, PatchCertificatesRefuseNodesThatOverlap) {
  PatchMinimum small(2);
  std::mt19937 rng(11);
  std::vector<std::pair<const char*, std::vector<std::array<P, 3>>>> cases;
  {
    auto t = heightField(rng, 8, 0);  // z = 0, x, y in [0, 21]
    t.push_back({P{6, 6, -2}, P{15, 6, 3}, P{15, 15, 3}});
    t.push_back({P{6, 6, -2}, P{15, 15, 3}, P{6, 15, -2}});
    cases.push_back({"a sheet through a field", t});
  }
  {
    // A ramp around the z axis: 10 sectors of 45 degrees (450 degrees in all), rising
    // steeply, then dropping through its first sector at the end.
    std::vector<std::array<P, 3>> t;
    const double r0 = 20, r1 = 40;
    auto at = [](double r, double a, int64_t z) {
      return P{int64_t(std::lround(r * std::cos(a))), int64_t(std::lround(r * std::sin(a))), z};
    };
    for (int k = 0; k < 10; ++k) {
      const double a0 = k * M_PI / 4, a1 = (k + 1) * M_PI / 4;
      const int64_t z0 = k < 9 ? 2 * k : 16, z1 = k < 8 ? 2 * (k + 1) : k == 8 ? 16 : -5;
      const P p = at(r0, a0, z0), q = at(r1, a0, z0), u = at(r1, a1, z1), v = at(r0, a1, z1);
      t.push_back({p, q, u});
      t.push_back({p, u, v});
    }
    cases.push_back({"a ramp past its start", t});
  }
  {
    auto t = heightField(rng, 6, 0);  // z = 0, x, y in [0, 15]
    // A flap on the side x = 15, folded back over the field, dipping through it.
    t.push_back({P{15, 3, 0}, P{15, 6, 0}, P{6, 6, 2}});
    t.push_back({P{15, 3, 0}, P{6, 6, 2}, P{6, 3, -2}});
    cases.push_back({"a folded flap", t});
  }
  {
    auto t = heightField(rng, 6, 0);  // z = 0, x, y in [0, 15]
    // A triangle at the field's corner (0, 0, 0), over the field and through it: the
    // boundary leaves that corner twice, and the sides there do not alternate.
    t.push_back({P{0, 0, 0}, P{9, 3, 2}, P{3, 9, -2}});
    cases.push_back({"a triangle at a corner", t});
  }
  // Each case again with its added triangles wound the other way: they are then the few of
  // their node that turn against the rest, and the certificate wound over them is tried.
  const size_t nCases = cases.size();
  for (size_t c = 0; c < nCases; ++c) {
    auto t = cases[c].second;
    const size_t field = c == 0 ? 98 : c == 1 ? 0 : 50;
    if (field == 0) continue;  // the ramp is all added
    for (size_t i = field; i < t.size(); ++i) std::swap(t[i][1], t[i][2]);
    cases.push_back({"wound the other way", t});
  }
  // With every node of more than 4 positions tried only as a union of its children.
  for (uint32_t taskSize : {0u, 4u}) {
    PatchTaskSize tasks(taskSize);
    for (auto& [name, t] : cases) {
      Brute want = brute(t);
      ASSERT_FALSE(want.pairs.empty()) << name << ": the case must have pairs";
      Passed run;
      runPass(t, run);
      ASSERT_TRUE(run.ok) << name;
      EXPECT_EQ(run.pairs, want.pairs) << name << ", tasks of " << taskSize;
    }
  }
}

// A height field with one triangle in 20 wound the other way (what a mesh with flipped
// faces looks like): the certificate is tried on the triangles wound to face one way, and
// the whole field is one patch, as its points are the same.
TEST(Geometry, PatchCertificatesCoverAFieldWithFlippedTriangles) {
  std::mt19937 rng(8);
  auto t = heightField(rng, 12, 5);  // 242 triangles
  int flipped = 0;
  for (size_t i = 0; i < t.size(); i += 20, ++flipped) std::swap(t[i][1], t[i][2]);
  ASSERT_GT(flipped, 10);
  expectOnePatch(t);
}

// Random height fields, damaged (corners dragged across the field, triangles flipped or
// removed, stray triangles added), against the integer brute force, with every node of two
// or more positions tried: the certificates never hide a pair.
// The same with the nodes of more than 8 positions tried only as unions of their children
// (scale 1), or also from their triangles inside tasks of 32 positions (scale 4), every other
// round on 3 threads with the parts split down to single items: the unions and the large
// nodes never hide a pair either.
void patchesAgainstIntegerBruteForce(uint32_t taskSize, uint32_t scale = 0) {
  PatchMinimum small(2);
  PatchTaskSize tasks(taskSize, scale);
  stltopo::setParallelGrainForTesting(taskSize ? 1 : 0);
  std::mt19937 rng(2026 + taskSize + scale);
  int withPairs = 0, certifiedRounds = 0, rounds = 0, unionRounds = 0, largeRounds = 0;
  for (int round = 0; round < 1500; ++round) {
    const int g = 3 + int(rng() % 5);
    auto t = heightField(rng, g, int(rng() % 4));
    const int damage = int(rng() % 5);
    for (int d = 0; d < damage; ++d) {
      switch (rng() % 4) {
        case 0: {  // drag a corner to a random point over the field
          const P from = t[rng() % t.size()][rng() % 3];
          const P to = {int64_t(rng() % (3 * g)), int64_t(rng() % (3 * g)), int64_t(rng() % 4) - 1};
          for (auto& x : t)
            for (auto& c : x)
              if (c == from) c = to;
          break;
        }
        case 1: std::swap(t[rng() % t.size()][1], t[rng() % t.size()][2]); break;
        case 2:
          if (t.size() > 2) t.erase(t.begin() + long(rng() % t.size()));
          break;
        default: {  // a stray triangle, counter-clockwise seen from above
          std::array<P, 3> x;
          for (auto& c : x) c = {int64_t(rng() % (3 * g)), int64_t(rng() % (3 * g)), int64_t(rng() % 5) - 2};
          t.push_back(x);
        }
      }
    }
    Brute want = brute(t);
    const uint64_t before = stltopo::geometry_detail::patchCertifiedPositionsForTesting();
    const uint64_t unionsBefore = stltopo::geometry_detail::patchUnionsForTesting();
    const uint64_t largeBefore = stltopo::geometry_detail::patchLargeNodesForTesting();
    Passed run;
    runPass(t, run, taskSize && round % 2 ? 3 : 1);
    ASSERT_TRUE(run.ok) << "round " << round;
    ASSERT_EQ(run.pairs, want.pairs) << "round " << round << ", tasks of " << taskSize;
    certifiedRounds += stltopo::geometry_detail::patchCertifiedPositionsForTesting() > before;
    unionRounds += stltopo::geometry_detail::patchUnionsForTesting() > unionsBefore;
    largeRounds += stltopo::geometry_detail::patchLargeNodesForTesting() > largeBefore;
    withPairs += !want.pairs.empty();
    ++rounds;
  }
  stltopo::setParallelGrainForTesting(0);
  EXPECT_GT(certifiedRounds, rounds / 4);
  EXPECT_GT(withPairs, rounds / 4);
  if (taskSize && scale == 1) EXPECT_GT(unionRounds, rounds / 4);
  if (taskSize && scale != 1) {
    EXPECT_GT(largeRounds, rounds / 4);
    EXPECT_GT(unionRounds, rounds / 20);
  }
}
TEST(Geometry, PatchCertificatesAgainstIntegerBruteForce) { patchesAgainstIntegerBruteForce(0); }
TEST(Geometry, PatchUnionsAgainstIntegerBruteForce) { patchesAgainstIntegerBruteForce(8, 1); }
TEST(Geometry, PatchLargeNodesAgainstIntegerBruteForce) { patchesAgainstIntegerBruteForce(8, 4); }

// Every fixture, and a torus, as read and with corners dragged at random (folds and
// crossings inside what would be patches), with the patches tried at their usual sizes:
// the pass finds the same pairs, kinds and completeness as without them.
TEST(Geometry, PatchCertificatesNeverChangeThePairs) {
#ifndef STLTOPO_FIXTURES
  GTEST_SKIP() << "no fixtures directory";
#else
  const std::vector<std::string> files = gen::fixtureFiles(gen::kWithoutRegress);
  std::vector<std::pair<std::string, std::string>> inputs;  // name, bytes
  for (const std::string& f : files) inputs.push_back({f, gen::readFile(f)});
  inputs.push_back({"torus 256 x 64", gen::binary(gen::torus(256, 64))});
  std::mt19937 rng(99);
  int compared = 0, withPairs = 0;
  const uint64_t certified0 = stltopo::geometry_detail::patchCertifiedPositionsForTesting();
  auto pass = [](const stltopo::Mesh& mesh, bool patches, stltopo::Intersections& x) {
    stltopo::Topology topo;
    stltopo::TriangleChecks checks;
    stltopo::geometry_detail::setPatchCertificatesForTesting(patches);
    stltopo::Status s = stltopo::buildTopology(mesh, topo);
    if (s.ok()) s = stltopo::checkTriangles(mesh, &topo, checks);
    if (s.ok()) s = stltopo::findIntersections(mesh, topo, checks, x);
    stltopo::geometry_detail::setPatchCertificatesForTesting(true);
    return s;
  };
  for (const auto& [name, bytes] : inputs) {
    stltopo::Mesh read;
    if (!gen::read(bytes, read).ok() || read.nTriangles() == 0 || read.nTriangles() > 60000) continue;
    for (int round = 0; round < 3; ++round) {
      stltopo::Mesh mesh;
      ASSERT_TRUE(gen::read(bytes, mesh).ok()) << name;
      if (round > 0) {
        double diag = 0;
        for (int k = 0; k < 3; ++k)
          diag += double(mesh.bboxMax[k] - mesh.bboxMin[k]) * (mesh.bboxMax[k] - mesh.bboxMin[k]);
        const float reach = float(std::sqrt(diag) / (round == 1 ? 200 : 20));
        const uint32_t drags = std::max<uint32_t>(1, mesh.nVertices() / 100);
        std::uniform_real_distribution<float> off(-reach, reach);
        for (uint32_t i = 0; i < drags; ++i) {
          const uint32_t v = uint32_t(rng() % mesh.nVertices());
          for (int k = 0; k < 3; ++k) mesh.positions[3 * size_t(v) + k] += off(rng);
        }
      }
      stltopo::Intersections on, off;
      ASSERT_TRUE(pass(mesh, true, on).ok()) << name;
      ASSERT_TRUE(pass(mesh, false, off).ok()) << name;
      ASSERT_TRUE(gen::sameArray(on.pairs, off.pairs) && gen::sameArray(on.kinds, off.kinds))
          << name << " round " << round;
      ASSERT_EQ(on.complete, off.complete) << name << " round " << round;
      ++compared;
      withPairs += on.nPairs() > 0;
    }
  }
  EXPECT_GT(compared, 150);
  EXPECT_GT(withPairs, 60);
  EXPECT_GT(stltopo::geometry_detail::patchCertifiedPositionsForTesting() - certified0, 100000u);
#endif
}

// analyzeGeometry without the shell list (what `info --intersections` runs without
// --shells): on every fixture, as read and with the tolerance weld, and on nested and
// inside-out cubes, the same `solid` as with the shell list, from the shells' volumes only.
// (and the same after the checks: analyzeGeometryAfterChecks on a topology stripped of the
// arrays the checks read)
TEST(Geometry, SolidWithoutTheShellListIsTheSame) {
  std::vector<std::pair<std::string, std::string>> inputs;  // name, bytes
#ifdef STLTOPO_FIXTURES
  for (const std::string& path : gen::fixtureFiles()) inputs.push_back({path, gen::readFile(path)});
#endif
  inputs.push_back({"cavity", gen::binary(join(cubeSoup(0, 0, 0, 30), cubeSoup(10, 10, 10, 10, true)))});
  inputs.push_back({"nested", gen::binary(join(cubeSoup(0, 0, 0, 30), cubeSoup(10, 10, 10, 10)))});
  inputs.push_back({"inside out", gen::binary(cubeSoup(0, 0, 0, 30, true))});
  inputs.push_back({"three levels", gen::binary(join(join(cubeSoup(0, 0, 0, 30), cubeSoup(5, 5, 5, 20, true)),
                                                     cubeSoup(10, 10, 10, 10)))});
  int solid = 0, compared = 0, fanPasses = 0;
  for (const auto& [name, bytes] : inputs) {
    for (float tolerance : {0.0f, 0.001f}) {
      stltopo::Mesh mesh;
      if (!gen::read(bytes, mesh).ok() || mesh.nTriangles() > 300000) continue;
      stltopo::Topology topo;
      stltopo::TopologyOptions to;
      to.triangleShell = true;
      to.tolerance = tolerance;
      ASSERT_TRUE(stltopo::buildTopology(mesh, topo, to).ok()) << name;
      stltopo::GeometryReport full, lean;
      ASSERT_TRUE(stltopo::analyzeGeometry(mesh, topo, full).ok()) << name;
      ASSERT_TRUE(stltopo::analyzeGeometry(mesh, topo, lean, {}, false).ok()) << name;
      EXPECT_EQ(lean.solid, full.solid) << name << " tolerance " << tolerance;
      EXPECT_TRUE(lean.shells.empty()) << name;
      EXPECT_TRUE(gen::sameArray(lean.intersections.pairs, full.intersections.pairs)) << name;
      // After the checks, on a topology without the arrays only the checks read (what
      // `stltopo info --intersections` does): the same report.
      stltopo::Topology bare;
      ASSERT_TRUE(stltopo::buildTopology(mesh, bare, to).ok()) << name;
      stltopo::GeometryReport after;
      ASSERT_TRUE(stltopo::checkTriangles(mesh, &bare, after.checks).ok()) << name;
      bare.next.release(), bare.prev.release(), bare.face.release();
      bare.triangleHalfedge.release(), bare.vertexHalfedge.release();
      const uint64_t fansBefore = stltopo::geometry_detail::fanCertifiedVerticesForTesting();
      ASSERT_TRUE(stltopo::analyzeGeometryAfterChecks(mesh, bare, after, {}, false).ok()) << name;
      fanPasses += stltopo::geometry_detail::fanCertifiedVerticesForTesting() > fansBefore;
      EXPECT_EQ(after.solid, full.solid) << name << " tolerance " << tolerance;
      EXPECT_TRUE(after.shells.empty()) << name;
      EXPECT_TRUE(gen::sameArray(after.intersections.pairs, full.intersections.pairs)) << name;
      EXPECT_TRUE(gen::sameArray(after.intersections.kinds, full.intersections.kinds)) << name;
      EXPECT_EQ(after.intersections.complete, full.intersections.complete) << name;
      EXPECT_TRUE(gen::sameArray(after.checks.zeroArea, full.checks.zeroArea)) << name;
      EXPECT_EQ(after.checks.nDuplicateTriangles, full.checks.nDuplicateTriangles) << name;
      solid += full.solid;
      ++compared;
    }
  }
  EXPECT_GT(compared, 8);
  EXPECT_GE(solid, 3);
  EXPECT_GT(fanPasses, 0);  // the fan certificates (which read vert and pairKind) ran without the arrays
#ifdef STLTOPO_FIXTURES
  EXPECT_GE(compared, 150);
  EXPECT_GT(solid, 40);
#endif
}

// The exact predicates where floating point alone fails: coordinates far apart in scale.
TEST(Geometry, PredicatesAreExactAcrossScales) {
  // A triangle in the plane z = 0 with huge coordinates, and a point 2^-20 above it
  // next to a huge corner: the naive double determinant loses it.
  Result r;
  analyze(tris({{{{1e7f, 1e7f, 0}, {-1e7f, 1e7f, 0}, {0, -1e7f, 0}}},
                {{{0.5f, 0.5f, 0x1p-20f}, {0.5f, 0.75f, 5}, {0.75f, 0.5f, 5}}},     // above: no hit
                {{{0.5f, 0.5f, -0x1p-20f}, {0.5f, 0.75f, 5}, {0.75f, 0.5f, 5}}}}),  // through
          r);
  bool zeroTwo = false, zeroOne = false;
  for (const std::string& p : pairsOf(r.geo.intersections)) {
    zeroOne |= p.rfind("0 1 ", 0) == 0;
    zeroTwo |= p == "0 2 crossing";
  }
  EXPECT_FALSE(zeroOne);
  EXPECT_TRUE(zeroTwo);
  // Collinear corners far from the origin (exactly collinear in float32) vs nearly.
  Result c;
  analyze(tris({{{{16777216.f, 1, 1}, {16777218.f, 2, 2}, {16777220.f, 3, 3}}},
                {{{16777216.f, 1, 1}, {16777218.f, 2, 2}, {16777220.f, 3, 3.0000002f}}}}),
          c);
  ASSERT_EQ(c.geo.checks.zeroArea.size(), 1u);
  EXPECT_EQ(c.geo.checks.zeroArea[0], 0u);
}

}  // namespace

// The two exact stages of the predicates agree: 128-bit integers (coordinates within 40 bits
// of magnitude) and expansion arithmetic (any input), on random and nearly degenerate inputs.
namespace {

TEST(Geometry, ExactStagesAgree) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(-1, 1);
  int zeros = 0, compared = 0;
  for (int round = 0; round < 200000; ++round) {
    const int scale = int(rng() % 24) - 12;  // magnitudes 2^-12 .. 2^11
    auto pt = [&](std::array<float, 3>& p) {
      for (float& x : p) x = std::ldexp(unit(rng), scale);
    };
    std::array<float, 3> a, b, c, d;
    pt(a), pt(b), pt(c), pt(d);
    switch (round % 5) {
      case 0: break;  // random
      case 1:         // d in the plane of a, b, c (up to float rounding)
        for (int k = 0; k < 3; ++k) d[k] = a[k] + 0.5f * (b[k] - a[k]) + 0.25f * (c[k] - a[k]);
        break;
      case 2:  // d exactly a corner moved by one ulp
        d = a;
        {
          const int k = int(rng() % 3);
          d[k] = std::nextafter(d[k], 2.0f);
        }
        break;
      case 3:  // on a grid: exact coplanarity is frequent
        for (auto* p : {&a, &b, &c, &d})
          for (float& x : *p) x = std::ldexp(float(int(rng() % 5) - 2), scale);
        break;
      case 4: {  // in one axis-aligned plane, often on one axis-aligned line: the filters'
                 // zero-bound shortcut (an exact 0 without the exact stage)
        const int k = int(rng() % 3);
        for (auto* p : {&b, &c, &d}) (*p)[k] = a[k];
        if (rng() % 2)
          for (auto* p : {&b, &d}) (*p)[(k + 1) % 3] = a[(k + 1) % 3];
        if (rng() % 2) d = rng() % 2 ? a : b;
        break;
      }
    }
    const stltopo::pred::Plane plane(a.data(), b.data(), c.data());
    const int e = stltopo::pred::orient3dExpansion(a.data(), b.data(), c.data(), d.data());
    const int x = stltopo::pred::orient3dExact(a.data(), b.data(), c.data(), d.data());
    ASSERT_EQ(x, e) << "round " << round;
    const int f = stltopo::pred::orient3d(a.data(), b.data(), c.data(), d.data());
    ASSERT_EQ(f, e) << "round " << round;
    ASSERT_EQ(plane.side(d.data()), e) << "round " << round;
    const int e2 = stltopo::pred::orient2dExpansion(a[0], a[1], b[0], b[1], d[0], d[1]);
    ASSERT_EQ(stltopo::pred::orient2dExact(a[0], a[1], b[0], b[1], d[0], d[1]), e2) << "round " << round;
    ASSERT_EQ(stltopo::pred::orient2d(a[0], a[1], b[0], b[1], d[0], d[1]), e2) << "round " << round;
    for (int k = 1; k < 3; ++k) {
      const int i = k, j = (k + 1) % 3;
      const int e3 = stltopo::pred::orient2dExpansion(a[i], a[j], b[i], b[j], d[i], d[j]);
      ASSERT_EQ(stltopo::pred::orient2d(a[i], a[j], b[i], b[j], d[i], d[j]), e3) << "round " << round;
    }
    zeros += e == 0;
    ++compared;
  }
  EXPECT_GT(zeros, 1000);  // the exact stages decided many exact zeros
  EXPECT_EQ(compared, 200000);
}

}  // namespace

// The hierarchy's Morton codes, as the pass computes them (x and y two at a time where the
// build has SIMD), against the scalar formula: the same value for every triangle, on random
// bit patterns (denormals, signed zeros, magnitudes up to FLT_MAX), on coordinates spread over
// many magnitudes, on a mesh flat along an axis (scale 0 there) and on centroids that fall on
// cell sides and on the box's faces (the clamp's ends).
TEST(Geometry, MortonCodesAreTheScalarFormula) {
  std::mt19937 rng(20261204);
  auto randomFinite = [&]() {
    for (;;) {
      const uint32_t bits = uint32_t(rng());
      float f;
      std::memcpy(&f, &bits, sizeof f);
      if (std::isfinite(f)) return f;
    }
  };
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  auto check = [](const std::vector<float>& positions, const char* what) {
    std::vector<uint32_t> tri(positions.size() / 3);
    for (uint32_t i = 0; i < tri.size(); ++i) tri[i] = i;
    stltopo::IndexedMesh in;
    in.positions = positions.data();
    in.positionsLength = positions.size();
    in.triangles = tri.data();
    in.trianglesLength = tri.size() - tri.size() % 3;
    stltopo::IndexedOptions o;
    o.weld = stltopo::Weld::None;
    stltopo::Mesh mesh;
    ASSERT_TRUE(stltopo::meshFromIndexed(in, mesh, nullptr, o).ok()) << what;
    stltopo::Array<uint32_t> fast, scalar;
    ASSERT_TRUE(stltopo::geometry_detail::mortonCodesForTesting(mesh, fast, scalar).ok()) << what;
    ASSERT_EQ(fast.size(), mesh.nTriangles()) << what;
    size_t differ = 0;
    for (size_t t = 0; t < fast.size(); ++t) {
      differ += fast[t] != scalar[t];
      EXPECT_LT(scalar[t], 1u << 30) << what;
    }
    EXPECT_EQ(differ, 0u) << what << ": " << fast.size() << " triangles";
  };
  {
    std::vector<float> p(3 * 3 * 20000);
    for (float& x : p) x = randomFinite();
    check(p, "random bit patterns");
  }
  {
    std::vector<float> p(3 * 3 * 20000);
    std::uniform_int_distribution<int> e(-40, 38);
    for (float& x : p) x = unit(rng) * std::pow(10.0f, float(e(rng)));
    check(p, "many magnitudes");
  }
  {
    std::vector<float> p(3 * 3 * 20000);
    for (size_t i = 0; i < p.size(); ++i) p[i] = i % 3 == 1 ? 7.25f : unit(rng) * 100;
    check(p, "flat along y");
  }
  {
    // Corners on a grid of 1023 * 3 steps over [0, 1]: centroids on and next to cell sides,
    // with the box's corners present so that the box is [0, 1]^3.
    std::vector<float> p = {0, 0, 0, 1, 1, 1, 0, 1, 0};
    std::uniform_int_distribution<int> g(0, 3 * 1023);
    for (int i = 0; i < 3 * 20000; ++i)
      for (int k = 0; k < 3; ++k) {
        float x = float(g(rng)) / float(3 * 1023);
        if (rng() % 4 == 0) x = std::nextafter(x, rng() % 2 ? 2.0f : -1.0f);
        p.push_back(std::min(1.0f, std::max(0.0f, x)));
      }
    check(p, "cell sides");
  }
  {
    // The box [0, 1023]^3 (scale 1): centroids on integer coordinates, so that q is an integer
    // exactly and a rounding other than the formula's (a multiplication by 1/3 instead of the
    // division, say) lands in the cell below.
    std::vector<float> p = {0, 0, 0, 1023, 1023, 1023, 0, 1023, 0};
    // Centroids in the top cell and on the box's top face (q = 1023, the clamp's upper end).
    p.insert(p.end(), {1023, 1023, 1023, 1023, 1023, 1023, 1023, 1023, 1023});
    p.insert(p.end(), {1022.5f, 0, 1023, 1022.5f, 0, 1023, 1022.5f, 0, 1023});
    std::uniform_int_distribution<int> g(0, 1023);
    for (int i = 0; i < 20000; ++i) {
      float c[3][3];
      for (int k = 0; k < 3; ++k) {
        int m, a, b, d;  // m: the centroid's coordinate, the mean of a, b and d
        do {
          m = g(rng), a = g(rng), b = g(rng);
          d = 3 * m - a - b;
        } while (d < 0 || d > 1023);
        c[0][k] = float(a), c[1][k] = float(b), c[2][k] = float(d);
      }
      for (auto& corner : c) p.insert(p.end(), corner, corner + 3);
    }
    check(p, "integer centroids");
  }
}
