// EditableMesh: hand-checked edits on generated meshes, refused edits that change nothing,
// attributes through edits, and randomized edit sequences on fixtures and generated
// meshes, each checked against a fresh buildTopology of the compacted mesh.
#include <gtest/gtest.h>

#include <algorithm>
#include <cinttypes>
#include <filesystem>
#include <limits>
#include <random>

#include "edit_check.h"
#include "stl_gen.h"
#include "stltopo/edit.h"

using namespace stltopo;

namespace {

Mesh readSoup(const gen::Soup& s) {
  Mesh m;
  Status st = gen::read(gen::binary(s), m);
  EXPECT_TRUE(st.ok()) << st.message;
  return m;
}

void makeEditable(const gen::Soup& s, EditableMesh& em) {
  Mesh m = readSoup(s);
  Status st = em.init(m);
  ASSERT_TRUE(st.ok()) << st.message;
  ASSERT_EQ(editcheck::differenceFromRebuild(em), "");
}

std::vector<uint32_t> holeSizes(EditableMesh& em) {
  std::vector<uint32_t> out;
  const EditLoops& l = em.loops();
  for (uint32_t h = 0; h < l.nLoops(); ++h)
    if (!l.loopIsSeam[h]) out.push_back(l.loopOffsets[h + 1] - l.loopOffsets[h]);
  return out;
}

using editcheck::Snapshot;

gen::Soup tetrahedron() {
  gen::Soup s;
  s.v = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  s.f = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  return s;
}

}  // namespace

TEST(Edit, UneditedMeshEqualsItsTopology) {
  EditableMesh em;
  makeEditable(gen::cube(), em);
  EXPECT_EQ(em.stats().triangles, 12u);
  EXPECT_TRUE(em.stats().watertight);
  EXPECT_EQ(em.stats().eulerCharacteristic, 2);
}

TEST(Edit, RemovingOneCubeFaceGivesOneHoleOfThreeEdges) {
  EditableMesh em;
  makeEditable(gen::cube(), em);
  ASSERT_TRUE(em.removeTriangle(0).ok());
  EXPECT_EQ(holeSizes(em), std::vector<uint32_t>{3});
  EXPECT_EQ(em.stats().boundaryEdges, 3u);
  EXPECT_FALSE(em.stats().watertight);
  EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
}

TEST(Edit, RemovingTwoNeighbouringFacesGivesOneHoleOfFourEdges) {
  EditableMesh em;
  makeEditable(gen::cube(), em);
  // Triangles 0 and 1 are the two halves of one side of the cube (they share an edge).
  ASSERT_TRUE(em.removeTriangle(0).ok());
  ASSERT_TRUE(em.removeTriangle(1).ok());
  EXPECT_EQ(holeSizes(em), std::vector<uint32_t>{4});
  EXPECT_EQ(em.stats().edges, 17u);
  EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
}

TEST(Edit, RemovingTwoFacesTouchingAtAVertexGivesLoopsByTheFanRule) {
  // Two triangles of a cube that share only vertex 0: (0,2,3) on the z = 0 side and
  // (0,4,6)... the cube's quads are listed in gen::cube(); find a pair by their vertices.
  gen::Soup s = gen::cube();
  Mesh m = readSoup(s);
  EditableMesh em;
  ASSERT_TRUE(em.init(m).ok());
  uint32_t t0 = kInvalid, t1 = kInvalid;
  for (uint32_t a = 0; a < 12 && t0 == kInvalid; ++a)
    for (uint32_t b = a + 1; b < 12; ++b) {
      int shared = 0;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) shared += m.triangles[3 * a + i] == m.triangles[3 * b + j];
      if (shared == 1) {
        t0 = a;
        t1 = b;
        break;
      }
    }
  ASSERT_NE(t0, kInvalid);
  ASSERT_TRUE(em.removeTriangle(t0).ok());
  ASSERT_TRUE(em.removeTriangle(t1).ok());
  // The two holes meet at one vertex. The fan rule continues a boundary through the fan of
  // remaining triangles it arrives in, which ends at the other hole: one loop of 6 edges
  // that passes the vertex twice. The vertex's remaining triangles are two fans, so it has
  // two vnext cycles: non-manifold.
  EXPECT_EQ(holeSizes(em), std::vector<uint32_t>{6});
  EXPECT_EQ(em.stats().nonManifoldVertices, 1u);
  EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
  // Filling it cuts the loop at the vertex into two triangles: closed again.
  Array<uint32_t> added;
  ASSERT_TRUE(em.fillLoop(0, FillMethod::Ear, &added).ok());
  EXPECT_EQ(added.size(), 2u);
  EXPECT_TRUE(em.stats().watertight);
  EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
}

TEST(Edit, FillingAHoleBringsTheCubeBackToWatertightGenusZero) {
  for (FillMethod method : {FillMethod::Fan, FillMethod::Ear}) {
    EditableMesh em;
    makeEditable(gen::cube(), em);
    ASSERT_TRUE(em.removeTriangle(0).ok());
    ASSERT_TRUE(em.removeTriangle(1).ok());
    ASSERT_EQ(em.loops().nLoops(), 1u);
    Array<uint32_t> added;
    Status s = em.fillLoop(0, method, &added);
    ASSERT_TRUE(s.ok()) << s.message;
    EXPECT_EQ(added.size(), 2u);
    const EditStats& st = em.stats();
    EXPECT_TRUE(st.watertight);
    EXPECT_TRUE(st.manifold);
    EXPECT_EQ(st.eulerCharacteristic, 2);
    EXPECT_EQ(st.shells, 1u);
    EXPECT_EQ(em.loops().nLoops(), 0u);
    EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
    Mesh m;
    ASSERT_TRUE(em.toMesh(m).ok());
    EXPECT_NEAR(m.volume, 1.0, 1e-12);
  }
}

// The perimeter of loop h, from the positions of its vertices (an independent sum).
static double perimeterOf(EditableMesh& em, uint32_t h) {
  const EditLoops& l = em.loops();
  double sum = 0;
  for (uint32_t i = l.loopOffsets[h]; i < l.loopOffsets[h + 1]; ++i) {
    uint32_t e = l.loopHalfedges[i];
    const float* a = em.positions().data() + 3 * size_t(em.vert()[e]);
    const float* b = em.positions().data() + 3 * size_t(em.vert()[e ^ 1u]);
    sum += std::hypot(double(a[0]) - b[0], double(a[1]) - b[1], double(a[2]) - b[2]);
  }
  return sum;
}

TEST(Edit, SetPositionMovesOnlyTheVertexAndKeepsPerimetersUpToDate) {
  EditableMesh em;
  makeEditable(gen::cube(), em);
  ASSERT_TRUE(em.removeTriangle(0).ok());  // a hole of three edges, sides 1, 1 and sqrt 2
  ASSERT_EQ(em.loops().nLoops(), 1u);
  EXPECT_NEAR(em.loops().loopPerimeter[0], 2 + std::sqrt(2.0), 1e-12);
  const EditStats statsBefore = em.stats();
  std::vector<float> positionsBefore(em.positions().begin(), em.positions().end());
  // A vertex of the hole moves 2 away: the perimeter follows.
  const uint32_t v = em.vert()[em.loops().loopHalfedge[0]];
  const float x = positionsBefore[3 * v] + 2, y = positionsBefore[3 * v + 1], z = positionsBefore[3 * v + 2];
  ASSERT_TRUE(em.setPosition(v, x, y, z).ok());
  const double moved = em.loops().loopPerimeter[0];
  EXPECT_GT(moved, 2 + std::sqrt(2.0) + 1);
  EXPECT_NEAR(moved, perimeterOf(em, 0), 1e-12);
  for (size_t i = 0; i < positionsBefore.size(); ++i)
    EXPECT_EQ(em.positions()[i], i == 3 * v ? x : positionsBefore[i]) << i;
  const EditStats& st = em.stats();
  EXPECT_EQ(st.edges, statsBefore.edges);
  EXPECT_EQ(st.holes, statsBefore.holes);
  EXPECT_EQ(st.eulerCharacteristic, statsBefore.eulerCharacteristic);
  EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
  // A vertex not on the hole: the perimeter stays.
  uint32_t off = kInvalid;
  for (uint32_t w = 0; w < em.nVertices() && off == kInvalid; ++w) {
    bool onLoop = false;
    for (uint32_t i = em.loops().loopOffsets[0]; i < em.loops().loopOffsets[1]; ++i)
      onLoop = onLoop || em.vert()[em.loops().loopHalfedges[i]] == w;
    if (!onLoop) off = w;
  }
  ASSERT_NE(off, kInvalid);
  ASSERT_TRUE(em.setPosition(off, 1, 1, 3).ok());
  EXPECT_EQ(em.loops().loopPerimeter[0], moved);
  EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
  // With the loops stale (after an edit that changed the boundary) the move is seen when
  // they are numbered again.
  ASSERT_TRUE(em.removeTriangle(5).ok());
  ASSERT_TRUE(em.setPosition(v, 5, 0, 0).ok());
  EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
  Mesh m;
  ASSERT_TRUE(em.toMesh(m).ok());
  EXPECT_EQ(m.bboxMax[0], 5.0f);
  // Refused: out of range, non-finite; nothing changes.
  Snapshot before(em);
  EXPECT_EQ(em.setPosition(em.nVertices(), 0, 0, 0).code, Code::InvalidArgument);
  EXPECT_EQ(em.setPosition(v, 0, std::numeric_limits<float>::quiet_NaN(), 0).code, Code::InvalidArgument);
  EXPECT_EQ(em.setPosition(v, std::numeric_limits<float>::infinity(), 0, 0).code, Code::InvalidArgument);
  EXPECT_TRUE(Snapshot(em) == before);
  // A vertex that a collapse removed.
  EditableMesh tor;
  makeEditable(gen::torus(6, 5), tor);
  ASSERT_TRUE(tor.collapseEdge(0).ok());
  uint32_t dead = kInvalid;
  for (uint32_t w = 0; w < tor.nVertices(); ++w)
    if (!tor.vertexAlive(w)) dead = w;
  ASSERT_NE(dead, kInvalid);
  Snapshot torBefore(tor);
  EXPECT_EQ(tor.setPosition(dead, 0, 0, 0).code, Code::InvalidArgument);
  EXPECT_TRUE(Snapshot(tor) == torBefore);
}

TEST(Edit, CollapsingAnEdgeOfATetrahedronIsRefused) {
  EditableMesh em;
  makeEditable(tetrahedron(), em);
  ASSERT_TRUE(em.stats().watertight);
  for (uint32_t e = 0; e < em.nHalfedges(); ++e) {
    Snapshot before(em);
    Status st = em.collapseEdge(e);
    EXPECT_EQ(st.code, Code::EditRefused) << e;
    EXPECT_NE(st.message.find("edit-refused: "), std::string::npos);
    EXPECT_TRUE(Snapshot(em) == before);
  }
}

TEST(Edit, SplittingAnEdgeAddsOneVertexThreeEdgesTwoTriangles) {
  EditableMesh em;
  makeEditable(gen::torus(6, 5), em);
  EditStats before = em.stats();
  uint32_t m = kInvalid, a = em.vert()[0], b = em.vert()[1];
  ASSERT_TRUE(em.splitEdge(0, 0.25, &m).ok());
  EditStats after = em.stats();
  EXPECT_EQ(m, before.vertices);
  EXPECT_EQ(after.vertices, before.vertices + 1);
  EXPECT_EQ(after.edges, before.edges + 3);
  EXPECT_EQ(after.triangles, before.triangles + 2);
  EXPECT_EQ(after.eulerCharacteristic, 0);
  EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
  // The new vertex lies at a quarter of the edge.
  const float* p = em.positions().data();
  for (int k = 0; k < 3; ++k) EXPECT_FLOAT_EQ(p[3 * m + k], float(0.75 * p[3 * a + k] + 0.25 * p[3 * b + k]));
}

TEST(Edit, FlipKeepsTheCountsAndIsRefusedOnABoundary) {
  EditableMesh em;
  makeEditable(gen::torus(6, 5), em);
  EditStats before = em.stats();
  ASSERT_TRUE(em.flipEdge(0).ok());
  EXPECT_EQ(em.stats().edges, before.edges);
  EXPECT_EQ(em.stats().eulerCharacteristic, 0);
  EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
  // Flipping back restores the edge.
  ASSERT_TRUE(em.flipEdge(0).ok());
  EXPECT_EQ(editcheck::differenceFromRebuild(em), "");

  EditableMesh open;
  gen::Soup s = gen::cube();
  s.f.erase(s.f.begin());
  makeEditable(s, open);
  uint32_t b = open.loops().loopHalfedge[0];
  Snapshot snap(open);
  Status st = open.flipEdge(b);
  EXPECT_EQ(st.code, Code::EditRefused);
  st = open.flipEdge(b ^ 1u);
  EXPECT_EQ(st.code, Code::EditRefused);
  EXPECT_TRUE(Snapshot(open) == snap);
}

TEST(Edit, FlipIsRefusedWhenTheNewEdgeExists) {
  // Tetrahedron: the flipped edge of any edge joins the two other vertices, which are
  // joined already.
  EditableMesh em;
  makeEditable(tetrahedron(), em);
  Snapshot before(em);
  Status st = em.flipEdge(0);
  EXPECT_EQ(st.code, Code::EditRefused);
  EXPECT_NE(st.message.find("exists already"), std::string::npos);
  EXPECT_TRUE(Snapshot(em) == before);
}

TEST(Edit, CollapseOnATorusKeepsItATorusAndRefusedEditsChangeNothing) {
  EditableMesh em;
  makeEditable(gen::torus(8, 6), em);
  uint32_t keep = kInvalid, a = em.vert()[0], b = em.vert()[1];
  Status st = em.collapseEdge(0, 0.5, &keep);
  ASSERT_TRUE(st.ok()) << st.message;
  EXPECT_EQ(keep, a);
  EXPECT_FALSE(em.vertexAlive(b));
  EXPECT_EQ(em.stats().eulerCharacteristic, 0);
  EXPECT_TRUE(em.stats().watertight);
  EXPECT_TRUE(em.stats().manifold);
  EXPECT_EQ(em.stats().triangles, 8u * 6 * 2 - 2);
  EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
  // Dead ids are refused as invalid arguments, and change nothing.
  Snapshot before(em);
  uint32_t dead = kInvalid;
  for (uint32_t e = 0; e < em.nHalfedges() && dead == kInvalid; ++e)
    if (!em.halfedgeAlive(e)) dead = e;
  ASSERT_NE(dead, kInvalid);
  EXPECT_EQ(em.collapseEdge(dead).code, Code::InvalidArgument);
  EXPECT_EQ(em.removeTriangle(em.nTriangles()).code, Code::InvalidArgument);
  EXPECT_EQ(em.addTriangle(b, a, keep).code, Code::InvalidArgument);
  EXPECT_EQ(em.addTriangle(a, a, keep).code, Code::EditRefused);
  EXPECT_EQ(em.splitEdge(2, 1.0).code, Code::InvalidArgument);
  EXPECT_TRUE(Snapshot(em) == before);
}

TEST(Edit, AddTrianglePairsWithBoundarySidesAndRefusesNonManifoldEdges) {
  gen::Soup s = gen::cube();
  std::array<uint32_t, 3> removed = s.f[0];
  EditableMesh em;
  makeEditable(s, em);
  Mesh m;
  ASSERT_TRUE(em.toMesh(m).ok());
  uint32_t a = m.triangles[0], b = m.triangles[1], c = m.triangles[2];
  ASSERT_TRUE(em.removeTriangle(0).ok());
  (void)removed;
  // The same way round again closes it; the other way round is inconsistent.
  Snapshot before(em);
  Status st = em.addTriangle(a, c, b);
  EXPECT_EQ(st.code, Code::EditRefused);
  EXPECT_TRUE(Snapshot(em) == before);
  uint32_t t = kInvalid;
  ASSERT_TRUE(em.addTriangle(a, b, c, &t).ok());
  EXPECT_EQ(t, 12u);
  EXPECT_TRUE(em.stats().watertight);
  EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
  // A third triangle on a closed edge is non-manifold: refused unless asked for.
  uint32_t v;
  ASSERT_TRUE(em.addVertex(5, 5, 5, &v).ok());
  before = Snapshot(em);
  EXPECT_EQ(em.addTriangle(a, b, v).code, Code::EditRefused);
  EXPECT_TRUE(Snapshot(em) == before);
  ASSERT_TRUE(em.addTriangle(b, a, v, &t, true).ok());
  EXPECT_EQ(em.stats().nonManifoldEdges, 1u);
  EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
}

TEST(Edit, ReverseTriangleAndShell) {
  EditableMesh em;
  gen::Soup two = gen::cube();
  gen::append(two, gen::cube(3, 0, 0));
  makeEditable(two, em);
  ASSERT_TRUE(em.reverseTriangle(0).ok());
  EXPECT_EQ(em.stats().inconsistentEdges, 3u);
  EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
  ASSERT_TRUE(em.reverseTriangle(0).ok());
  EXPECT_TRUE(em.stats().watertight);
  ASSERT_TRUE(em.reverseShell(12).ok());
  EXPECT_TRUE(em.stats().watertight);
  EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
  Mesh m;
  ASSERT_TRUE(em.toMesh(m).ok());
  EXPECT_NEAR(m.volume, 0.0, 1e-12);  // one unit cube outward, one inward
  EXPECT_EQ(em.stats().shells, 2u);
}

// reverseTriangles(ids) is reverseTriangle of each id: the same triangles, counts, loops and
// kept normals (the half-edge slots may differ, as after any edit), checked against a rebuild;
// a bad list (a repeated, dead or out-of-range id) is refused and changes nothing.
TEST(Edit, ReverseTrianglesIsReverseTriangleOfEach) {
  gen::Soup soup = gen::torus(12, 10);
  gen::append(soup, gen::cube(30, 0, 0));
  EditableMesh one, many;
  makeEditable(soup, one);
  makeEditable(soup, many);
  for (EditableMesh* em : {&one, &many}) {
    std::vector<float> normals(3 * size_t(em->nTriangles()));
    for (size_t i = 0; i < normals.size(); ++i) normals[i] = float(i % 7) - 3.0f;
    ASSERT_TRUE(em->addAttribute(kAttrNormal, Element::Triangle, ValueType::F32, 3, normals.data()).ok());
  }
  // Neighbours (0, 1: their shared edge stays paired), a lone triangle, the cube's side, and an
  // order that is not increasing.
  const std::vector<uint32_t> ids = {41, 0, 1, 2, 17, 240, 241, 100};
  for (uint32_t t : ids) ASSERT_TRUE(one.reverseTriangle(t).ok());
  ASSERT_TRUE(many.reverseTriangles(ids.data(), uint32_t(ids.size())).ok());
  EXPECT_EQ(editcheck::differenceFromRebuild(many), "");
  EXPECT_EQ(one.infoJson("f"), many.infoJson("f"));
  Mesh a, b;
  ASSERT_TRUE(one.toMesh(a).ok());
  ASSERT_TRUE(many.toMesh(b).ok());
  ASSERT_EQ(a.triangles.size(), b.triangles.size());
  EXPECT_TRUE(std::equal(a.triangles.begin(), a.triangles.end(), b.triangles.begin()));
  ASSERT_EQ(a.normals.size(), b.normals.size());
  EXPECT_TRUE(std::equal(a.normals.begin(), a.normals.end(), b.normals.begin()));
  EXPECT_EQ(a.normals[3 * 41], -(float(123 % 7) - 3.0f));  // negated
  EXPECT_EQ(a.volume, b.volume);
  // Refused, and nothing changes.
  Snapshot before(many);
  const uint32_t twice[] = {5, 6, 5};
  EXPECT_EQ(many.reverseTriangles(twice, 3).code, Code::InvalidArgument);
  const uint32_t outOfRange[] = {5, many.nTriangles()};
  EXPECT_EQ(many.reverseTriangles(outOfRange, 2).code, Code::InvalidArgument);
  EXPECT_EQ(many.reverseTriangles(nullptr, 2).code, Code::InvalidArgument);
  EXPECT_TRUE(Snapshot(many) == before);
  ASSERT_TRUE(many.removeTriangle(7).ok());
  Snapshot removed(many);
  const uint32_t dead[] = {6, 7};
  EXPECT_EQ(many.reverseTriangles(dead, 2).code, Code::InvalidArgument);
  EXPECT_TRUE(Snapshot(many) == removed);
  EXPECT_TRUE(many.reverseTriangles(nullptr, 0).ok());
  EXPECT_TRUE(Snapshot(many) == removed);
}

// The editor numbers its loops as a fresh build does. It finds them from the edges that are
// not interior when they are few (a torus with holes and flipped faces, 1,600 triangles)
// and by scanning every side when they are many (a soup of separate triangles): both ways
// give a fresh build's loops, after edits that make them stale.
TEST(Edit, LoopsAreNumberedAsAFreshBuildWithFewOrManyBoundaryEdges) {
  gen::Soup few = gen::torus(40, 20, {5, 77, 300, 301, 302, 640, 1100});
  for (size_t t = 3; t < few.f.size(); t += 97) std::swap(few.f[t][1], few.f[t][2]);
  gen::Soup many;
  for (int i = 0; i < 300; ++i) {
    const float x = float(i % 20), y = float(i / 20);
    const uint32_t b = uint32_t(many.v.size());
    many.v.push_back({x, y, 0});
    many.v.push_back({x + 0.5f, y, 0});
    many.v.push_back({x, y + 0.5f, 0});
    many.f.push_back({b, b + 1, b + 2});
  }
  for (const gen::Soup* s : {&few, &many}) {
    EditableMesh em;
    makeEditable(*s, em);
    const uint32_t loops = em.loops().nLoops();
    EXPECT_GT(loops, s == &many ? 299u : 5u);
    ASSERT_TRUE(em.removeTriangle(9).ok());
    ASSERT_TRUE(em.removeTriangle(400 % em.nTriangles()).ok());
    const uint32_t r[] = {10, 11, 12};
    ASSERT_TRUE(em.reverseTriangles(r, 3).ok());
    EXPECT_EQ(editcheck::differenceFromRebuild(em), "") << (s == &many ? "soup" : "torus");
    EXPECT_GT(em.loops().nLoops(), 0u);
  }
}

// toMesh gives each solid its live triangles, in order, with an empty solid kept empty.
TEST(Edit, ToMeshKeepsEachSolidsTriangles) {
  Mesh m = readSoup(gen::cube());
  m.solids.clear();
  const char* names[] = {"a", "empty", "b", "c"};
  const uint32_t first[] = {0, 4, 4, 9}, count[] = {4, 0, 5, 3};
  for (int k = 0; k < 4; ++k) {
    Solid s;
    s.name = names[k];
    s.firstTriangle = first[k];
    s.triangleCount = count[k];
    m.solids.push_back(s);
  }
  EditableMesh em;
  ASSERT_TRUE(em.init(m).ok());
  ASSERT_TRUE(em.removeTriangle(0).ok());
  ASSERT_TRUE(em.removeTriangle(5).ok());
  ASSERT_TRUE(em.removeTriangle(6).ok());
  ASSERT_TRUE(em.removeTriangle(11).ok());
  Mesh out;
  ASSERT_TRUE(em.toMesh(out, nullptr, nullptr).ok());
  ASSERT_EQ(out.solids.size(), 4u);
  const uint32_t wantFirst[] = {0, 3, 3, 6}, wantCount[] = {3, 0, 3, 2};
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(out.solids[k].name, names[k]);
    EXPECT_EQ(out.solids[k].firstTriangle, wantFirst[k]) << k;
    EXPECT_EQ(out.solids[k].triangleCount, wantCount[k]) << k;
  }
  EXPECT_EQ(out.nTriangles(), 8u);
  // Triangle 1 (the first live one) comes first, triangle 4 starts solid b.
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(out.positions[3 * out.triangles[c]], m.positions[3 * m.triangles[3 + c]]);
    EXPECT_EQ(out.positions[3 * out.triangles[9 + c]], m.positions[3 * m.triangles[12 + c]]);
  }
}

// toMesh without the figures: the same arrays (kept normals too), solids and bbox, with area,
// volume and normal mismatches left 0.
TEST(Edit, ToMeshWithoutFiguresHasTheSameArrays) {
  ReadOptions ro;
  ro.keepNormals = true;
  Mesh m;
  ASSERT_TRUE(gen::read(gen::binary(gen::torus(6, 5, {4})), m, ro).ok());
  for (int k = 0; k < 3; ++k) m.normals[3 * 7 + k] = -m.normals[3 * 7 + k];  // against the winding
  EditableMesh em;
  ASSERT_TRUE(em.init(m).ok());
  ASSERT_TRUE(em.removeTriangle(2).ok());
  const uint32_t r[] = {3, 9};
  ASSERT_TRUE(em.reverseTriangles(r, 2).ok());
  Mesh with, without;
  ASSERT_TRUE(em.toMesh(with).ok());
  ASSERT_TRUE(em.toMesh(without, nullptr, nullptr, false, false).ok());
  ASSERT_FALSE(with.normals.empty());
  EXPECT_TRUE(gen::sameMesh(with, without));
  EXPECT_GT(with.area, 0);
  EXPECT_GT(with.normalMismatches, 0u);
  EXPECT_EQ(without.area, 0);
  EXPECT_EQ(without.volume, 0);
  EXPECT_EQ(without.normalMismatches, 0u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(without.bboxMin[k], with.bboxMin[k]);
    EXPECT_EQ(without.bboxMax[k], with.bboxMax[k]);
  }
  ASSERT_EQ(without.solids.size(), with.solids.size());
  EXPECT_EQ(without.solids[0].triangleCount, with.solids[0].triangleCount);
}

TEST(Edit, CompactRenumbersDenselyAndReturnsTheMaps) {
  EditableMesh em;
  makeEditable(gen::torus(6, 5), em);
  ASSERT_TRUE(em.removeTriangle(3).ok());
  ASSERT_TRUE(em.collapseEdge(em.triangleHalfedge()[20]).ok());
  uint32_t nt = em.stats().triangles;
  std::string before = em.infoJson("f");
  CompactMaps maps;
  ASSERT_TRUE(em.compact(&maps).ok());
  EXPECT_EQ(em.nTriangles(), nt);
  EXPECT_EQ(maps.triangles[3], kInvalid);
  EXPECT_EQ(maps.triangles[4], 3u);
  EXPECT_EQ(em.infoJson("f"), before);
  EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
}

TEST(Edit, AttributesFollowTheRules) {
  EditableMesh em;
  makeEditable(gen::torus(6, 5), em);
  const uint32_t nv = em.nVertices();
  std::vector<float> temp(nv);
  for (uint32_t v = 0; v < nv; ++v) temp[v] = float(v);
  AttributeRules avg;
  avg.merge = avg.split = Rule::Average;
  ASSERT_TRUE(em.addAttribute("temp", Element::Vertex, ValueType::F32, 1, temp.data(), avg).ok());
  std::vector<uint8_t> label(em.nTriangles(), 1);
  label[0] = 2;
  AttributeRules strict;
  strict.merge = strict.split = Rule::Fail;
  ASSERT_TRUE(em.addAttribute("label", Element::Triangle, ValueType::U8, 1, label.data(), strict).ok());
  uint32_t a = em.vert()[0], b = em.vert()[1], m;
  ASSERT_TRUE(em.splitEdge(0, 0.25, &m).ok());
  const float* t = static_cast<const float*>(em.attribute("temp")->data);
  EXPECT_FLOAT_EQ(t[m], 0.75f * float(a) + 0.25f * float(b));
  // Triangle 0 (label 2) and its neighbour across edge 0 (label 1): a flip must merge them,
  // which "fail" refuses; collapse merges vertices only.
  uint32_t e = em.triangleHalfedge()[0];
  Snapshot before(em);
  bool refusedOne = false;
  for (int k = 0; k < 3; ++k, e = em.next()[e]) {
    Status s = em.flipEdge(e);
    if (s.code == Code::EditRefused && s.message.find("label") != std::string::npos) refusedOne = true;
    if (s.ok()) break;
  }
  EXPECT_TRUE(refusedOne);
  // A custom rule: the merge keeps the larger value.
  AttributeRules custom;
  custom.merge = Rule::Custom;
  custom.mergeFn = [](const double* x, const double* y, double, double* out, uint32_t n) {
    for (uint32_t k = 0; k < n; ++k) out[k] = std::max(x[k], y[k]);
    return true;
  };
  ASSERT_TRUE(em.addAttribute("temp", Element::Vertex, ValueType::F32, 1, nullptr, custom).ok());
  float* tv = static_cast<float*>(em.attribute("temp")->data);
  for (uint32_t v = 0; v < em.nVertices(); ++v) tv[v] = float(v);
  uint32_t e2 = em.triangleHalfedge()[10];
  uint32_t x = em.vert()[e2], y = em.vert()[e2 ^ 1u], keep;
  ASSERT_TRUE(em.collapseEdge(e2, 0.5, &keep).ok());
  EXPECT_EQ(keep, x);
  EXPECT_FLOAT_EQ(static_cast<const float*>(em.attribute("temp")->data)[keep], float(std::max(x, y)));
  EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
}

TEST(Edit, ColoursAndAttributeWordsSurviveEditsAndCompaction) {
  gen::Soup s = gen::cube();
  s.attr.assign(12, 0);
  for (int t = 0; t < 12; ++t) s.attr[t] = uint16_t(0x8000 | (t << 10) | 0x1F);  // VisCAM colours
  Mesh m = readSoup(s);
  ASSERT_EQ(m.colorConvention, ColorConvention::VisCam);
  EditableMesh em;
  ASSERT_TRUE(em.init(m).ok());
  ASSERT_TRUE(em.removeTriangle(0).ok());
  ASSERT_TRUE(em.compact().ok());
  Mesh out;
  ASSERT_TRUE(em.toMesh(out).ok());
  ASSERT_EQ(out.nTriangles(), 11u);
  EXPECT_EQ(out.colorConvention, ColorConvention::VisCam);
  for (uint32_t t = 0; t < 11; ++t) {
    EXPECT_EQ(out.attributes[t], m.attributes[t + 1]);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(out.colors[3 * t + k], m.colors[3 * (t + 1) + k]);
    EXPECT_EQ(out.colorValid[t], m.colorValid[t + 1]);
  }
}

// ---------------------------------------------------------------------------
// Randomized edit sequences. Each edit is checked: a refused edit changed nothing; a done
// edit leaves validate() holding and a topology equal, array by array, to buildTopology of
// the compacted mesh. The seed is printed on failure; STLTOPO_EDIT_SEED=<n> reruns one.

namespace {

struct Rng {
  std::mt19937_64 g;
  uint32_t operator()(uint32_t n) { return n == 0 ? 0 : uint32_t(g() % n); }
};

void runRandomEdits(const std::string& name, const Mesh& mesh, uint64_t seed, uint32_t nEdits, uint32_t checkEvery,
                    double tolerance = 0) {
  EditableMesh em;
  TopologyOptions o;
  o.tolerance = tolerance;
  Status s = em.init(mesh, o);
  ASSERT_TRUE(s.ok()) << s.message;
  Rng rng{std::mt19937_64(seed)};
  editcheck::RandomEditor<Rng> ed(em, rng);
  for (uint32_t i = 0; i < nEdits; ++i) {
    std::string what;
    std::string d = ed.step(what, (i + 1) % checkEvery == 0);
    ASSERT_EQ(d, "") << name << ": seed " << seed << ", edit " << i << " (" << what << ")";
  }
  ASSERT_EQ(editcheck::differenceFromRebuild(em), "") << name << ": seed " << seed << " at the end";
  EXPECT_GT(ed.done(), nEdits / 10) << name << ": too few edits were done";
}

uint64_t seedFor(uint64_t base) {
  const char* env = std::getenv("STLTOPO_EDIT_SEED");
  return env ? std::strtoull(env, nullptr, 10) : base;
}

Mesh readFixture(const std::string& rel) {
  Mesh m;
  std::string bytes = gen::readFile(gen::fixturePath(rel));
  Status s = gen::read(bytes, m);
  EXPECT_TRUE(s.ok()) << rel << ": " << s.message;
  return m;
}

}  // namespace

TEST(EditRandom, GeneratedMeshesEveryEditChecked) {
  gen::Soup torus = gen::torus(7, 5, {3, 11, 12});
  gen::Soup cubes = gen::cube();
  gen::append(cubes, gen::cube(1, 0, 0));  // two cubes sharing a side: non-manifold edges
  gen::Soup pinched = gen::cube();
  gen::append(pinched, gen::cube(1, 1, 1));  // touching at a corner: a non-manifold vertex
  const std::pair<const char*, gen::Soup> cases[] = {
      {"torus with holes", torus}, {"two cubes", cubes}, {"pinched", pinched}};
  for (const auto& c : cases)
    for (uint64_t k = 0; k < 4; ++k) runRandomEdits(c.first, readSoup(c.second), seedFor(1000 + k), 600, 1);
}

TEST(EditRandom, FixturesClosedOpenAndBroken) {
  const char* small[] = {
      "wolph_numpy-stl/tests/stl_binary/Moon.stl",    // closed
      "hmeyer_stl_io/src/testdata/bunny_99.stl",      // open
      "wolph_numpy-stl/tests/stl_tests/triamid.stl",  // inconsistent edges, seams
      "mikedh_trimesh/models/shared.STL",             // a non-manifold edge
      "mikedh_trimesh/models/multibody.stl",          // inconsistent shells
      "mikedh_trimesh/models/soup.stl",               // separate triangles
  };
  for (const char* f : small) {
    Mesh m = readFixture(f);
    for (uint64_t k = 0; k < 2; ++k) runRandomEdits(f, m, seedFor(2000 + k), 1000, 1);
  }
  const char* larger[] = {
      "assimp_assimp/test/models/STL/sphereWithHole.stl",  // open, non-manifold vertices
      "assimp_assimp/test/models/STL/Spider_binary.stl",   // degenerate and inconsistent
      "assimp_assimp/test/models/STL/3DSMaxExport.STL",    // non-manifold edges
  };
  for (const char* f : larger) runRandomEdits(f, readFixture(f), seedFor(3000), 2000, 50);
}

TEST(EditRandom, ToleranceWeldedFixture) {
  Mesh m = readFixture("assimp_assimp/test/models/STL/Spider_binary.stl");
  runRandomEdits("Spider tolerance 0.01", m, seedFor(4000), 1000, 10, 0.01);
}
