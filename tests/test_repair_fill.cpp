// The fill-holes repair step (src/repair/fill_holes.cpp), run directly on an EditableMesh:
// holes filled where they can be, skipped with the reason where not (limits, seams,
// non-manifold inner edges, fold-over), the result checked against a fresh build and the
// exact intersection pass; the minimum-weight triangulation against a fan; refinement and
// fairing. Also the exact normalsDot predicate the fold-over check uses.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "edit_check.h"
#include "predicates.h"
#include "repair/steps.h"
#include "stl_gen.h"
#include "stltopo/geometry.h"
#include "stltopo/repair.h"

using namespace stltopo;

namespace {

void makeEditable(const gen::Soup& s, EditableMesh& em) {
  Mesh m;
  Status st = gen::read(gen::binary(s), m);
  ASSERT_TRUE(st.ok()) << st.message;
  st = em.init(m);
  ASSERT_TRUE(st.ok()) << st.message;
}

struct FillRun {
  RepairOptions options;
  RepairStepPlan plan;
  Status status;
};

FillRun fill(EditableMesh& em, RepairOptions o = {}) {
  FillRun r;
  r.options = std::move(o);
  r.plan.kind = RepairStepKind::FillHoles;
  repair_detail::StepContext ctx{em, r.options, r.plan};
  r.status = repair_detail::runFillHoles(ctx);
  return r;
}

// (RepairStepPlan::nSkipped is the runner's, src/repair/repair.cpp.)
uint32_t skippedItems(const RepairStepPlan& plan) {
  uint32_t n = 0;
  for (const RepairItem& it : plan.items) n += it.skipped;
  return n;
}

std::string describe(const RepairStepPlan& plan) {
  std::string out;
  for (const RepairItem& it : plan.items) out += it.action + (it.skipped ? " [skipped: " + it.reason + "]" : "") + "\n";
  return out;
}

// The number of intersecting pairs of the compacted mesh (the exact intersection pass).
uint64_t intersectingPairs(const EditableMesh& em) {
  Mesh m;
  EXPECT_TRUE(em.toMesh(m).ok());
  Topology t;
  TopologyOptions o;
  o.triangleShell = true;
  EXPECT_TRUE(buildTopology(m, t, o).ok());
  GeometryReport g;
  Status s = analyzeGeometry(m, t, g);
  EXPECT_TRUE(s.ok()) << s.message;
  return g.intersections.nPairs();
}

// A box [0, n] x [0, n] x [-1, 0] whose top is an n x n grid of unit squares (the cells in
// `holes`, as y * n + x, left out) and whose bottom is one such grid; the walls are strips.
gen::Soup gridBox(int n, const std::vector<int>& holes, float zTop = 0) {
  gen::Soup s;
  auto top = [&](int x, int y) { return uint32_t(y * (n + 1) + x); };
  auto bot = [&](int x, int y) { return uint32_t((n + 1) * (n + 1) + y * (n + 1) + x); };
  for (int layer = 0; layer < 2; ++layer)
    for (int y = 0; y <= n; ++y)
      for (int x = 0; x <= n; ++x) s.v.push_back({float(x), float(y), layer == 0 ? zTop : -1.0f});
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      if (std::find(holes.begin(), holes.end(), y * n + x) == holes.end()) {
        s.f.push_back({top(x, y), top(x + 1, y), top(x + 1, y + 1)});
        s.f.push_back({top(x, y), top(x + 1, y + 1), top(x, y + 1)});
      }
      s.f.push_back({bot(x, y), bot(x + 1, y + 1), bot(x + 1, y)});
      s.f.push_back({bot(x, y), bot(x, y + 1), bot(x + 1, y + 1)});
    }
  // The rim counter-clockwise seen from above; the wall of edge p -> q is (q, p, p'), (q, p', q').
  std::vector<std::pair<int, int>> rim;
  for (int x = 0; x < n; ++x) rim.push_back({x, 0});
  for (int y = 0; y < n; ++y) rim.push_back({n, y});
  for (int x = n; x > 0; --x) rim.push_back({x, n});
  for (int y = n; y > 0; --y) rim.push_back({0, y});
  for (size_t i = 0; i < rim.size(); ++i) {
    auto [px, py] = rim[i];
    auto [qx, qy] = rim[(i + 1) % rim.size()];
    s.f.push_back({top(qx, qy), top(px, py), bot(px, py)});
    s.f.push_back({top(qx, qy), bot(px, py), bot(qx, qy)});
  }
  return s;
}

// A cup: a disc at z = 0 and a wall up to a rim of radius r at z = height + h cos 2θ (a
// saddle-shaped rim, the one hole).
gen::Soup cup(int n, float h, float r = 1, float height = 2) {
  gen::Soup s;
  const double pi = 3.14159265358979323846;
  s.v.push_back({0, 0, 0});
  for (int i = 0; i < n; ++i) s.v.push_back({float(std::cos(2 * pi * i / n)), float(std::sin(2 * pi * i / n)), 0});
  for (int i = 0; i < n; ++i) {
    double a = 2 * pi * i / n;
    s.v.push_back({float(r * std::cos(a)), float(r * std::sin(a)), float(height + h * std::cos(2 * a))});
  }
  auto b = [&](int i) { return uint32_t(1 + (i % n)); };
  auto t = [&](int i) { return uint32_t(1 + n + (i % n)); };
  for (int i = 0; i < n; ++i) {
    s.f.push_back({0, b(i + 1), b(i)});
    s.f.push_back({b(i), b(i + 1), t(i + 1)});
    s.f.push_back({b(i), t(i + 1), t(i)});
  }
  return s;
}

// Per triangle of `em` not in the first `keep` slots: the smallest cos of the angle between
// its normal and a neighbour's across any of its edges (the worst dihedral of the patch).
double worstCosOfNewTriangles(EditableMesh& em, uint32_t keep) {
  const Array<float>& P = em.positions();
  const Array<uint32_t>& T = em.triangles();
  auto normal = [&](uint32_t t, double* n) {
    const float* a = &P[3 * T[3 * t]];
    const float* b = &P[3 * T[3 * t + 1]];
    const float* c = &P[3 * T[3 * t + 2]];
    double u[3] = {double(b[0]) - a[0], double(b[1]) - a[1], double(b[2]) - a[2]};
    double v[3] = {double(c[0]) - a[0], double(c[1]) - a[1], double(c[2]) - a[2]};
    n[0] = u[1] * v[2] - u[2] * v[1];
    n[1] = u[2] * v[0] - u[0] * v[2];
    n[2] = u[0] * v[1] - u[1] * v[0];
    double l = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int k = 0; k < 3; ++k) n[k] /= l;
  };
  double worst = 1;
  for (uint32_t t = keep; t < em.nTriangles(); ++t) {
    if (!em.triangleAlive(t)) continue;
    double n[3], m[3];
    normal(t, n);
    uint32_t e = em.triangleHalfedge()[t];
    for (int k = 0; k < 3; ++k, e = em.next()[e]) {
      uint32_t f = em.face(e ^ 1u);
      if (f >= em.nTriangles()) continue;
      normal(f, m);
      worst = std::min(worst, n[0] * m[0] + n[1] * m[1] + n[2] * m[2]);
    }
  }
  return worst;
}

std::vector<float> positionsOf(const EditableMesh& em) { return {em.positions().begin(), em.positions().end()}; }

}  // namespace

TEST(RepairFill, CubeWithAHoleComesBackWatertightWithVolumeOne) {
  EditableMesh em;
  makeEditable(gen::cube(), em);
  ASSERT_TRUE(em.removeTriangle(0).ok());
  ASSERT_TRUE(em.removeTriangle(1).ok());
  ASSERT_EQ(em.stats().holes, 1u);
  FillRun r = fill(em);
  ASSERT_TRUE(r.status.ok()) << r.status.message;
  ASSERT_EQ(r.plan.items.size(), 1u);
  const RepairItem& it = r.plan.items[0];
  EXPECT_FALSE(it.skipped) << it.reason;
  EXPECT_EQ(it.action.rfind("fill hole 0 (4 edges) with 2 triangles", 0), 0u) << it.action;
  EXPECT_EQ(it.loops, std::vector<uint32_t>{0});
  EXPECT_EQ(it.vertices.size(), 4u);
  EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
  EXPECT_TRUE(em.stats().watertight);
  EXPECT_EQ(em.stats().eulerCharacteristic, 2);
  Mesh m;
  ASSERT_TRUE(em.toMesh(m).ok());
  EXPECT_NEAR(m.volume, 1.0, 1e-12);
}

TEST(RepairFill, AMissingFaceAtASharpEdgeIsPutBack) {
  // A tetrahedron without one face: its faces turn by more than 90 degrees at every edge,
  // so the hole's only fill (the face) failed the fold-over angle once. It is put back.
  gen::Soup s;
  s.v = {{0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {1, 1, 1}};
  s.f = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}};
  for (int missing = 0; missing < 4; ++missing) {
    gen::Soup t = s;
    t.f.erase(t.f.begin() + missing);
    EditableMesh em;
    makeEditable(t, em);
    ASSERT_EQ(em.stats().holes, 1u);
    FillRun r = fill(em);
    ASSERT_TRUE(r.status.ok()) << r.status.message;
    ASSERT_EQ(r.plan.items.size(), 1u);
    EXPECT_FALSE(r.plan.items[0].skipped) << missing << ": " << r.plan.items[0].reason;
    EXPECT_TRUE(em.stats().watertight);
    EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
    Mesh m;
    ASSERT_TRUE(em.toMesh(m).ok());
    EXPECT_EQ(m.volume, 16.0 / 6) << missing;  // the tetrahedron's own (4 * 4 / 2 * 1 / 3)
  }
}

TEST(RepairFill, TorusWithHolesIsFilledEverywhereWithoutCrossings) {
  // Separate holes of one, two and three quads and one of a row of four.
  EditableMesh em;
  makeEditable(gen::torus(32, 16, {5, 40, 41, 100, 101, 116, 300, 301, 302, 303}), em);
  const uint32_t holes = em.stats().holes;
  ASSERT_EQ(holes, 4u);
  const uint32_t before = em.nTriangles();
  FillRun r = fill(em);
  ASSERT_TRUE(r.status.ok()) << r.status.message;
  ASSERT_EQ(r.plan.items.size(), holes);
  EXPECT_EQ(skippedItems(r.plan), 0u) << describe(r.plan);
  EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
  const EditStats& st = em.stats();
  EXPECT_EQ(st.holes, 0u);
  EXPECT_TRUE(st.watertight);
  EXPECT_TRUE(st.manifold);
  EXPECT_EQ(st.eulerCharacteristic, 0);  // still a torus
  EXPECT_EQ(intersectingPairs(em), 0u);
  EXPECT_GT(worstCosOfNewTriangles(em, before), 0.0);
}

TEST(RepairFill, LimitsSkipWithTheFigures) {
  // A 2 x 2 hole (8 edges, perimeter 8, area 4) and a one-cell hole (4 edges, perimeter 4, area 1).
  const gen::Soup box = gridBox(8, {0 * 8 + 5, 5 * 8 + 1, 5 * 8 + 2, 6 * 8 + 1, 6 * 8 + 2});
  struct Case {
    const char* name;
    RepairOptions o;
    const char* reason;
  };
  std::vector<Case> cases(3);
  cases[0] = {"edges", {}, "8 edges, over the limit of 6 (maxHoleEdges)"};
  cases[0].o.maxHoleEdges = 6;
  cases[1] = {"perimeter", {}, "perimeter 8, over the limit of 5 (maxHolePerimeter)"};
  cases[1].o.maxHolePerimeter = 5;
  cases[2] = {"area", {}, "the fill's area 4 is over the limit of 2.5 (maxHoleArea)"};
  cases[2].o.maxHoleArea = 2.5;
  for (const Case& c : cases) {
    EditableMesh em;
    makeEditable(box, em);
    ASSERT_EQ(em.stats().holes, 2u);
    FillRun r = fill(em, c.o);
    ASSERT_TRUE(r.status.ok()) << r.status.message;
    ASSERT_EQ(r.plan.items.size(), 2u) << c.name;
    uint32_t skipped = 0;
    for (const RepairItem& it : r.plan.items)
      if (it.skipped) {
        ++skipped;
        EXPECT_EQ(it.reason, c.reason) << c.name;
        EXPECT_NE(it.action.find("(8 edges)"), std::string::npos) << c.name << ": " << it.action;
      } else {
        EXPECT_NE(it.action.find("(4 edges) with 2 triangles"), std::string::npos) << c.name << ": " << it.action;
      }
    EXPECT_EQ(skipped, 1u) << c.name << "\n" << describe(r.plan);
    EXPECT_EQ(em.stats().holes, 1u) << c.name;
    EXPECT_EQ(editcheck::differenceFromRebuild(em), "") << c.name;
  }
  // Exactly at the limits: filled.
  RepairOptions o;
  o.maxHoleEdges = 8;
  o.maxHolePerimeter = 8;
  o.maxHoleArea = 4;
  EditableMesh em;
  makeEditable(box, em);
  FillRun r = fill(em, o);
  ASSERT_TRUE(r.status.ok());
  EXPECT_EQ(skippedItems(r.plan), 0u) << describe(r.plan);
  EXPECT_TRUE(em.stats().watertight);
}

TEST(RepairFill, LeftOutItemsAreSkippedAndUnchanged) {
  EditableMesh em;
  makeEditable(gridBox(6, {1, 4 * 6 + 4}), em);
  ASSERT_EQ(em.stats().holes, 2u);
  RepairOptions o;
  o.exclude.push_back({RepairStepKind::FillHoles, 1});
  FillRun r = fill(em, o);
  ASSERT_TRUE(r.status.ok());
  ASSERT_EQ(r.plan.items.size(), 2u);
  EXPECT_FALSE(r.plan.items[0].skipped);
  EXPECT_TRUE(r.plan.items[1].skipped);
  EXPECT_EQ(r.plan.items[1].reason, "left out by the user");
  EXPECT_EQ(em.stats().holes, 1u);
}

TEST(RepairFill, SaddleShapedHoleFillsWithoutFoldOverOrCrossing) {
  for (float h : {0.3f, 0.8f, 1.5f}) {
    EditableMesh em;
    makeEditable(cup(24, h), em);
    ASSERT_EQ(em.stats().holes, 1u);
    const uint32_t before = em.nTriangles();
    FillRun r = fill(em);
    ASSERT_TRUE(r.status.ok());
    ASSERT_EQ(r.plan.items.size(), 1u);
    EXPECT_FALSE(r.plan.items[0].skipped) << h << ": " << r.plan.items[0].reason;
    EXPECT_NE(r.plan.items[0].action.find("with 22 triangles (minimum weight)"), std::string::npos)
        << r.plan.items[0].action;
    EXPECT_TRUE(em.stats().watertight);
    EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
    EXPECT_EQ(intersectingPairs(em), 0u) << h;
    EXPECT_GT(worstCosOfNewTriangles(em, before), 0.0) << h;
    // Every new triangle faces up-ish (out of the cup), none folds into it.
    Mesh m;
    ASSERT_TRUE(em.toMesh(m).ok());
    EXPECT_GT(m.volume, 0);
  }
}

TEST(RepairFill, AFillThatWouldMakeANonManifoldEdgeIsSkippedAndChangesNothing) {
  // A tetrahedron a b c d without faces a-b-c and a-c-d: the hole a-b-c-d has diagonals a-c
  // and b-d. b-d exists (faces a-b-d, b-c-d); a triangle a-c-e adds a-c. Both fills of the
  // hole would put an inner edge on an existing edge. The triangle's own loop would fill it
  // with its reverse (folded over).
  gen::Soup s;
  s.v = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {-1, -1, 2}};
  // a = 0, b = 1, c = 2, d = 3, e = 4.
  s.f = {{0, 1, 3}, {1, 2, 3}, {0, 2, 4}};
  EditableMesh em;
  makeEditable(s, em);
  ASSERT_EQ(em.loops().nLoops(), 2u);
  editcheck::Snapshot before(em);
  FillRun r = fill(em);
  ASSERT_TRUE(r.status.ok());
  ASSERT_EQ(r.plan.items.size(), 2u);
  bool sawNonManifold = false, sawFold = false;
  for (const RepairItem& it : r.plan.items) {
    EXPECT_TRUE(it.skipped) << it.action;
    sawNonManifold |= it.reason == "every triangulation would put a new inner edge on an existing edge (non-manifold)";
    sawFold |= it.reason.find("fold over") != std::string::npos;
  }
  EXPECT_TRUE(sawNonManifold) << describe(r.plan);
  EXPECT_TRUE(sawFold) << describe(r.plan);
  EXPECT_TRUE(editcheck::Snapshot(em) == before);
}

TEST(RepairFill, AFillThatWouldCrossTheMeshIsSkippedAndChangesNothing) {
  // A small cube stands in the hole of the top, through its plane: any fill of the hole
  // (flat, in the plane z = 0) would cut the cube's sides.
  gen::Soup s = gridBox(6, {2 * 6 + 2, 2 * 6 + 3, 3 * 6 + 2, 3 * 6 + 3});
  gen::append(s, gen::cube(2.75f, 2.75f, -0.25f, 0.5f));
  for (bool refine : {false, true}) {
    EditableMesh em;
    makeEditable(s, em);
    ASSERT_EQ(em.stats().holes, 1u);
    ASSERT_EQ(intersectingPairs(em), 0u);
    editcheck::Snapshot before(em);
    RepairOptions o;
    o.fillRefine = refine;
    FillRun r = fill(em, o);
    ASSERT_TRUE(r.status.ok());
    ASSERT_EQ(r.plan.items.size(), 1u);
    EXPECT_TRUE(r.plan.items[0].skipped);
    EXPECT_EQ(r.plan.items[0].reason.rfind("the fill would cross the mesh (new triangle (", 0), 0u)
        << r.plan.items[0].reason;
    EXPECT_TRUE(editcheck::Snapshot(em) == before);
  }
  // Lowered under the top, the cube is out of the way.
  gen::Soup t = gridBox(6, {2 * 6 + 2, 2 * 6 + 3, 3 * 6 + 2, 3 * 6 + 3});
  gen::append(t, gen::cube(2.75f, 2.75f, -0.75f, 0.5f));
  EditableMesh em;
  makeEditable(t, em);
  FillRun r = fill(em);
  ASSERT_TRUE(r.status.ok());
  EXPECT_FALSE(r.plan.items[0].skipped) << r.plan.items[0].reason;
  EXPECT_TRUE(em.stats().watertight);
}

// The fill step's cell grid (fill_holes.cpp, CellGrid) only spares the query of the loops'
// boxes for triangles far from every loop: with and without it, the same plan and the same
// mesh, on boxes whose top has random holes (more than the 16 loops from which the step
// makes a grid) with small cubes standing in and around them (fills that would cross a cube
// are skipped).
TEST(RepairFill, TheCellGridChangesNoFill) {
  std::mt19937 rng(50);
  uint32_t crossed = 0, filled = 0;
  for (int round = 0; round < 40; ++round) {
    const int n = 16 + int(rng() % 5);
    std::vector<int> holes;
    for (int k = 0; k < 40; ++k) holes.push_back(int(rng() % uint32_t(n * n)));
    gen::Soup s = gridBox(n, holes);
    for (int k = 0; k < 40; ++k) {
      const float size = 0.2f + 0.1f * float(rng() % 5);
      gen::append(s, gen::cube(float(rng() % uint32_t(4 * n)) / 4, float(rng() % uint32_t(4 * n)) / 4,
                               -0.1f * float(rng() % 8), size));
    }
    std::string plan[2];
    std::vector<editcheck::Snapshot> after;
    for (int grid = 0; grid < 2; ++grid) {
      repair_detail::setFillCellGridForTesting(grid == 1);
      EditableMesh em;
      makeEditable(s, em);
      ASSERT_GT(em.stats().holes, 16u);
      FillRun r = fill(em);
      ASSERT_TRUE(r.status.ok()) << r.status.message;
      plan[grid] = describe(r.plan);
      after.emplace_back(em);
      if (grid == 1)
        for (const RepairItem& it : r.plan.items) {
          crossed += it.skipped && it.reason.rfind("the fill would cross the mesh", 0) == 0;
          filled += !it.skipped;
        }
    }
    repair_detail::setFillCellGridForTesting(true);
    EXPECT_EQ(plan[1], plan[0]) << "round " << round;
    EXPECT_TRUE(after[1] == after[0]) << "round " << round;
  }
  EXPECT_GE(crossed, 10u);
  EXPECT_GE(filled, 10u);
}

TEST(RepairFill, SeamsAreSkipped) {
  // Three triangles on one edge: its loops have cut sides.
  gen::Soup s;
  s.v = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  s.f = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  EditableMesh em;
  makeEditable(s, em);
  ASSERT_GT(em.stats().seams, 0u);
  editcheck::Snapshot before(em);
  FillRun r = fill(em);
  ASSERT_TRUE(r.status.ok());
  uint32_t seams = 0;
  for (const RepairItem& it : r.plan.items)
    if (it.skipped && it.reason.rfind("a seam", 0) == 0) ++seams;
  EXPECT_EQ(seams, em.stats().seams) << describe(r.plan);
}

TEST(RepairFill, ALoopThroughAVertexTwiceIsCutIntoSimpleParts) {
  // Two cells of the top grid touching at one corner: one loop through that vertex twice.
  EditableMesh em;
  makeEditable(gridBox(4, {1 * 4 + 1, 2 * 4 + 2}), em);
  ASSERT_EQ(em.loops().nLoops(), 1u);
  ASSERT_EQ(em.loops().loopOffsets[1], 8u);
  FillRun r = fill(em);
  ASSERT_TRUE(r.status.ok());
  ASSERT_EQ(r.plan.items.size(), 1u);
  EXPECT_FALSE(r.plan.items[0].skipped) << r.plan.items[0].reason;
  EXPECT_NE(r.plan.items[0].action.find("(8 edges) with 4 triangles"), std::string::npos) << r.plan.items[0].action;
  EXPECT_TRUE(em.stats().watertight);
  EXPECT_TRUE(em.stats().manifold);
  EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
  Mesh m;
  ASSERT_TRUE(em.toMesh(m).ok());
  EXPECT_NEAR(m.volume, 16.0, 1e-9);
}

TEST(RepairFill, MinimumWeightBeatsAFanOnANonConvexHole) {
  // A U-shaped hole in the flat top: cells (1..5, 1), (1, 2..4) and (5, 2..4).
  std::vector<int> u;
  const int n = 7;
  for (int x = 1; x <= 5; ++x) u.push_back(1 * n + x);
  for (int y = 2; y <= 4; ++y) u.push_back(y * n + 1), u.push_back(y * n + 5);
  const gen::Soup box = gridBox(n, u);
  // The fan from the loop's first vertex.
  EditableMesh fan;
  makeEditable(box, fan);
  ASSERT_EQ(fan.stats().holes, 1u);
  const uint32_t before = fan.nTriangles();
  ASSERT_TRUE(fan.fillLoop(0, FillMethod::Fan).ok());
  const double fanWorst = worstCosOfNewTriangles(fan, before);
  const uint64_t fanCrossings = intersectingPairs(fan);
  // The step.
  EditableMesh mw;
  makeEditable(box, mw);
  FillRun r = fill(mw);
  ASSERT_TRUE(r.status.ok());
  ASSERT_EQ(r.plan.items.size(), 1u);
  EXPECT_FALSE(r.plan.items[0].skipped) << r.plan.items[0].reason;
  EXPECT_TRUE(mw.stats().watertight);
  EXPECT_EQ(editcheck::differenceFromRebuild(mw), "");
  const double mwWorst = worstCosOfNewTriangles(mw, before);
  // The fan folds (some new triangle faces down against its neighbour) and crosses the
  // mesh; minimum weight stays flat: every new triangle faces up, and the area is the hole's.
  EXPECT_LT(fanWorst, 0.0);
  EXPECT_GT(fanCrossings, 0u);
  EXPECT_EQ(mwWorst, 1.0);
  EXPECT_EQ(intersectingPairs(mw), 0u);
  Mesh m;
  ASSERT_TRUE(mw.toMesh(m).ok());
  EXPECT_NEAR(m.area, 2 * 49.0 + 4 * 7.0, 1e-9);
  EXPECT_NEAR(m.volume, 49.0, 1e-9);
}

TEST(RepairFill, LongLoopsAreFilledByEarClipping) {
  // A round hole of 240 edges (a cup with a flat rim) and a square one of 4 x 51 = 204 edges
  // with collinear runs: both over the minimum-weight cap of 200.
  EditableMesh round;
  makeEditable(cup(240, 0), round);
  FillRun r = fill(round);
  ASSERT_TRUE(r.status.ok());
  ASSERT_EQ(r.plan.items.size(), 1u);
  EXPECT_FALSE(r.plan.items[0].skipped) << r.plan.items[0].reason;
  EXPECT_EQ(r.plan.items[0].action, "fill hole 0 (240 edges) with 238 triangles (ear clipping)");
  EXPECT_TRUE(round.stats().watertight);
  EXPECT_EQ(editcheck::differenceFromRebuild(round), "");
  EXPECT_EQ(intersectingPairs(round), 0u);
  std::vector<int> cells;
  for (int y = 1; y < 52; ++y)
    for (int x = 1; x < 52; ++x) cells.push_back(y * 53 + x);
  EditableMesh square;
  makeEditable(gridBox(53, cells), square);
  r = fill(square);
  ASSERT_TRUE(r.status.ok());
  ASSERT_EQ(r.plan.items.size(), 1u);
  EXPECT_FALSE(r.plan.items[0].skipped) << r.plan.items[0].reason;
  EXPECT_EQ(r.plan.items[0].action, "fill hole 0 (204 edges) with 202 triangles (ear clipping)");
  EXPECT_TRUE(square.stats().watertight);
  EXPECT_EQ(editcheck::differenceFromRebuild(square), "");
  EXPECT_EQ(intersectingPairs(square), 0u);
  // Under the cap, the same square hole by minimum weight.
  cells.clear();
  for (int y = 1; y < 50; ++y)
    for (int x = 1; x < 50; ++x) cells.push_back(y * 51 + x);
  EditableMesh smaller;
  makeEditable(gridBox(51, cells), smaller);
  r = fill(smaller);
  ASSERT_TRUE(r.status.ok());
  EXPECT_EQ(r.plan.items[0].action, "fill hole 0 (196 edges) with 194 triangles (minimum weight)");
  EXPECT_EQ(intersectingPairs(smaller), 0u);
}

TEST(RepairFill, WhenEarClippingFailsALongLoopGetsMinimumWeight) {
  // A saddle rim of 240 edges: ear clipping in the Newell plane folds over at the rim, so the
  // loop (under the fallback cap of 600) is triangulated by minimum weight after all.
  EditableMesh em;
  makeEditable(cup(240, 1.5f), em);
  const uint32_t before = em.nTriangles();
  FillRun r = fill(em);
  ASSERT_TRUE(r.status.ok());
  ASSERT_EQ(r.plan.items.size(), 1u);
  EXPECT_FALSE(r.plan.items[0].skipped) << r.plan.items[0].reason;
  EXPECT_EQ(r.plan.items[0].action,
            "fill hole 0 (240 edges) with 238 triangles (minimum weight, as ear clipping failed the checks)");
  EXPECT_TRUE(em.stats().watertight);
  EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
  EXPECT_EQ(intersectingPairs(em), 0u);
  EXPECT_GT(worstCosOfNewTriangles(em, before), 0.0);
  // The ear-clipped fan itself folds: filled by the editor's ear clipping, some new
  // triangle's normal turns by more than 90 degrees against a neighbour.
  EditableMesh ears;
  makeEditable(cup(240, 1.5f), ears);
  ASSERT_TRUE(ears.fillLoop(0, FillMethod::Ear).ok());
  EXPECT_LT(worstCosOfNewTriangles(ears, before), 0.0);
}

TEST(RepairFill, RefineMakesEdgesNearTheLoopsEdgeLength) {
  // An 8 x 8 hole of unit cells in a 12 x 12 top: loop edges of length 1.
  std::vector<int> cells;
  for (int y = 2; y < 10; ++y)
    for (int x = 2; x < 10; ++x) cells.push_back(y * 12 + x);
  const gen::Soup box = gridBox(12, cells);
  auto innerEdgeLengths = [](EditableMesh& em, uint32_t firstNew) {
    std::vector<double> out;
    const Array<float>& P = em.positions();
    for (uint32_t t = firstNew; t < em.nTriangles(); ++t) {
      uint32_t e = em.triangleHalfedge()[t];
      for (int k = 0; k < 3; ++k, e = em.next()[e]) {
        uint32_t f = em.face(e ^ 1u);
        if (f < firstNew || f < t) continue;  // a loop edge, or counted from the other side
        const float* a = &P[3 * em.vert()[e]];
        const float* b = &P[3 * em.vert()[e ^ 1u]];
        out.push_back(std::hypot(double(a[0]) - b[0], double(a[1]) - b[1], double(a[2]) - b[2]));
      }
    }
    return out;
  };
  EditableMesh plain;
  makeEditable(box, plain);
  const uint32_t before = plain.nTriangles();
  FillRun r0 = fill(plain);
  ASSERT_TRUE(r0.status.ok());
  ASSERT_EQ(skippedItems(r0.plan), 0u) << describe(r0.plan);
  std::vector<double> l0 = innerEdgeLengths(plain, before);
  RepairOptions o;
  o.fillRefine = true;
  EditableMesh refined;
  makeEditable(box, refined);
  FillRun r1 = fill(refined, o);
  ASSERT_TRUE(r1.status.ok());
  ASSERT_EQ(skippedItems(r1.plan), 0u) << describe(r1.plan);
  EXPECT_NE(r1.plan.items[0].action.find("new vertices (minimum weight, refined)"), std::string::npos)
      << r1.plan.items[0].action;
  EXPECT_TRUE(refined.stats().watertight);
  EXPECT_EQ(editcheck::differenceFromRebuild(refined), "");
  EXPECT_EQ(intersectingPairs(refined), 0u);
  std::vector<double> l1 = innerEdgeLengths(refined, before);
  auto mean = [](const std::vector<double>& v) {
    double s = 0;
    for (double x : v) s += x;
    return s / double(v.size());
  };
  // Without refinement the 32 loop vertices span the hole with long edges; refined, the
  // inner edges are near the loop's edge length (1).
  EXPECT_GT(mean(l0), 3.0);
  EXPECT_GT(mean(l1), 0.6);
  EXPECT_LT(mean(l1), 1.6);
  EXPECT_LT(*std::max_element(l1.begin(), l1.end()), 2.5);
  EXPECT_GT(refined.nLiveVertices(), plain.nLiveVertices() + 30);
  // Still flat: every new vertex lies in the top plane z = 0.
  for (uint32_t v = plain.nVertices(); v < refined.nVertices(); ++v) EXPECT_EQ(refined.positions()[3 * v + 2], 0.0f);
  Mesh m;
  ASSERT_TRUE(refined.toMesh(m).ok());
  EXPECT_NEAR(m.volume, 144.0, 1e-6);
}

TEST(RepairFill, FairMovesOnlyTheNewVertices) {
  // A saddle cup narrowing to its rim (so that a smooth fill meets the wall at less than 90
  // degrees), refined with and without fairing. The mesh's vertices stay where they were;
  // the new vertices move (off the flat refinement of the minimum-weight patch).
  const gen::Soup c = cup(24, 0.15f, 0.4f, 1);
  RepairOptions o;
  o.fillRefine = true;
  EditableMesh a, b;
  makeEditable(c, a);
  makeEditable(c, b);
  const uint32_t nv = a.nVertices();
  const std::vector<float> original = positionsOf(a);
  FillRun ra = fill(a, o);
  o.fillFair = true;
  FillRun rb = fill(b, o);
  ASSERT_TRUE(ra.status.ok());
  ASSERT_TRUE(rb.status.ok());
  ASSERT_FALSE(ra.plan.items[0].skipped) << ra.plan.items[0].reason;
  EXPECT_NE(ra.plan.items[0].action.find("refined)"), std::string::npos) << ra.plan.items[0].action;
  ASSERT_FALSE(rb.plan.items[0].skipped) << rb.plan.items[0].reason;
  EXPECT_NE(rb.plan.items[0].action.find("refined and faired)"), std::string::npos) << rb.plan.items[0].action;
  ASSERT_GT(a.nVertices(), nv);
  ASSERT_EQ(a.nVertices(), b.nVertices());
  for (uint32_t i = 0; i < 3 * nv; ++i) {
    EXPECT_EQ(a.positions()[i], original[i]);
    EXPECT_EQ(b.positions()[i], original[i]);
  }
  double moved = 0;
  for (uint32_t i = 3 * nv; i < 3 * a.nVertices(); ++i)
    moved = std::max(moved, std::fabs(double(a.positions()[i]) - b.positions()[i]));
  EXPECT_GT(moved, 1e-3);
  for (EditableMesh* em : {&a, &b}) {
    EXPECT_TRUE(em->stats().watertight);
    EXPECT_EQ(editcheck::differenceFromRebuild(*em), "");
    EXPECT_EQ(intersectingPairs(*em), 0u);
  }
  // Faired, each new vertex is the mean of its neighbours (to the iterations' precision).
  double worst = 0;
  const Array<float>& P = b.positions();
  for (uint32_t v = nv; v < b.nVertices(); ++v) {
    double sum[3] = {0, 0, 0};
    int count = 0;
    uint32_t e0 = b.vertexHalfedge()[v], e = e0;
    do {
      uint32_t w = b.vert()[e ^ 1u];
      for (int k = 0; k < 3; ++k) sum[k] += P[3 * w + k];
      ++count;
      e = b.next()[e ^ 1u];
    } while (e != e0 && count < 100);
    for (int k = 0; k < 3; ++k) worst = std::max(worst, std::fabs(sum[k] / count - P[3 * v + k]));
  }
  EXPECT_LT(worst, 0.05);
}

TEST(RepairFill, DracoBunnyHolesAreFilled) {
  Mesh m;
  Status s = gen::read(gen::readFile(gen::fixturePath("google_draco/testdata/STL/bunny.stl")), m);
  ASSERT_TRUE(s.ok()) << s.message;
  for (bool refine : {false, true}) {
    EditableMesh em;
    ASSERT_TRUE(em.init(m).ok());
    const uint32_t holes = em.stats().holes;
    ASSERT_EQ(holes, 5u);
    const uint64_t pairsBefore = intersectingPairs(em);
    RepairOptions o;
    o.fillRefine = refine;
    o.fillFair = refine;
    FillRun r = fill(em, o);
    ASSERT_TRUE(r.status.ok()) << r.status.message;
    EXPECT_EQ(r.plan.items.size(), holes);
    EXPECT_EQ(skippedItems(r.plan), 0u) << describe(r.plan);
    EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
    EXPECT_EQ(em.stats().holes, 0u) << describe(r.plan);
    EXPECT_TRUE(em.stats().watertight);
    EXPECT_EQ(intersectingPairs(em), pairsBefore);
  }
}

TEST(RepairFill, NormalsDotIsExact) {
  // Small integer coordinates: the dot product is exact in int64 for comparison.
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> d(-6, 6);
  int zeros = 0;
  for (int i = 0; i < 200000; ++i) {
    float p[6][3];
    for (auto& q : p)
      for (float& x : q) x = float(d(rng));
    auto cross = [](const float* a, const float* b, const float* c, int64_t* n) {
      int64_t u[3], v[3];
      for (int k = 0; k < 3; ++k) u[k] = int64_t(b[k]) - int64_t(a[k]), v[k] = int64_t(c[k]) - int64_t(a[k]);
      n[0] = u[1] * v[2] - u[2] * v[1];
      n[1] = u[2] * v[0] - u[0] * v[2];
      n[2] = u[0] * v[1] - u[1] * v[0];
    };
    int64_t n1[3], n2[3];
    cross(p[0], p[1], p[2], n1);
    cross(p[3], p[4], p[5], n2);
    const int64_t dot = n1[0] * n2[0] + n1[1] * n2[1] + n1[2] * n2[2];
    const int want = dot > 0 ? 1 : dot < 0 ? -1 : 0;
    zeros += want == 0;
    ASSERT_EQ(pred::normalsDot(p[0], p[1], p[2], p[3], p[4], p[5]), want) << i;
    ASSERT_EQ(pred::normalsDotExpansion(p[0], p[1], p[2], p[3], p[4], p[5]), want) << i;
  }
  EXPECT_GT(zeros, 1000);
  // Nearly perpendicular normals of float coordinates far from small integers: the filter
  // and the expansions agree, and the sign is the exact one (a tiny tilt decides).
  const float a[3] = {1e6f, 1e6f, 0}, b[3] = {1e6f + 1, 1e6f, 0}, c[3] = {1e6f, 1e6f + 1, 0};  // normal +z
  for (float tilt : {0.0f, 0.0625f, -0.0625f}) {
    const float e[3] = {1e6f, 1e6f, 0}, f[3] = {1e6f + 1, 1e6f, 0},
                g[3] = {1e6f, 1e6f + tilt, 1};  // normal (0, -1, tilt)
    const int want = tilt == 0 ? 0 : (tilt > 0 ? 1 : -1);
    EXPECT_EQ(pred::normalsDot(a, b, c, e, f, g), want) << tilt;
    EXPECT_EQ(pred::normalsDotExpansion(a, b, c, e, f, g), want) << tilt;
  }
}
