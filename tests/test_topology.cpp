// Topology: pairing, boundary loops (holes vs seams, fan rule), vertex loops,
// report fields, navigation identities and validate() on generated meshes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "predicates.h"  // private (src/): the weld's distance test, checked below
#include "stl_gen.h"

using namespace stltopo;

namespace {

struct Built {
  Mesh mesh;
  Topology topo;
};

Built build(const gen::Soup& s, double tolerance = 0) {
  Built b;
  Status st = gen::read(gen::binary(s), b.mesh);
  EXPECT_TRUE(st.ok()) << st.message;
  TopologyOptions o;
  o.tolerance = tolerance;
  st = buildTopology(b.mesh, b.topo, o);
  EXPECT_TRUE(st.ok()) << st.message;
  Status v = validate(b.mesh, b.topo);
  EXPECT_TRUE(v.ok()) << v.message;
  // Every generated case also checks the report-only topology (prevAndFace = false).
  EXPECT_EQ(gen::leanTopologyDifference(b.mesh, b.topo, tolerance), "");
  return b;
}

std::vector<uint32_t> holeSizes(const Topology& t) {
  std::vector<uint32_t> out;
  for (uint32_t l = 0; l < t.nLoops(); ++l)
    if (!t.loopIsSeam[l]) out.push_back(t.loopOffsets[l + 1] - t.loopOffsets[l]);
  return out;
}

// The defining properties of the navigation operators, on every half-edge.
void checkNavigation(const Topology& t) {
  for (uint32_t e = 0; e < t.nHalfedges(); ++e) {
    ASSERT_EQ(sym(sym(e)), e);
    ASSERT_EQ(org(t, oNext(t, e)), org(t, e));
    ASSERT_EQ(org(t, oPrev(t, e)), org(t, e));
    ASSERT_EQ(lFace(t, lNext(t, e)), lFace(t, e));
    ASSERT_EQ(lFace(t, lPrev(t, e)), lFace(t, e));
    ASSERT_EQ(dst(t, dNext(t, e)), dst(t, e));
    ASSERT_EQ(dst(t, dPrev(t, e)), dst(t, e));
    ASSERT_EQ(rFace(t, rNext(t, e)), rFace(t, e));
    ASSERT_EQ(rFace(t, rPrev(t, e)), rFace(t, e));
    ASSERT_EQ(oPrev(t, oNext(t, e)), e);
    ASSERT_EQ(oNext(t, oPrev(t, e)), e);
    ASSERT_EQ(lPrev(t, lNext(t, e)), e);
    ASSERT_EQ(dPrev(t, dNext(t, e)), e);
    ASSERT_EQ(dNext(t, dPrev(t, e)), e);
    ASSERT_EQ(rPrev(t, rNext(t, e)), e);
    ASSERT_EQ(rNext(t, rPrev(t, e)), e);
    ASSERT_EQ(vnext(t, e), oPrev(t, e));
    ASSERT_EQ(dst(t, e), org(t, lNext(t, e)));
  }
}

// The mesh vertex id of a position (mesh ids follow first appearance, not the soup's).
uint32_t vid(const Mesh& m, std::array<float, 3> p) {
  for (uint32_t v = 0; v < m.nVertices(); ++v)
    if (m.positions[3 * v] == p[0] && m.positions[3 * v + 1] == p[1] && m.positions[3 * v + 2] == p[2]) return v;
  ADD_FAILURE() << "no such vertex";
  return kInvalid;
}

gen::Soup openCube() {
  gen::Soup s = gen::cube();
  s.f.erase(s.f.begin() + 2, s.f.begin() + 4);  // the top (+z) side
  return s;
}

}  // namespace

TEST(Topology, ClosedCubeIsWatertightGenusZero) {
  Built b = build(gen::cube());
  const Topology& t = b.topo;
  EXPECT_EQ(t.nEdges, 18u);
  EXPECT_EQ(t.nHalfedges(), 36u);
  EXPECT_EQ(t.nLoops(), 0u);
  EXPECT_EQ(t.nShells, 1u);
  EXPECT_EQ(t.nNonManifoldVertices, 0u);
  std::string j = infoJson("cube", b.mesh, &t);
  EXPECT_NE(j.find("\"eulerCharacteristic\":2,\"genus\":0,\"watertight\":true,\"manifold\":true"), std::string::npos)
      << j;
  checkNavigation(t);
}

TEST(Topology, HalfEdgesArePairedInFirstMetOrder) {
  Built b = build(gen::cube());
  const Topology& t = b.topo;
  // Triangle 0 = (0,2,3): its sides open pairs 0,1,2 in corner order.
  EXPECT_EQ(t.triangleHalfedge[0], 0u);
  EXPECT_EQ(t.next[0], 2u);
  EXPECT_EQ(t.next[2], 4u);
  EXPECT_EQ(t.vert[0], b.mesh.triangles[0]);
  EXPECT_EQ(t.vert[1], b.mesh.triangles[1]);  // twin starts where the side ends
  // Triangle 1 = (0,3,1): side 0->3 is the twin of triangle 0's side 3->0 (half-edge 4).
  EXPECT_EQ(t.triangleHalfedge[1], 5u);
}

TEST(Topology, OpenCubeHasOneHoleOfFourEdges) {
  Built b = build(openCube());
  const Topology& t = b.topo;
  EXPECT_EQ(t.nHoles, 1u);
  EXPECT_EQ(t.nSeams, 0u);
  EXPECT_EQ(t.nBoundaryEdges, 4u);
  EXPECT_EQ(holeSizes(t), std::vector<uint32_t>{4});
  EXPECT_NEAR(t.loopPerimeter[0], 4.0, 1e-12);
  EXPECT_EQ(t.face[t.loopHalfedge[0]], 10u);  // the hole face comes after the 10 triangles
  // Boundary vertices point at the boundary half-edge that leaves them.
  for (std::array<float, 3> p : {std::array<float, 3>{0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}})
    EXPECT_GE(t.face[t.vertexHalfedge[vid(b.mesh, p)]], 10u);
  // Walking around a boundary vertex from its hole half-edge visits its whole fan:
  // corner (0,0,1) has 2 triangles left, so 2 triangle half-edges + 1 hole half-edge.
  uint32_t v = vid(b.mesh, {0, 0, 1}), n = 0;
  forEachOutgoing(t, t.vertexHalfedge[v], [&](uint32_t e) {
    EXPECT_EQ(org(t, e), v);
    ++n;
  });
  EXPECT_EQ(n, 3u);
  checkNavigation(t);
}

TEST(Topology, TorusHasGenusOne) {
  Built b = build(gen::torus(16, 8));
  EXPECT_EQ(b.topo.nEdges, 16u * 8 * 3);
  std::string j = infoJson("t", b.mesh, &b.topo);
  EXPECT_NE(j.find("\"eulerCharacteristic\":0,\"genus\":1,\"watertight\":true"), std::string::npos) << j;
  checkNavigation(b.topo);
}

TEST(Topology, TorusWithTwoSeparateHoles) {
  Built b = build(gen::torus(16, 8, {0, 8 * 8 + 4}));
  EXPECT_EQ(b.topo.nHoles, 2u);
  EXPECT_EQ(holeSizes(b.topo), (std::vector<uint32_t>{4, 4}));
  EXPECT_EQ(b.topo.nNonManifoldVertices, 0u);
  checkNavigation(b.topo);
}

TEST(Topology, TwoHolesTouchingAtAVertexFormOneLoopUnderTheFanRule) {
  // Quads (2,2) and (3,3) share only the corner vertex (3,3).
  gen::Soup s = gen::torus(16, 8, {2 * 8 + 2, 3 * 8 + 3});
  Built b = build(s);
  const Topology& t = b.topo;
  EXPECT_EQ(t.nBoundaryEdges, 8u);
  EXPECT_EQ(t.nHoles, 1u);
  EXPECT_EQ(holeSizes(t), std::vector<uint32_t>{8});
  EXPECT_EQ(t.nNonManifoldVertices, 1u);
  uint32_t pinch = vid(b.mesh, s.v[3 * 8 + 3]);
  EXPECT_EQ(t.vertexNonManifold[pinch], 1u);
  uint32_t visits = 0;
  forEachFaceHalfedge(t, t.loopHalfedge[0], [&](uint32_t e) { visits += org(t, e) == pinch; });
  EXPECT_EQ(visits, 2u);
  checkNavigation(t);
}

TEST(Topology, TwoCubesSharingAnEdgeStayClosed) {
  gen::Soup s = gen::cube();
  gen::append(s, gen::cube(1, 1, 0));
  Built b = build(s);
  const Topology& t = b.topo;
  EXPECT_EQ(b.mesh.nVertices(), 14u);
  EXPECT_EQ(t.nNonManifoldEdges, 1u);
  EXPECT_EQ(t.nLoops(), 0u);  // opposite sides pair up within each cube
  EXPECT_EQ(t.nBoundaryEdges, 0u);
  EXPECT_EQ(t.nNonManifoldVertices, 2u);
  EXPECT_EQ(t.nShells, 1u);
  std::string j = infoJson("c", b.mesh, &t);
  EXPECT_NE(j.find("\"watertight\":false,\"manifold\":false"), std::string::npos) << j;
  checkNavigation(t);
}

TEST(Topology, TwoCubesTouchingAtACorner) {
  gen::Soup s = gen::cube();
  gen::append(s, gen::cube(1, 1, 1));
  Built b = build(s);
  const Topology& t = b.topo;
  EXPECT_EQ(b.mesh.nVertices(), 15u);
  EXPECT_EQ(t.nNonManifoldEdges, 0u);
  EXPECT_EQ(t.nNonManifoldVertices, 1u);
  EXPECT_EQ(t.vertexNonManifold[vid(b.mesh, {1, 1, 1})], 1u);
  EXPECT_EQ(t.nShells, 2u);
  std::string j = infoJson("c", b.mesh, &t);
  // chi = 15 - 36 + 24 = 3; watertight (no bad edges) but not manifold: a pinched closed mesh
  // is no surface, so it has no genus ((4 - 3) / 2 = 0.5 would mislead).
  EXPECT_NE(j.find("\"eulerCharacteristic\":3,\"genus\":null,\"watertight\":true,\"manifold\":false"),
            std::string::npos)
      << j;
}

TEST(Topology, FlippedTriangleGivesThreeInconsistentEdgesAndSeamsNotHoles) {
  gen::Soup s = gen::cube();
  std::swap(s.f[5][1], s.f[5][2]);
  Built b = build(s);
  const Topology& t = b.topo;
  EXPECT_EQ(t.nInconsistentEdges, 3u);
  EXPECT_EQ(t.nBoundaryEdges, 0u);
  EXPECT_EQ(t.nHoles, 0u);
  // The flipped triangle's cut sides close one 3-loop; the cube's opening another.
  EXPECT_EQ(t.nSeams, 2u);
  uint32_t cutPairs = 0;
  for (uint8_t k : t.pairKind) cutPairs += k == uint8_t(EdgeKind::Inconsistent);
  EXPECT_EQ(cutPairs, 6u);
  checkNavigation(t);
}

TEST(Topology, DegenerateTriangleIsFlaggedAndLeftOut) {
  gen::Soup s = gen::cube();
  s.f.push_back({0, 1, 1});
  Built b = build(s);
  const Topology& t = b.topo;
  EXPECT_EQ(t.nDegenerate, 1u);
  EXPECT_EQ(t.triangleDegenerate[12], 1u);
  EXPECT_EQ(t.triangleHalfedge[12], kInvalid);
  EXPECT_EQ(t.nEdges, 18u);
  std::string j = infoJson("c", b.mesh, &t);
  EXPECT_NE(j.find("\"degenerateTriangles\":1"), std::string::npos);
  EXPECT_NE(j.find("\"watertight\":true"), std::string::npos);
}

TEST(Topology, NonManifoldEdgeWithALeftoverSideMakesASeam) {
  gen::Soup s = gen::cube();
  s.v.push_back({0.5f, 0.5f, 3});
  s.f.push_back({4, 5, 8});  // a fin on the top edge 4-5, same direction as a cube side
  Built b = build(s);
  const Topology& t = b.topo;
  EXPECT_EQ(t.nNonManifoldEdges, 1u);
  EXPECT_EQ(t.nBoundaryEdges, 2u);
  EXPECT_EQ(t.nHoles, 0u);
  EXPECT_EQ(t.nSeams, 1u);
  checkNavigation(t);
}

TEST(Topology, ShuffledTrianglesGiveTheSameCounts) {
  gen::Soup s = gen::torus(12, 6, {5, 40});
  Built a = build(s);
  std::mt19937 rng(7);
  std::shuffle(s.f.begin(), s.f.end(), rng);
  Built b = build(s);
  std::string ja = infoJson("x", a.mesh, &a.topo), jb = infoJson("x", b.mesh, &b.topo);
  auto strip = [](const std::string& j) { return j.substr(j.find("\"edges\"")); };
  EXPECT_EQ(strip(ja), strip(jb));
  EXPECT_EQ(a.mesh.nVertices(), b.mesh.nVertices());
}

TEST(Topology, SoupOfSeparateTriangles) {
  gen::Soup s;
  for (int i = 0; i < 5; ++i) {
    float x = float(i * 3);
    uint32_t base = uint32_t(s.v.size());
    s.v.push_back({x, 0, 0});
    s.v.push_back({x + 1, 0, 0});
    s.v.push_back({x, 1, 0});
    s.f.push_back({base, base + 1, base + 2});
  }
  Built b = build(s);
  EXPECT_EQ(b.topo.nHoles, 5u);
  EXPECT_EQ(b.topo.nShells, 5u);
  EXPECT_EQ(holeSizes(b.topo), (std::vector<uint32_t>{3, 3, 3, 3, 3}));
}

TEST(Topology, EmptyMeshIsNotWatertight) {
  Mesh m;
  ASSERT_TRUE(gen::read("solid e\nendsolid e\n", m).ok());
  Topology t;
  ASSERT_TRUE(buildTopology(m, t).ok());
  EXPECT_TRUE(validate(m, t).ok());
  std::string j = infoJson("e", m, &t);
  EXPECT_NE(j.find("\"bbox\":null"), std::string::npos);
  EXPECT_NE(j.find("\"genus\":null,\"watertight\":false,\"manifold\":true"), std::string::npos) << j;
}

// The tolerance weld's rule, by brute force: vertices in id order, each joins the lowest-id
// representative within tol (exactly: pred::withinDistance, checked against integers below)
// or becomes one. The
// grid only makes it fast; clouds with points on and near cell sides (multiples of tol, of
// 4·tol, a float step off them), clusters and far coordinates must give the same answer.
TEST(Topology, ToleranceWeldEqualsTheBruteForceRule) {
  std::mt19937 rng(2024);
  for (int round = 0; round < 60; ++round) {
    double tol = std::array<double, 4>{0.25, 1e-3, 0.1, 3}[round % 4];
    gen::Soup s;
    std::uniform_int_distribution<int> grid(-3, 3);  // few bases: many points within tol of each other
    std::uniform_int_distribution<int> pick(0, 5);
    auto coord = [&]() -> float {
      double base = grid(rng) * tol * std::array<double, 4>{1, 4, 0.5, 2}[pick(rng) % 4];
      switch (pick(rng)) {
        case 0: return float(base);
        case 1: return std::nextafter(float(base), 1e30f);
        case 2: return std::nextafter(float(base), -1e30f);
        case 3: return float(base + tol * std::uniform_real_distribution<double>(-1.2, 1.2)(rng));
        case 4: return float(base * 1e7);  // far out in units of tol
        default: return float(base + tol * 0.5);
      }
    };
    size_t nPoints = 30 + round * 7;
    for (size_t i = 0; i < nPoints; ++i) s.v.push_back({coord(), coord(), coord()});
    for (size_t i = 0; i + 2 < nPoints; i += 3) s.f.push_back({uint32_t(i), uint32_t(i + 1), uint32_t(i + 2)});
    Mesh mesh;
    ASSERT_TRUE(gen::read(gen::binary(s), mesh).ok());
    Topology topo;
    TopologyOptions o;
    o.tolerance = tol;
    ASSERT_TRUE(buildTopology(mesh, topo, o).ok());
    const float* p = mesh.positions.data();
    std::vector<uint32_t> rep(mesh.nVertices());
    for (uint32_t v = 0; v < mesh.nVertices(); ++v) {
      rep[v] = v;
      for (uint32_t r = 0; r < v; ++r) {
        if (rep[r] != r) continue;
        if (pred::withinDistance(p + 3 * size_t(r), p + 3 * size_t(v), tol, tol * tol)) {
          rep[v] = r;
          break;
        }
      }
    }
    for (uint32_t v = 0; v < mesh.nVertices(); ++v)
      ASSERT_EQ(topo.vertexWeld[v], rep[v]) << "round " << round << " vertex " << v;
  }
}

// sign(|p - q|^2 - tol^2) in integers, for coordinates that are multiples of 2^-20 of at most
// 2^30 in magnitude (integers of at most 2^50 when scaled by 2^20; the squares' sum below 2^105).
static int exactDistanceSign(const float* p, const float* q, double tol) {
  unsigned __int128 s = 0;
  for (int k = 0; k < 3; ++k) {
    const int64_t d = int64_t(std::ldexp(double(p[k]), 20)) - int64_t(std::ldexp(double(q[k]), 20));
    s += (unsigned __int128)(__int128(d) * d);
  }
  int e;
  const double f = std::frexp(tol, &e);  // tol * 2^20 = m * 2^(k2 / 2), m < 2^53
  const uint64_t m = uint64_t(std::ldexp(f, 53));
  const int k2 = 2 * (e - 53 + 20);
  const unsigned __int128 m2 = (unsigned __int128)m * m;  // below 2^106
  auto bits = [](unsigned __int128 x) {
    int n = 0;
    for (; x; x >>= 1) ++n;
    return n;
  };
  if (s == 0) return -1;
  const int bs = bits(s), bm = bits(m2) + k2;
  if (bs != bm) return bs < bm ? -1 : 1;
  const unsigned __int128 a = k2 < 0 ? s << -k2 : s, b = k2 < 0 ? m2 : m2 << k2;
  return a < b ? -1 : a > b ? 1 : 0;
}

// The weld's distance test is exact: against integers, on random points and on tolerances
// within a few ulps of their distance, where the sum of squares in double rounds either way.
TEST(Topology, ToleranceWeldDistanceIsExact) {
  std::mt19937_64 rng(7);
  auto coord = [&]() {
    const int64_t k = int64_t(rng() % (uint64_t(1) << 40)) - (int64_t(1) << 39);
    // 16 to 40 significant bits, rounded to a float, times 2^-20 .. 2^-9: at most 2^30, a
    // multiple of 2^-20 (a float's 24 bits from an integer of at most 40, shifted)
    return float(std::ldexp(double(k >> int(rng() % 24)), -20 + int(rng() % 12)));
  };
  int ties = 0, wrongInDouble = 0;
  for (int i = 0; i < 200000; ++i) {
    float p[3], q[3];
    for (int k = 0; k < 3; ++k) {
      p[k] = coord();
      q[k] = rng() % 4 == 0 ? p[k] : coord();  // often on one axis or in one plane
    }
    const double dx = double(p[0]) - q[0], dy = double(p[1]) - q[1], dz = double(p[2]) - q[2];
    double tol = std::sqrt(dx * dx + dy * dy + dz * dz);
    if (!(tol > 0)) continue;
    for (int step = int(rng() % 5) - 2; step != 0; step += step > 0 ? -1 : 1)
      tol = std::nextafter(tol, step > 0 ? 1e300 : 0.0);
    const int want = exactDistanceSign(p, q, tol);
    ties += want == 0;
    wrongInDouble += (dx * dx + dy * dy + dz * dz <= tol * tol) != (want <= 0);
    ASSERT_EQ(pred::withinDistance(p, q, tol, tol * tol), want <= 0) << i;
    ASSERT_EQ(pred::distance2Exact(p, q, tol), want) << i;
  }
  EXPECT_GT(ties, 0);
  EXPECT_GT(wrongInDouble, 0);  // the cases a sum of squares in double gets wrong
}

// A point just beyond tol does not weld, though the sum of squares in double says it is
// within: (1, 2^-30, 0) is sqrt(1 + 2^-60) from the origin, and 1 + 2^-60 rounds to 1.
TEST(Topology, ToleranceWeldKeepsAPointJustBeyondTheTolerance) {
  for (float y : {std::ldexp(1.0f, -30), 0.0f}) {
    gen::Soup s;
    s.v = {{0, 0, 0}, {5, 0, 0}, {0, 5, 0}, {1, y, 0}, {1, 5, 5}, {9, 9, 9}};
    s.f = {{0, 1, 2}, {3, 4, 5}};
    Built b = build(s, 1.0);
    EXPECT_EQ(b.topo.nWeldedVertices, y == 0 ? 5u : 6u) << y;  // (1, 0, 0) is exactly 1 away
  }
}

TEST(Topology, ToleranceWeldClosesCracksWithoutMovingPositions) {
  gen::Soup s = gen::cube();
  // Split vertex 7 into a copy 1e-6 away used by the last triangle that touches it.
  s.v.push_back({1.000001f, 1, 1});
  for (auto it = s.f.rbegin(); it != s.f.rend(); ++it) {
    bool done = false;
    for (auto& c : *it)
      if (c == 7) {
        c = 8;
        done = true;
      }
    if (done) break;
  }
  Built exact = build(s);
  EXPECT_GT(exact.topo.nBoundaryEdges, 0u);
  Built welded = build(s, 1e-5);
  EXPECT_EQ(welded.topo.nBoundaryEdges, 0u);
  EXPECT_EQ(welded.topo.vertexWeld[8], vid(welded.mesh, {1, 1, 1}));
  EXPECT_EQ(welded.mesh.positions[3 * 8], 1.000001f);
  EXPECT_EQ(welded.mesh.nVertices(), 9u);
  // The report counts positions as `vertices` and the weld's representatives apart.
  EXPECT_EQ(welded.topo.nWeldedVertices, 8u);
  std::string j = infoJson("c", welded.mesh, &welded.topo);
  EXPECT_NE(j.find("\"vertices\":9,\"weldedVertices\":8,"), std::string::npos) << j;
  EXPECT_NE(infoText("c", welded.mesh, &welded.topo).find("9 vertices (8 after the tolerance weld)"),
            std::string::npos);
  // The exact weld prints no weldedVertices.
  EXPECT_EQ(exact.topo.nWeldedVertices, 9u);
  EXPECT_EQ(infoJson("c", exact.mesh, &exact.topo).find("weldedVertices"), std::string::npos);
}

TEST(Validate, DetectsABrokenInvariant) {
  Built b = build(gen::cube());
  std::swap(b.topo.next[0], b.topo.next[2]);
  Status s = validate(b.mesh, b.topo);
  EXPECT_EQ(s.code, Code::Invalid);
  EXPECT_NE(s.element, kInvalid);
}

// Each check of validate() on its own: one array entry or count of a valid topology is
// corrupted, and validate() must name that check. The meshes: a cube with a flipped
// triangle (seams), an open cube (a hole), a grid with two holes touching at a vertex
// (a non-manifold vertex) and two cubes sharing an edge (a non-manifold edge).
namespace {

struct Corruption {
  const char* name;
  Built (*mesh)();
  void (*corrupt)(Topology&);
  const char* message;
};

Built openCubeBuilt() { return build(openCube()); }
Built flippedCube() {
  gen::Soup s = gen::cube();
  std::swap(s.f[5][1], s.f[5][2]);
  return build(s);
}
Built cubesSharingAnEdge() {
  gen::Soup s = gen::cube();
  gen::append(s, gen::cube(1, 1, 0));
  return build(s);
}
Built cubesSharingACorner() {
  gen::Soup s = gen::cube();
  gen::append(s, gen::cube(1, 1, 1));
  return build(s);
}
Built cubeWithDegenerate() {
  gen::Soup s = gen::cube();
  s.f.push_back({0, 0, 1});
  return build(s);
}

// The pair whose kind is `k` (the first one).
uint32_t pairOfKind(const Topology& t, EdgeKind k) {
  for (uint32_t p = 0; p < t.pairKind.size(); ++p)
    if (t.pairKind[p] == uint8_t(k)) return p;
  ADD_FAILURE() << "no pair of that kind";
  return 0;
}

}  // namespace

TEST(Validate, EachCheckCatchesItsCorruption) {
  const Corruption cases[] = {
      {"pairKind interior->boundary", +[] { return build(gen::cube()); },
       [](Topology& t) { t.pairKind[0] = uint8_t(EdgeKind::Boundary); }, "pairKind differs"},
      {"pairKind boundary->inconsistent", openCubeBuilt,
       [](Topology& t) { t.pairKind[pairOfKind(t, EdgeKind::Boundary)] = uint8_t(EdgeKind::Inconsistent); },
       "pairKind differs"},
      {"pairKind non-manifold->interior", cubesSharingAnEdge,
       [](Topology& t) { t.pairKind[pairOfKind(t, EdgeKind::NonManifold)] = uint8_t(EdgeKind::Interior); },
       "pairKind differs"},
      {"loopIsSeam hole->seam", openCubeBuilt, [](Topology& t) { t.loopIsSeam[0] = 1; }, "loopIsSeam differs"},
      {"loopIsSeam seam->hole", flippedCube, [](Topology& t) { t.loopIsSeam[0] = 0; }, "loopIsSeam differs"},
      {"vertexNonManifold set", openCubeBuilt, [](Topology& t) { t.vertexNonManifold[0] = 1; },
       "vertexNonManifold differs"},
      {"vertexNonManifold cleared", cubesSharingACorner,
       [](Topology& t) {
         for (auto& f : t.vertexNonManifold) f = 0;
       },
       "vertexNonManifold differs"},
      {"nNonManifoldVertices", cubesSharingACorner, [](Topology& t) { t.nNonManifoldVertices = 0; },
       "non-manifold-vertex count differs"},
      {"nEdges", openCubeBuilt, [](Topology& t) { ++t.nEdges; }, "edge count differs"},
      {"nBoundaryEdges", openCubeBuilt, [](Topology& t) { --t.nBoundaryEdges; }, "boundary-edge count differs"},
      {"nInconsistentEdges", flippedCube, [](Topology& t) { t.nInconsistentEdges = 0; },
       "inconsistent-edge count differs"},
      {"nNonManifoldEdges", cubesSharingAnEdge, [](Topology& t) { t.nNonManifoldEdges = 2; },
       "non-manifold-edge count differs"},
      {"nHoles/nSeams swapped", flippedCube, [](Topology& t) { std::swap(t.nHoles, t.nSeams); },
       "hole or seam count differs"},
      {"nUsedVertices", openCubeBuilt, [](Topology& t) { ++t.nUsedVertices; }, "used-vertex count differs"},
      {"nDegenerate", cubeWithDegenerate, [](Topology& t) { t.nDegenerate = 0; }, "degenerate-triangle count differs"},
      {"nWeldedVertices", openCubeBuilt, [](Topology& t) { --t.nWeldedVertices; }, "welded-vertex count differs"},
      {"nShells", cubesSharingACorner, [](Topology& t) { t.nShells = 1; }, "shell count differs"},
      {"nShells of one cube", openCubeBuilt, [](Topology& t) { t.nShells = 2; }, "shell count differs"},
  };
  for (const Corruption& c : cases) {
    SCOPED_TRACE(c.name);
    Built b = c.mesh();
    ASSERT_TRUE(validate(b.mesh, b.topo).ok());
    c.corrupt(b.topo);
    Status s = validate(b.mesh, b.topo);
    EXPECT_EQ(s.code, Code::Invalid);
    EXPECT_NE(s.message.find(c.message), std::string::npos) << s.message;
  }
}

TEST(Report, JsonEscapesAndNumbers) {
  EXPECT_EQ(jsonString("a\"b\\c\n\x01"), "\"a\\\"b\\\\c\\n\\u0001\"");
  EXPECT_EQ(jsonString("\xff"
                       "ok"),
            "\"\xEF\xBF\xBDok\"");
  Mesh m;
  ASSERT_TRUE(gen::read(gen::binary(gen::cube(0, 0, 0, 0.1f)), m).ok());
  std::string j = infoJson("f", m, nullptr);
  EXPECT_NE(j.find("\"max\":[0.1,0.1,0.1]"), std::string::npos) << j;
  EXPECT_EQ(j.find("\"edges\""), std::string::npos);
  Status e;
  e.code = Code::Truncated;
  e.message = "truncated: x";
  e.offset = 7;
  e.triangle = 2;
  EXPECT_EQ(
      errorJson("f", e),
      "{\"file\":\"f\",\"error\":{\"code\":\"truncated\",\"message\":\"truncated: x\",\"offset\":7,\"triangle\":2}}");
}
