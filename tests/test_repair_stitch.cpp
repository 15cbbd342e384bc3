// Repair steps stitch and split-nonmanifold (src/repair/stitch.cpp, split_nonmanifold.cpp)
// and the edits they use (EditableMesh::mergeVertices, splitEdgeAt, splitVertex): generated
// cracks, T-junctions and non-manifold meshes, refused edits that change nothing, and
// stitch on every fixture with several tolerances, never making a figure worse.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <random>
#include <set>

#include "edit_check.h"
#include "predicates.h"  // private (src/): the tolerance tests, checked below
#include "repair/steps.h"
#include "stl_gen.h"
#include "stltopo/edit.h"

using namespace stltopo;
using editcheck::Snapshot;

namespace {

void makeEditable(const gen::Soup& s, EditableMesh& em) {
  Mesh m;
  Status st = gen::read(gen::binary(s), m);
  ASSERT_TRUE(st.ok()) << st.message;
  st = em.init(m);
  ASSERT_TRUE(st.ok()) << st.message;
}

// The vertex at (x, y, z) (the reader numbers vertices by first use, not as the soup does).
uint32_t vertexAt(EditableMesh& em, float x, float y, float z) {
  const float* P = em.positions().data();
  for (uint32_t v = 0; v < em.nVertices(); ++v)
    if (em.vertexAlive(v) && P[3 * v] == x && P[3 * v + 1] == y && P[3 * v + 2] == z) return v;
  ADD_FAILURE() << "no vertex at " << x << " " << y << " " << z;
  return kInvalid;
}

// The rim vertices of cubeHalves: lower (z = 0.5) or upper (z = 0.5 + gap), in the order
// (0,0), (1,0), (1,1), (0,1).
std::array<uint32_t, 4> rim(EditableMesh& em, float z) {
  return {vertexAt(em, 0, 0, z), vertexAt(em, 1, 0, z), vertexAt(em, 1, 1, z), vertexAt(em, 0, 1, z)};
}

// A cube [0,1]^3 cut at z = 0.5 into two open boxes, the upper one lifted by `gap`.
gen::Soup cubeHalves(float gap) {
  gen::Soup s;
  const float zs[4] = {0, 0.5f, 0.5f + gap, 1 + gap};
  for (int layer = 0; layer < 4; ++layer)
    for (int i = 0; i < 4; ++i) {
      const float x[4] = {0, 1, 1, 0}, y[4] = {0, 0, 1, 1};
      s.v.push_back({x[i], y[i], zs[layer]});
    }
  auto id = [](int layer, int i) { return uint32_t(4 * layer + (i & 3)); };
  // Bottom (outward: -z) and top (+z).
  s.f.push_back({id(0, 0), id(0, 2), id(0, 1)});
  s.f.push_back({id(0, 0), id(0, 3), id(0, 2)});
  s.f.push_back({id(3, 0), id(3, 1), id(3, 2)});
  s.f.push_back({id(3, 0), id(3, 2), id(3, 3)});
  // Walls of each half (counter-clockwise seen from outside).
  for (int half = 0; half < 2; ++half) {
    int lo = 2 * half, hi = 2 * half + 1;
    for (int i = 0; i < 4; ++i) {
      s.f.push_back({id(lo, i), id(lo, i + 1), id(hi, i + 1)});
      s.f.push_back({id(lo, i), id(hi, i + 1), id(hi, i)});
    }
  }
  return s;
}

// cubeHalves whose upper rim has a vertex more in the middle of each side: the two rims
// do not match vertex for vertex (a crack between different tessellations).
gen::Soup cubeHalvesMismatched(float gap) {
  gen::Soup s = cubeHalves(gap);
  s.f.resize(12);  // bottom, top and the lower walls; the upper walls are made again
  const float x[4] = {0, 1, 1, 0}, y[4] = {0, 0, 1, 1};
  for (int i = 0; i < 4; ++i) {
    const int j = (i + 1) % 4;
    const uint32_t lo_i = uint32_t(8 + i), lo_j = uint32_t(8 + j), hi_i = uint32_t(12 + i), hi_j = uint32_t(12 + j);
    const uint32_t m = uint32_t(s.v.size());
    s.v.push_back({0.5f * (x[i] + x[j]), 0.5f * (y[i] + y[j]), 0.5f + gap});
    s.f.push_back({lo_i, m, hi_i});
    s.f.push_back({m, lo_j, hi_j});
    s.f.push_back({m, hi_j, hi_i});
  }
  return s;
}

// Two squares in z = 0 on either side of y = 0: the upper one is two triangles meeting at
// (1, 0), the lower one a single triangle whose edge (2,0)-(0,0) passes through (1, 0).
gen::Soup tJunction() {
  gen::Soup s;
  s.v = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0.5f, 1, 0}, {1.5f, 1, 0}, {1, -1, 0}};
  s.f = {{0, 1, 3}, {1, 2, 4}, {1, 4, 3}, {0, 5, 2}};
  return s;
}

uint32_t nSkipped(const RepairStepPlan& p) {
  uint32_t n = 0;
  for (const RepairItem& i : p.items) n += i.skipped ? 1 : 0;
  return n;
}
uint32_t nDone(const RepairStepPlan& p) { return uint32_t(p.items.size()) - nSkipped(p); }

uint64_t keyOf2(uint32_t a, uint32_t b) { return a < b ? (uint64_t(a) << 32) | b : (uint64_t(b) << 32) | a; }

// Runs one step on em and returns its plan entry.
Status runStep(RepairStepKind kind, EditableMesh& em, const RepairOptions& o, RepairStepPlan& plan) {
  plan = RepairStepPlan{};
  plan.kind = kind;
  repair_detail::StepContext ctx{em, o, plan};
  return kind == RepairStepKind::Stitch ? repair_detail::runStitch(ctx) : repair_detail::runSplitNonManifold(ctx);
}

struct Counts {
  uint32_t boundary, nonManifoldEdges, inconsistent, nonManifoldVertices;
};
Counts counts(EditableMesh& em) {
  const EditStats& s = em.stats();
  return {s.boundaryEdges, s.nonManifoldEdges, s.inconsistentEdges, s.nonManifoldVertices};
}
void expectNotWorse(const Counts& before, const Counts& after, const std::string& what) {
  EXPECT_LE(after.boundary + after.nonManifoldEdges + after.inconsistent,
            before.boundary + before.nonManifoldEdges + before.inconsistent)
      << what;
  EXPECT_LE(after.nonManifoldEdges, before.nonManifoldEdges) << what;
  EXPECT_LE(after.inconsistent, before.inconsistent) << what;
  EXPECT_LE(after.nonManifoldVertices, before.nonManifoldVertices) << what;
}

// The positions of the live triangles' corners, as a multiset per triangle (the split
// keeps every corner where it was).
std::multiset<std::array<float, 9>> cornerPositions(EditableMesh& em) {
  std::multiset<std::array<float, 9>> out;
  const float* P = em.positions().data();
  for (uint32_t t = 0; t < em.nTriangles(); ++t) {
    if (!em.triangleAlive(t)) continue;
    std::array<float, 9> a;
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k) a[3 * c + k] = P[3 * size_t(em.triangles()[3 * t + c]) + k];
    out.insert(a);
  }
  return out;
}

}  // namespace

// ------------------------------------------------------------------------ mergeVertices

TEST(MergeVertices, ZipsTwoOpenBoxesIntoAWatertightCube) {
  EditableMesh em;
  makeEditable(cubeHalves(0.001f), em);
  ASSERT_EQ(em.stats().boundaryEdges, 8u);
  const auto keep = rim(em, 0.5f), gone = rim(em, 0.501f);
  Status s = em.mergeVertices(keep.data(), gone.data(), 4);
  ASSERT_TRUE(s.ok()) << s.message;
  const EditStats& st = em.stats();
  EXPECT_TRUE(st.watertight);
  EXPECT_TRUE(st.manifold);
  EXPECT_EQ(st.eulerCharacteristic, 2);
  EXPECT_EQ(st.vertices, 12u);
  for (uint32_t g : gone) EXPECT_FALSE(em.vertexAlive(g));
  // The kept vertices stayed where they were.
  for (uint32_t k : keep) EXPECT_EQ(em.positions()[3 * k + 2], 0.5f);
  EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
}

TEST(MergeVertices, ASinglePairThatWouldPinchIsRefusedAndChangesNothing) {
  EditableMesh em;
  makeEditable(cubeHalves(0.001f), em);
  const auto lower = rim(em, 0.5f), upper = rim(em, 0.501f);
  Snapshot before(em);
  Status s = em.mergeVertices(lower[0], upper[0]);
  EXPECT_EQ(s.code, Code::EditRefused);
  EXPECT_NE(s.message.find("non-manifold"), std::string::npos) << s.message;
  EXPECT_TRUE(Snapshot(em) == before);
  // Allowed, the pinch is made: one non-manifold vertex, no edge joins.
  s = em.mergeVertices(lower[0], upper[0], true);
  ASSERT_TRUE(s.ok()) << s.message;
  EXPECT_EQ(em.stats().nonManifoldVertices, 1u);
  EXPECT_EQ(em.stats().boundaryEdges, 8u);
  EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
  // The next pair along the rims joins an edge and removes the pinch.
  s = em.mergeVertices(lower[1], upper[1]);
  ASSERT_TRUE(s.ok()) << s.message;
  EXPECT_EQ(em.stats().nonManifoldVertices, 0u);
  EXPECT_EQ(em.stats().boundaryEdges, 6u);
  EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
}

TEST(MergeVertices, RefusalsChangeNothing) {
  EditableMesh em;
  makeEditable(cubeHalves(0.001f), em);
  const auto lower = rim(em, 0.5f), upper = rim(em, 0.501f);
  Snapshot before(em);
  // Two corners of one triangle.
  Status s = em.mergeVertices(lower[0], lower[1]);
  EXPECT_EQ(s.code, Code::EditRefused);
  EXPECT_NE(s.message.find("repeated corner"), std::string::npos) << s.message;
  EXPECT_TRUE(Snapshot(em) == before);
  // The rims zipped mirrored (the square's diagonal through (0,0) and (1,1)): the rim
  // edges would meet running the same way.
  const uint32_t mirrored[4] = {upper[0], upper[3], upper[2], upper[1]};
  s = em.mergeVertices(lower.data(), mirrored, 4);
  EXPECT_EQ(s.code, Code::EditRefused) << s.message;
  EXPECT_NE(s.message.find("same way"), std::string::npos) << s.message;
  EXPECT_TRUE(Snapshot(em) == before);
  // Bad arguments.
  const uint32_t twice[2] = {lower[0], lower[0]}, other[2] = {upper[0], upper[1]};
  EXPECT_EQ(em.mergeVertices(twice, other, 2).code, Code::InvalidArgument);
  EXPECT_EQ(em.mergeVertices(lower[0], lower[0]).code, Code::InvalidArgument);
  EXPECT_EQ(em.mergeVertices(lower[0], 999).code, Code::InvalidArgument);
  EXPECT_EQ(em.mergeVertices(nullptr, nullptr, 0).code, Code::InvalidArgument);
  EXPECT_TRUE(Snapshot(em) == before);
}

TEST(MergeVertices, RefusesAFoldOver) {
  // Two triangles apart in z = 0; moving the apex of the first across its base would
  // turn its normal around.
  gen::Soup s;
  s.v = {{0, 0, 0}, {1, 0, 0}, {0.5f, 1, 0}, {3, 0, 0}, {4, 0, 0}, {0.5f, -1, 0}};
  s.f = {{0, 1, 2}, {3, 5, 4}};
  EditableMesh em;
  makeEditable(s, em);
  Snapshot before(em);
  Status st = em.mergeVertices(vertexAt(em, 0.5f, -1, 0), vertexAt(em, 0.5f, 1, 0), true);
  EXPECT_EQ(st.code, Code::EditRefused);
  EXPECT_NE(st.message.find("fold over"), std::string::npos) << st.message;
  EXPECT_TRUE(Snapshot(em) == before);
}

TEST(MergeVertices, RefusesAnInconsistentPairAndAThirdSide) {
  // Two triangles whose edges 0-1 and 3-4 run the same way: merging 3 into 0 and 4 into 1
  // would make an inconsistent edge.
  gen::Soup s;
  s.v = {{0, 0, 0}, {1, 0, 0}, {0.5f, 1, 0}, {0, 0, 0.001f}, {1, 0, 0.001f}, {0.5f, 1, 0.5f}};
  s.f = {{0, 1, 2}, {3, 4, 5}};
  EditableMesh em;
  makeEditable(s, em);
  Snapshot before(em);
  const uint32_t keep[2] = {vertexAt(em, 0, 0, 0), vertexAt(em, 1, 0, 0)};
  const uint32_t gone[2] = {vertexAt(em, 0, 0, 0.001f), vertexAt(em, 1, 0, 0.001f)};
  Status st = em.mergeVertices(keep, gone, 2);
  EXPECT_EQ(st.code, Code::EditRefused);
  EXPECT_NE(st.message.find("same way"), std::string::npos) << st.message;
  EXPECT_TRUE(Snapshot(em) == before);
  // Three sheets on one edge: two triangles on edge 0-1 already (a closed pair), a third
  // would make it non-manifold.
  gen::Soup b;
  b.v = {{0, 0, 0}, {1, 0, 0}, {0.5f, 1, 0}, {0.5f, -1, 0}, {0, 0, 0.001f}, {1, 0, 0.001f}, {0.5f, 0, 1}};
  b.f = {{0, 1, 2}, {1, 0, 3}, {5, 4, 6}};
  EditableMesh em2;
  makeEditable(b, em2);
  Snapshot before2(em2);
  const uint32_t keep2[2] = {vertexAt(em2, 0, 0, 0), vertexAt(em2, 1, 0, 0)};
  const uint32_t gone2[2] = {vertexAt(em2, 0, 0, 0.001f), vertexAt(em2, 1, 0, 0.001f)};
  st = em2.mergeVertices(keep2, gone2, 2, true);
  EXPECT_EQ(st.code, Code::EditRefused);
  EXPECT_NE(st.message.find("3 sides"), std::string::npos) << st.message;
  EXPECT_TRUE(Snapshot(em2) == before2);
}

TEST(MergeVertices, VertexAttributesMergeByTheirRule) {
  EditableMesh em;
  makeEditable(cubeHalves(0.001f), em);
  std::vector<float> values(em.nVertices());
  for (uint32_t v = 0; v < em.nVertices(); ++v) values[v] = float(v);
  AttributeRules avg;
  avg.merge = Rule::Average;
  ASSERT_TRUE(em.addAttribute("w", Element::Vertex, ValueType::F32, 1, values.data(), avg).ok());
  const auto keep = rim(em, 0.5f), gone = rim(em, 0.501f);
  ASSERT_TRUE(em.mergeVertices(keep.data(), gone.data(), 4).ok());
  const float* w = static_cast<const float*>(em.attribute("w")->data);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(w[keep[i]], 0.5f * float(keep[i] + gone[i])) << i;
  // Fail refuses unequal values (and changes nothing).
  EditableMesh em2;
  makeEditable(cubeHalves(0.001f), em2);
  AttributeRules fail;
  fail.merge = Rule::Fail;
  ASSERT_TRUE(em2.addAttribute("w", Element::Vertex, ValueType::F32, 1, values.data(), fail).ok());
  Snapshot before(em2);
  EXPECT_EQ(em2.mergeVertices(keep.data(), gone.data(), 4).code, Code::EditRefused);
  EXPECT_TRUE(Snapshot(em2) == before);
}

// ------------------------------------------------------------------------ splitEdgeAt

TEST(SplitEdgeAt, ClosesAnExactTJunction) {
  EditableMesh em;
  makeEditable(tJunction(), em);
  const EditStats before = em.stats();
  ASSERT_EQ(before.boundaryEdges, 8u);
  // The boundary half-edge of the lower triangle's edge (2,0)-(0,0).
  const uint32_t a = vertexAt(em, 0, 0, 0), b = vertexAt(em, 2, 0, 0), v = vertexAt(em, 1, 0, 0);
  uint32_t e = kInvalid;
  for (uint32_t h = 0; h < em.nHalfedges(); ++h)
    if (em.isBoundary(h) && em.vert()[h] == a && em.vert()[h ^ 1u] == b) e = h;
  ASSERT_NE(e, kInvalid);
  Status s = em.splitEdgeAt(e, v);
  ASSERT_TRUE(s.ok()) << s.message;
  const EditStats& st = em.stats();
  EXPECT_EQ(st.boundaryEdges, 5u);  // the three edges on y = 0 became two interior ones
  EXPECT_EQ(st.triangles, 5u);
  EXPECT_EQ(st.holes, 1u);
  EXPECT_TRUE(st.manifold);
  EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
}

TEST(SplitEdgeAt, TwoVerticesOnOneEdgeSplitItInOrder) {
  gen::Soup s;  // three triangles above y = 0 meeting it at x = 0, 0.5, 1.5, 2; one below
  s.v = {{0, 0, 0}, {0.5f, 0, 0}, {1.5f, 0, 0}, {2, 0, 0}, {1, 1, 0}, {1, -1, 0}};
  s.f = {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {0, 5, 3}};
  EditableMesh em;
  makeEditable(s, em);
  const uint32_t a = vertexAt(em, 0, 0, 0), b = vertexAt(em, 2, 0, 0);
  uint32_t e = kInvalid;
  for (uint32_t h = 0; h < em.nHalfedges(); ++h)
    if (em.isBoundary(h) && em.vert()[h] == a && em.vert()[h ^ 1u] == b) e = h;
  ASSERT_NE(e, kInvalid);
  // Listed out of order along the edge: the edit sorts them.
  const uint32_t edges[2] = {e, e}, verts[2] = {vertexAt(em, 1.5f, 0, 0), vertexAt(em, 0.5f, 0, 0)};
  Status st = em.stitch(nullptr, nullptr, 0, edges, verts, 2);
  ASSERT_TRUE(st.ok()) << st.message;
  EXPECT_EQ(em.stats().triangles, 6u);
  EXPECT_EQ(em.stats().boundaryEdges, 4u);
  EXPECT_TRUE(em.stats().manifold);
  EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
}

TEST(SplitEdgeAt, RefusalsChangeNothing) {
  EditableMesh em;
  makeEditable(tJunction(), em);
  uint32_t far = kInvalid;
  ASSERT_TRUE(em.addVertex(5, 0, 0, &far).ok());
  Snapshot before(em);
  const uint32_t a = vertexAt(em, 0, 0, 0), b = vertexAt(em, 2, 0, 0), v = vertexAt(em, 1, 0, 0);
  uint32_t e = kInvalid, inner = kInvalid;
  for (uint32_t h = 0; h < em.nHalfedges(); ++h) {
    if (em.isBoundary(h) && em.vert()[h] == a && em.vert()[h ^ 1u] == b) e = h;
    if (!em.isBoundary(h) && !em.isBoundary(h ^ 1u)) inner = h;
  }
  ASSERT_NE(e, kInvalid);
  ASSERT_NE(inner, kInvalid);
  Status s = em.splitEdgeAt(e, vertexAt(em, 1, -1, 0));  // a corner of the triangle
  EXPECT_EQ(s.code, Code::EditRefused);
  EXPECT_NE(s.message.find("corner"), std::string::npos) << s.message;
  s = em.splitEdgeAt(e, far);  // beyond the edge's end
  EXPECT_EQ(s.code, Code::EditRefused);
  EXPECT_NE(s.message.find("strictly inside"), std::string::npos) << s.message;
  EXPECT_EQ(em.splitEdgeAt(inner, v).code, Code::InvalidArgument);  // not a boundary edge
  EXPECT_TRUE(Snapshot(em) == before);
}

TEST(Stitch, ZipsACrackBetweenDifferentTessellationsInOneEdit) {
  EditableMesh em;
  makeEditable(cubeHalvesMismatched(0.001f), em);
  ASSERT_EQ(em.stats().boundaryEdges, 12u);
  const auto keep = rim(em, 0.5f), gone = rim(em, 0.501f);
  // The lower rim's boundary half-edges, each with the upper rim's midpoint above it.
  std::vector<uint32_t> edges, mids;
  for (int i = 0; i < 4; ++i) {
    const float mx = 0.5f * (em.positions()[3 * keep[i]] + em.positions()[3 * keep[(i + 1) % 4]]);
    const float my = 0.5f * (em.positions()[3 * keep[i] + 1] + em.positions()[3 * keep[(i + 1) % 4] + 1]);
    for (uint32_t h = 0; h < em.nHalfedges(); ++h)
      if (em.isBoundary(h) && keyOf2(em.vert()[h], em.vert()[h ^ 1u]) == keyOf2(keep[i], keep[(i + 1) % 4]))
        edges.push_back(h);
    mids.push_back(vertexAt(em, mx, my, 0.501f));
  }
  ASSERT_EQ(edges.size(), 4u);
  // Each part alone is refused (a pinch, or edges that do not pair), and changes nothing.
  Snapshot before(em);
  EXPECT_EQ(em.mergeVertices(keep.data(), gone.data(), 4).code, Code::EditRefused);
  EXPECT_EQ(em.splitEdgeAt(edges[0], mids[0]).code, Code::EditRefused);
  EXPECT_TRUE(Snapshot(em) == before);
  // Together they close the crack.
  Status s = em.stitch(keep.data(), gone.data(), 4, edges.data(), mids.data(), 4);
  ASSERT_TRUE(s.ok()) << s.message;
  EXPECT_TRUE(em.stats().watertight);
  EXPECT_TRUE(em.stats().manifold);
  EXPECT_EQ(em.stats().triangles, 28u);
  EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
}

TEST(StitchStep, ClosesACrackBetweenDifferentTessellations) {
  EditableMesh em;
  makeEditable(cubeHalvesMismatched(0.001f), em);
  RepairOptions o;
  o.stitchTolerance = 0.01;
  RepairStepPlan plan;
  ASSERT_TRUE(runStep(RepairStepKind::Stitch, em, o, plan).ok());
  ASSERT_EQ(plan.items.size(), 1u);
  EXPECT_FALSE(plan.items[0].skipped) << plan.items[0].reason;
  EXPECT_NE(plan.items[0].action.find("merge 4 vertices and split 4 boundary edges"), std::string::npos)
      << plan.items[0].action;
  EXPECT_TRUE(em.stats().watertight);
  EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
}

// ------------------------------------------------------------------------ splitVertex

namespace {
// Two unit cubes, the second at offset (ox, oy, oz): at (1, 1, 1) they share one vertex,
// at (1, 1, 0) the edge x = y = 1.
gen::Soup twoCubes(float ox, float oy, float oz) {
  gen::Soup s = gen::cube();
  gen::append(s, gen::cube(ox, oy, oz));
  return s;
}
}  // namespace

TEST(SplitVertex, TwoCubesSharingAVertexComeApart) {
  EditableMesh em;
  makeEditable(twoCubes(1, 1, 1), em);
  ASSERT_EQ(em.stats().nonManifoldVertices, 1u);
  auto corners = cornerPositions(em);
  uint32_t v = kInvalid;
  for (uint32_t x = 0; x < em.nVertices(); ++x)
    if (em.vertexNonManifold(x)) v = x;
  uint32_t first = 0, count = 0;
  Status s = em.splitVertex(v, &first, &count);
  ASSERT_TRUE(s.ok()) << s.message;
  EXPECT_EQ(count, 1u);
  EXPECT_EQ(first, 15u);
  const EditStats& st = em.stats();
  EXPECT_EQ(st.nonManifoldVertices, 0u);
  EXPECT_TRUE(st.watertight);
  EXPECT_EQ(st.shells, 2u);
  EXPECT_EQ(st.eulerCharacteristic, 4);
  EXPECT_EQ(cornerPositions(em), corners);
  EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
  // Nothing left to split.
  Snapshot before(em);
  EXPECT_EQ(em.splitVertex(v).code, Code::EditRefused);
  EXPECT_TRUE(Snapshot(em) == before);
}

TEST(SplitNonManifoldStep, TwoCubesSharingAnEdge) {
  EditableMesh em;
  makeEditable(twoCubes(1, 1, 0), em);
  ASSERT_EQ(em.stats().nonManifoldEdges, 1u);
  auto corners = cornerPositions(em);
  RepairOptions o;
  RepairStepPlan plan;
  ASSERT_TRUE(runStep(RepairStepKind::SplitNonManifold, em, o, plan).ok());
  const EditStats& st = em.stats();
  EXPECT_EQ(st.nonManifoldEdges, 0u);
  EXPECT_EQ(st.nonManifoldVertices, 0u);
  EXPECT_TRUE(st.watertight);
  EXPECT_EQ(st.shells, 2u);
  EXPECT_EQ(nDone(plan), 2u);  // both ends of the edge
  EXPECT_EQ(nSkipped(plan), 0u);
  EXPECT_EQ(cornerPositions(em), corners);
  EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
}

TEST(SplitNonManifoldStep, BowTieAndBookOfThreePages) {
  {
    gen::Soup s;  // two triangles meeting at vertex 0
    s.v = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
    s.f = {{0, 1, 2}, {0, 3, 4}};
    EditableMesh em;
    makeEditable(s, em);
    ASSERT_EQ(em.stats().nonManifoldVertices, 1u);
    RepairOptions o;
    RepairStepPlan plan;
    ASSERT_TRUE(runStep(RepairStepKind::SplitNonManifold, em, o, plan).ok());
    EXPECT_EQ(em.stats().nonManifoldVertices, 0u);
    EXPECT_EQ(em.stats().vertices, 6u);
    ASSERT_EQ(plan.items.size(), 1u);
    EXPECT_NE(plan.items[0].action.find("split vertex 0"), std::string::npos) << plan.items[0].action;
    EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
  }
  {
    gen::Soup s;  // three triangles on edge 0-1: two pair up by orientation, the third is cut
    s.v = {{0, 0, 0}, {1, 0, 0}, {0.5f, 1, 0}, {0.5f, -1, 0}, {0.5f, 0, 1}};
    s.f = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
    EditableMesh em;
    makeEditable(s, em);
    ASSERT_EQ(em.stats().nonManifoldEdges, 1u);
    auto corners = cornerPositions(em);
    RepairOptions o;
    RepairStepPlan plan;
    ASSERT_TRUE(runStep(RepairStepKind::SplitNonManifold, em, o, plan).ok());
    const EditStats& st = em.stats();
    EXPECT_EQ(st.nonManifoldEdges, 0u);
    EXPECT_EQ(st.nonManifoldVertices, 0u);
    EXPECT_EQ(st.edges, 8u);  // 0-1 paired (the first two pages), its copy for the third
    EXPECT_EQ(st.shells, 2u);
    EXPECT_EQ(cornerPositions(em), corners);
    EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
  }
}

// ------------------------------------------------------------------------ the stitch step

TEST(StitchStep, ClosesTheGapBetweenTwoHalvesWithinTheTolerance) {
  EditableMesh em;
  makeEditable(cubeHalves(0.001f), em);
  RepairOptions o;
  o.stitchTolerance = 0.01;
  RepairStepPlan plan;
  ASSERT_TRUE(runStep(RepairStepKind::Stitch, em, o, plan).ok());
  ASSERT_EQ(plan.items.size(), 1u);
  EXPECT_FALSE(plan.items[0].skipped) << plan.items[0].reason;
  EXPECT_NE(plan.items[0].action.find("close a crack: merge 4 vertices"), std::string::npos) << plan.items[0].action;
  EXPECT_EQ(plan.items[0].vertices.size(), 8u);
  EXPECT_TRUE(em.stats().watertight);
  EXPECT_TRUE(em.stats().manifold);
  EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
}

TEST(StitchStep, BelowTheToleranceNothingChanges) {
  EditableMesh em;
  makeEditable(cubeHalves(0.001f), em);
  Snapshot before(em);
  RepairOptions o;
  o.stitchTolerance = 0.0005;
  RepairStepPlan plan;
  ASSERT_TRUE(runStep(RepairStepKind::Stitch, em, o, plan).ok());
  EXPECT_TRUE(plan.items.empty());
  EXPECT_TRUE(Snapshot(em) == before);
}

TEST(StitchStep, ExcludedItemsAreSkippedAndChangeNothing) {
  EditableMesh em;
  makeEditable(cubeHalves(0.001f), em);
  Snapshot before(em);
  RepairOptions o;
  o.stitchTolerance = 0.01;
  o.exclude.push_back({RepairStepKind::Stitch, 0});
  RepairStepPlan plan;
  ASSERT_TRUE(runStep(RepairStepKind::Stitch, em, o, plan).ok());
  ASSERT_EQ(plan.items.size(), 1u);
  EXPECT_TRUE(plan.items[0].skipped);
  EXPECT_TRUE(Snapshot(em) == before);
}

TEST(StitchStep, ClosesAnExactTJunctionWithoutATolerance) {
  EditableMesh em;
  makeEditable(tJunction(), em);
  RepairOptions o;  // tolerance 0: exact T-junctions only
  RepairStepPlan plan;
  ASSERT_TRUE(runStep(RepairStepKind::Stitch, em, o, plan).ok());
  ASSERT_EQ(plan.items.size(), 1u);
  EXPECT_FALSE(plan.items[0].skipped) << plan.items[0].reason;
  char expected[120];
  std::snprintf(expected, sizeof expected, "close T-junction: split boundary edge %u-%u at vertex %u (on the edge)",
                vertexAt(em, 0, 0, 0), vertexAt(em, 2, 0, 0), vertexAt(em, 1, 0, 0));
  EXPECT_EQ(plan.items[0].action, expected);
  EXPECT_EQ(em.stats().boundaryEdges, 5u);
  EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
}

TEST(StitchStep, ClosesATJunctionBesideAFlippedTriangle) {
  // A closed box [0,2]^3 whose edge (0,0,0)-(0,0,2) is cut at (0,0,1) in one of its two
  // triangles only (a T-junction), and the triangle across the other edge of the uncut side is
  // flipped (an inconsistent edge that stitch runs before orient fixes). Splitting the uncut
  // triangle hands that edge to its new part: the edge stays as inconsistent as it was, so
  // the split may go ahead (it was refused as "two sides running the same way" once).
  gen::Soup s = gen::cube(0, 0, 0, 2);
  const std::array<float, 3> lo{0, 0, 0}, hi{0, 0, 2};
  auto at = [&](const std::array<float, 3>& q) {
    for (uint32_t i = 0; i < s.v.size(); ++i)
      if (s.v[i] == q) return i;
    ADD_FAILURE();
    return 0u;
  };
  const uint32_t a = at(lo), b = at(hi);
  s.v.push_back({0, 0, 1});
  const uint32_t m = uint32_t(s.v.size() - 1);
  int cut = -1, across = -1;
  for (int i = 0; i < int(s.f.size()); ++i)
    for (int c = 0; c < 3; ++c) {
      if (s.f[i][c] == a && s.f[i][(c + 1) % 3] == b) cut = i * 3 + c;
      if (s.f[i][c] == b && s.f[i][(c + 1) % 3] == a) across = i * 3 + c;
    }
  ASSERT_GE(cut, 0);
  ASSERT_GE(across, 0);
  const int t = cut / 3, c = cut % 3;
  const uint32_t o = s.f[t][(c + 2) % 3];
  s.f[t] = {a, m, o};
  s.f.push_back({m, b, o});
  // Flip the neighbour of the uncut triangle across its side from a to its third corner.
  const int u = across / 3, k = across % 3;
  const uint32_t d = s.f[u][(k + 2) % 3];
  int flipped = -1;
  for (int i = 0; i < int(s.f.size()); ++i)
    for (int q = 0; q < 3; ++q)
      if (i != u && s.f[i][q] == d && s.f[i][(q + 1) % 3] == a) flipped = i;
  ASSERT_GE(flipped, 0);
  std::swap(s.f[flipped][1], s.f[flipped][2]);
  EditableMesh em;
  makeEditable(s, em);
  ASSERT_EQ(em.stats().inconsistentEdges, 3u);
  RepairOptions opts;
  RepairStepPlan plan;
  ASSERT_TRUE(runStep(RepairStepKind::Stitch, em, opts, plan).ok());
  ASSERT_EQ(plan.items.size(), 1u);
  EXPECT_FALSE(plan.items[0].skipped) << plan.items[0].reason;
  EXPECT_EQ(em.stats().boundaryEdges, 0u);
  EXPECT_EQ(em.stats().inconsistentEdges, 3u);  // as before: orient's to fix
  EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
}

TEST(StitchStep, ATJunctionWithinTheTolerance) {
  gen::Soup s = tJunction();
  s.v[1][1] = 0.002f;  // the T vertex 0.002 above the lower edge
  EditableMesh em;
  makeEditable(s, em);
  RepairOptions o;
  RepairStepPlan plan;
  ASSERT_TRUE(runStep(RepairStepKind::Stitch, em, o, plan).ok());
  EXPECT_TRUE(plan.items.empty());  // not exactly on the edge
  o.stitchTolerance = 0.01;
  ASSERT_TRUE(runStep(RepairStepKind::Stitch, em, o, plan).ok());
  ASSERT_EQ(plan.items.size(), 1u);
  EXPECT_FALSE(plan.items[0].skipped) << plan.items[0].reason;
  EXPECT_EQ(em.stats().boundaryEdges, 5u);
  EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
}

// Stitch's tolerance tests are exact (predicates.h): the pair's distance (withinDistance, as
// the tolerance weld), a T-junction's projection strictly inside the edge (dotSign) and its
// distance to the edge's line (withinLineDistance), against 128-bit integers on integer
// corners, a third of them at exactly the tolerance from the line (a Pythagorean offset
// across the edge, a third of the way along), with tolerances k / 1024 beside the distance:
// the ties go to the exact stage. (The projection in double, the rule before, happens to get
// all of these right; the pair's distance does not: the next test.)
TEST(StitchStep, ItsToleranceTestsAreExact) {
  std::mt19937_64 rng(5);
  auto coord = [&](int bits) { return float(int64_t(rng() % (uint64_t(1) << bits)) - (int64_t(1) << (bits - 1))); };
  int ties = 0, n = 0;
  for (int i = 0; i < 200000; ++i) {
    float a[3], b[3], v[3];
    for (int k = 0; k < 3; ++k) a[k] = coord(20);
    if (i % 3 == 0) {  // b - a = 3 (3m, 4m, z), v = a third of it plus (4j, -3j, 0): 5j from the line
      const float m = coord(8), z = coord(8), j = coord(6);
      const float w[3] = {9 * m, 12 * m, 3 * z}, off[3] = {4 * j, -3 * j, 0};
      for (int k = 0; k < 3; ++k) b[k] = a[k] + w[k], v[k] = a[k] + w[k] / 3 + off[k];
    } else {
      for (int k = 0; k < 3; ++k) b[k] = a[k] + coord(10), v[k] = a[k] + coord(11);
    }
    int64_t u[3], w[3];
    for (int k = 0; k < 3; ++k) u[k] = int64_t(v[k]) - int64_t(a[k]), w[k] = int64_t(b[k]) - int64_t(a[k]);
    __int128 cross2 = 0, len2 = 0, dot = 0;
    for (int k = 0; k < 3; ++k) {
      const int p = (k + 1) % 3, q = (k + 2) % 3;
      const __int128 c = __int128(u[p]) * w[q] - __int128(u[q]) * w[p];
      cross2 += c * c;
      len2 += __int128(w[k]) * w[k];
      dot += __int128(u[k]) * w[k];
    }
    if (len2 == 0) continue;
    const int wantDot = dot > 0 ? 1 : dot < 0 ? -1 : 0;
    ASSERT_EQ(pred::dotSign(v, a, b), wantDot) << i;
    ASSERT_EQ(pred::dotSignExact(v, a, b), wantDot) << i;
    const int64_t k = std::llround(1024 * std::sqrt(double(cross2) / double(len2))) + int64_t(rng() % 3) - 1;
    if (k <= 0) continue;
    const double tol = double(k) / 1024;
    const __int128 lhs = cross2 << 20, rhs = __int128(k) * k * len2;  // both below 2^90
    const bool want = lhs <= rhs;
    ties += lhs == rhs;
    ++n;
    ASSERT_EQ(pred::withinLineDistance(v, a, b, tol, tol * tol), want) << i;
    ASSERT_EQ(pred::withinLineDistanceExact(v, a, b, tol), want) << i;
  }
  EXPECT_GT(n, 100000);
  EXPECT_GT(ties, 1000);
}

// A pair just beyond the tolerance is not merged, though its distance in double is within it:
// (1, 2^-30, 0) is sqrt(1 + 2^-60) from the origin, and 1 + 2^-60 rounds to 1. At (1, 0, 0)
// the two corners are one item (a single pair: skipped, as it would pinch two fans).
TEST(StitchStep, APairJustBeyondTheToleranceIsNoItem) {
  for (float y : {std::ldexp(1.0f, -30), 0.0f}) {
    gen::Soup s;
    s.v = {{0, 0, 0}, {-3, 0, 0}, {-3, -3, 0}, {1, y, 0}, {4, 0, 0}, {4, 4, 0}};
    s.f = {{0, 1, 2}, {3, 4, 5}};
    EditableMesh em;
    makeEditable(s, em);
    RepairOptions o;
    o.stitchTolerance = 1;
    RepairStepPlan plan;
    ASSERT_TRUE(runStep(RepairStepKind::Stitch, em, o, plan).ok());
    EXPECT_EQ(plan.items.size(), y == 0 ? 1u : 0u) << y;
  }
}

TEST(StitchStep, APinchingPairIsSkippedWithTheReason) {
  // Two triangles whose corners 2 and 5 are 0.001 apart and nothing else is close: merging
  // them would pinch two fans at one vertex.
  gen::Soup s;
  s.v = {{0, 0, 0}, {1, 0, 0}, {0.5f, 1, 0}, {0, 2.001f, 0}, {1, 2.001f, 0}, {0.5f, 1.001f, 0}};
  s.f = {{0, 1, 2}, {3, 5, 4}};
  EditableMesh em;
  makeEditable(s, em);
  Snapshot before(em);
  RepairOptions o;
  o.stitchTolerance = 0.01;
  RepairStepPlan plan;
  ASSERT_TRUE(runStep(RepairStepKind::Stitch, em, o, plan).ok());
  ASSERT_EQ(plan.items.size(), 1u);
  EXPECT_TRUE(plan.items[0].skipped);
  EXPECT_NE(plan.items[0].reason.find("non-manifold"), std::string::npos) << plan.items[0].reason;
  EXPECT_TRUE(Snapshot(em) == before);
}

// ------------------------------------------------------------------------ fixtures

namespace {
bool loadFixture(const std::string& path, EditableMesh& em, double& diag) {
  std::string bytes = gen::readFile(path);
  Mesh m;
  if (!gen::read(bytes, m).ok() || m.nTriangles() == 0) return false;
  if (!em.init(m).ok()) return false;
  double d = 0;
  for (int k = 0; k < 3; ++k) d += double(m.bboxMax[k] - m.bboxMin[k]) * double(m.bboxMax[k] - m.bboxMin[k]);
  diag = std::sqrt(d);
  return true;
}
}  // namespace

// Stitch never makes a figure worse, on every fixture, at tolerances 0 and 1e-6, 1e-4,
// 1e-3 and 1e-2 of the bounding-box diagonal; the result is always a valid mesh equal to
// a fresh build. Prints the before/after table of the fixtures with defective edges.
TEST(StitchStep, NeverMakesAFixtureWorse) {
  const double fractions[] = {0, 1e-6, 1e-4, 1e-3, 1e-2};
  uint32_t files = 0;
  for (const std::string& path : gen::fixtureFiles(gen::kWithoutRegress | gen::kWithoutLarge)) {
    const std::string rel = gen::fixtureName(path);
    EditableMesh probe;
    double diag = 0;
    if (!loadFixture(path, probe, diag)) continue;
    ++files;
    const Counts start = counts(probe);
    const bool defective = start.boundary + start.nonManifoldEdges + start.inconsistent + start.nonManifoldVertices > 0;
    std::string row = rel + ": b/nm/inc/nmv " + std::to_string(start.boundary) + "/" +
                      std::to_string(start.nonManifoldEdges) + "/" + std::to_string(start.inconsistent) + "/" +
                      std::to_string(start.nonManifoldVertices);
    for (double f : fractions) {
      EditableMesh em;
      ASSERT_TRUE(loadFixture(path, em, diag));
      RepairOptions o;
      o.stitchTolerance = f * diag;
      RepairStepPlan plan;
      Status s = runStep(RepairStepKind::Stitch, em, o, plan);
      ASSERT_TRUE(s.ok()) << rel << " at " << f << ": " << s.message;
      const Counts after = counts(em);
      expectNotWorse(start, after, rel + " at tolerance " + std::to_string(f));
      if (nDone(plan) > 0 || defective) {
        EXPECT_EQ(editcheck::differenceFromRebuild(em), "") << rel << " at " << f;
      }
      char cell[160];
      std::snprintf(cell, sizeof cell, " | %g: %u/%u/%u/%u (%u done, %u skipped)", f, after.boundary,
                    after.nonManifoldEdges, after.inconsistent, after.nonManifoldVertices, nDone(plan), nSkipped(plan));
      row += cell;
    }
    if (defective) std::printf("[stitch] %s\n", row.c_str());
  }
  EXPECT_GT(files, 50u);
}

// split-nonmanifold on the fixtures with non-manifold elements: no non-manifold edge is
// left, positions stay, the mesh is valid; non-manifold vertices remain only where their
// fans are joined through inconsistent edges (listed as skipped).
TEST(SplitNonManifoldStep, Fixtures) {
  for (const std::string& path : gen::fixtureFiles(gen::kWithoutRegress)) {
    const std::string rel = gen::fixtureName(path);
    EditableMesh em;
    double diag = 0;
    if (!loadFixture(path, em, diag)) continue;
    const Counts start = counts(em);
    if (start.nonManifoldEdges + start.nonManifoldVertices == 0) continue;
    auto corners = cornerPositions(em);
    RepairOptions o;
    RepairStepPlan plan;
    Status s = runStep(RepairStepKind::SplitNonManifold, em, o, plan);
    ASSERT_TRUE(s.ok()) << rel << ": " << s.message;
    const Counts after = counts(em);
    EXPECT_EQ(after.nonManifoldEdges, 0u) << rel;
    EXPECT_LE(after.nonManifoldVertices, start.nonManifoldVertices) << rel;
    EXPECT_LE(after.inconsistent, start.inconsistent) << rel;
    if (after.nonManifoldVertices > 0) EXPECT_GT(after.inconsistent, 0u) << rel;
    EXPECT_EQ(nSkipped(plan), after.nonManifoldVertices) << rel;
    EXPECT_EQ(cornerPositions(em), corners) << rel;
    EXPECT_EQ(editcheck::differenceFromRebuild(em), "") << rel;
    std::printf("[split] %s: b/nm/inc/nmv %u/%u/%u/%u -> %u/%u/%u/%u (%u done, %u skipped)\n", rel.c_str(),
                start.boundary, start.nonManifoldEdges, start.inconsistent, start.nonManifoldVertices, after.boundary,
                after.nonManifoldEdges, after.inconsistent, after.nonManifoldVertices, nDone(plan), nSkipped(plan));
  }
}
