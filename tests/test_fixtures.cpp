// Tests on the real STL fixtures in tests/fixtures (copied from other projects'
// repositories; see tests/fixtures/SOURCES.md). The expected numbers come from
// the source projects' own tests and docs, or from the independent computation
// recorded in shared/fixtures/MANIFEST.md -- never from this library's output.
// Only the public API (src/stltopo.h) is used.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <utility>

#include <vector>
#include "stl_gen.h"

#include "stltopo.h"

#ifndef STLTOPO_FIXTURES
#error "STLTOPO_FIXTURES must name the tests/fixtures directory"
#endif

namespace {

using stltopo::Code;
using stltopo::Format;

using gen::fixturePath;

std::vector<uint8_t> readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  EXPECT_TRUE(in.good()) << "cannot open " << path;
  return std::vector<uint8_t>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

struct Loaded {
  stltopo::Status read;
  stltopo::Status topoStatus;
  stltopo::Mesh mesh;
  stltopo::Topology topo;
};

// Reads a fixture (path relative to tests/fixtures) and, when that succeeds, builds its topology.
Loaded load(const std::string& rel, const stltopo::ReadOptions& options = {}) {
  Loaded l;
  std::vector<uint8_t> bytes = readBytes(fixturePath(rel));
  l.read = stltopo::readStl(bytes.data(), bytes.size(), l.mesh, options);
  if (l.read.ok()) l.topoStatus = stltopo::buildTopology(l.mesh, l.topo);
  return l;
}

#define ASSERT_LOADED(l, rel)                                                                                 \
  ASSERT_TRUE((l).read.ok()) << (rel) << ": " << stltopo::codeName((l).read.code) << " " << (l).read.message; \
  ASSERT_TRUE((l).topoStatus.ok()) << (rel) << ": " << (l).topoStatus.message

bool hasWarning(const stltopo::Mesh& m, Code c) {
  return std::any_of(m.warnings.begin(), m.warnings.end(), [c](const stltopo::Status& w) { return w.code == c; });
}

std::vector<std::pair<std::string, uint32_t>> solidsOf(const stltopo::Mesh& m) {
  std::vector<std::pair<std::string, uint32_t>> out;
  for (const auto& s : m.solids) out.emplace_back(s.name, s.triangleCount);
  return out;
}

// Edge counts of the holes (boundary loops that are not seams), in loop order.
std::vector<uint32_t> holeSizes(const stltopo::Topology& t) {
  std::vector<uint32_t> out;
  for (uint32_t h = 0; h < t.nLoops(); ++h)
    if (!t.loopIsSeam[h]) out.push_back(t.loopOffsets[h + 1] - t.loopOffsets[h]);
  return out;
}

// Every file under tests/fixtures except the .md notes and the fuzz regressions in
// regress/ (which have their own test), as paths relative to it.
std::vector<std::string> allFixtures() {
  std::vector<std::string> out;
  for (const std::string& path : gen::fixtureFiles(gen::kWithoutRegress)) out.push_back(gen::fixtureName(path));
  return out;
}

const char* kBrokenHistoryBlob = "assimp_assimp/_history/a8a1ca98/test/models/STL/3DSMaxExport.STL";
const char* kZeroByteFile = "wolph_numpy-stl/tests/tmp/test_args_False_0/binary.stl";

// Numbers from shared/fixtures/MANIFEST.md ("computed here" by an independent
// script with exact float32 welding; tris and format read from the bytes).
// inconsistent = -1 where the MANIFEST does not state it.
struct ManifestRow {
  const char* path;
  Format format;
  uint32_t triangles, vertices, edges, boundaryEdges, nonManifoldEdges;
  int inconsistentEdges;
  uint32_t degenerate, shells;
  int euler;
};
const ManifestRow kManifest[] = {
    {"wolph_numpy-stl/tests/stl_ascii/Cube.stl", Format::Ascii, 12, 8, 18, 0, 0, 0, 0, 1, 2},
    {"wolph_numpy-stl/tests/stl_ascii/HalfDonut.stl", Format::Ascii, 288, 144, 432, 0, 0, 0, 0, 1, 0},
    {"wolph_numpy-stl/tests/stl_ascii/Moon.stl", Format::Ascii, 116, 60, 174, 0, 0, 0, 0, 1, 2},
    {"wolph_numpy-stl/tests/stl_ascii/Moon_Chinese.stl", Format::Ascii, 116, 60, 174, 0, 0, 0, 0, 1, 2},
    {"wolph_numpy-stl/tests/stl_ascii/Star.stl", Format::Ascii, 68, 36, 102, 0, 0, 0, 0, 1, 2},
    {"wolph_numpy-stl/tests/stl_binary/Cube.stl", Format::Binary, 12, 8, 18, 0, 0, 0, 0, 1, 2},
    {"wolph_numpy-stl/tests/stl_binary/CubeInvalidUnicode.stl", Format::Binary, 12, 8, 18, 0, 0, 0, 0, 1, 2},
    {"wolph_numpy-stl/tests/stl_binary/HalfDonut.stl", Format::Binary, 288, 144, 432, 0, 0, 0, 0, 1, 0},
    {"wolph_numpy-stl/tests/stl_binary/Moon.stl", Format::Binary, 116, 60, 174, 0, 0, 0, 0, 1, 2},
    {"wolph_numpy-stl/tests/stl_binary/Star.stl", Format::Binary, 68, 36, 102, 0, 0, 0, 0, 1, 2},
    {"wolph_numpy-stl/tests/stl_binary/StarWithEmptyHeader.stl", Format::Binary, 68, 36, 102, 0, 0, 0, 0, 1, 2},
    {"wolph_numpy-stl/tests/stl_binary/rear_case.stl", Format::Binary, 18808, 9404, 28212, 0, 0, 0, 0, 1, 0},
    {"wolph_numpy-stl/tests/stl_tests/bwb.stl", Format::Ascii, 4464, 2234, 6696, 0, 0, 0, 0, 1, 2},
    {"wolph_numpy-stl/tests/stl_tests/dos.stl", Format::Ascii, 116, 60, 174, 0, 0, 0, 0, 1, 2},
    {"wolph_numpy-stl/tests/stl_tests/triamid.stl", Format::Binary, 10, 7, 15, 0, 0, 13, 0, 1, 2},
    {"wolph_numpy-stl/tests/stl_tests/unix.stl", Format::Ascii, 116, 60, 174, 0, 0, 0, 0, 1, 2},
    {"assimp_assimp/test/models/STL/3DSMaxExport.STL", Format::Binary, 2000, 1042, 2992, 0, 16, -1, 0, 24, 50},
    {"assimp_assimp/test/models/STL/Spider_ascii.stl", Format::Ascii, 1368, 722, 2004, 72, 0, 10, 56, 18, 30},
    {"assimp_assimp/test/models/STL/Spider_binary.stl", Format::Binary, 1368, 722, 2004, 72, 0, 10, 56, 18, 30},
    {"assimp_assimp/test/models/STL/Wuson.stl", Format::Binary, 3732, 2117, 5804, 412, 0, -1, 0, 54, 45},
    {"assimp_assimp/test/models/STL/formatDetection", Format::Ascii, 1, 3, 3, 3, 0, -1, 0, 1, 1},
    {"assimp_assimp/test/models/STL/sphereWithHole.stl", Format::Ascii, 285, 146, 432, 9, 0, -1, 0, 1, -1},
    {"assimp_assimp/test/models/STL/triangle.stl", Format::Ascii, 1, 3, 3, 3, 0, -1, 0, 1, 1},
    {"assimp_assimp/test/models/STL/triangle_with_empty_solid.stl", Format::Ascii, 1, 3, 3, 3, 0, -1, 0, 1, 1},
    {"assimp_assimp/test/models/STL/triangle_with_two_solids.stl", Format::Ascii, 2, 6, 6, 6, 0, -1, 0, 2, 2},
    {"mikedh_trimesh/models/1002_tray_bottom.STL", Format::Ascii, 4520, 2216, 6780, 0, 0, 0, 0, 1, -44},
    {"mikedh_trimesh/models/20mm-xyz-cube.stl", Format::Binary, 260, 132, 390, 0, 0, 0, 0, 1, 2},
    {"mikedh_trimesh/models/7_8ths_cube.stl", Format::Binary, 24, 14, 36, 0, 0, 0, 0, 1, 2},
    {"mikedh_trimesh/models/ADIS16480.STL", Format::Ascii, 7436, 3672, 11154, 0, 0, 0, 0, 1, -46},
    {"mikedh_trimesh/models/angle_block.STL", Format::Binary, 704, 398, 1139, 166, 0, -1, 0, 1, -37},
    {"mikedh_trimesh/models/ascii.stl.zip.extracted/fuji_obj.stl", Format::Ascii, 344, 174, 516, 0, 0, 0, 0, 1, 2},
    {"mikedh_trimesh/models/box.STL", Format::Binary, 8954, 4455, 13431, 0, 0, 0, 0, 10, -22},
    {"mikedh_trimesh/models/busted.STL", Format::Binary, 3878, 1941, 5817, 0, 0, 0, 0, 1, 2},
    {"mikedh_trimesh/models/counter.unitsmm.STL", Format::Binary, 83750, 41837, 125625, 0, 0, 0, 0, 6, -38},
    {"mikedh_trimesh/models/cylinder.stl", Format::Binary, 416, 210, 624, 0, 0, 0, 0, 1, 2},
    {"mikedh_trimesh/models/featuretype.STL", Format::Binary, 3476, 2010, 5502, 576, 0, -1, 0, 1, -16},
    {"mikedh_trimesh/models/idler_riser.STL", Format::Binary, 1572, 803, 2380, 44, 0, -1, 0, 3, -5},
    {"mikedh_trimesh/models/large_block.STL", Format::Binary, 12, 8, 18, 0, 0, 0, 0, 1, 2},
    {"mikedh_trimesh/models/large_block_obb.STL", Format::Binary, 12, 8, 18, 0, 0, 0, 0, 1, 2},
    {"mikedh_trimesh/models/multibody.stl", Format::Ascii, 32, 20, 48, 0, 0, 12, 0, 2, 4},
    {"mikedh_trimesh/models/octagonal_pocket.stl", Format::Binary, 3262, 1658, 4920, 54, 0, -1, 0, 5, 0},
    {"mikedh_trimesh/models/origin_inside.STL", Format::Binary, 28, 16, 42, 0, 0, 0, 0, 1, 2},
    {"mikedh_trimesh/models/plate_holes.STL", Format::Binary, 1252, 618, 1878, 0, 0, 0, 0, 1, -8},
    {"mikedh_trimesh/models/round.stl", Format::Binary, 1120, 560, 1680, 0, 0, 0, 0, 1, 0},
    {"mikedh_trimesh/models/shared.STL", Format::Binary, 24, 14, 35, 0, 1, -1, 0, 1, 3},
    {"mikedh_trimesh/models/soup.stl", Format::Binary, 100, 300, 300, 300, 0, -1, 0, 100, 100},
    {"mikedh_trimesh/models/teapot.stl", Format::Binary, 894, 480, 1373, 64, 0, -1, 0, 4, 1},
    {"mikedh_trimesh/models/torus.STL", Format::Binary, 8700, 4350, 13050, 0, 0, 0, 0, 1, 0},
    {"mikedh_trimesh/models/two_objects_mixed_case_names.stl", Format::Ascii, 24, 16, 36, 0, 0, 0, 0, 2, 4},
    {"mikedh_trimesh/models/unit_cube.STL", Format::Binary, 12, 8, 18, 0, 0, 0, 0, 1, 2},
    {"mikedh_trimesh/models/unit_sphere.STL", Format::Binary, 1280, 642, 1920, 0, 0, 0, 0, 1, 2},
    {"Pix4D_OpenMesh/src/Unittests/TestFiles/cube1.stl", Format::Ascii, 15048, 7526, 22572, 0, 0, 0, 0, 1, 2},
    {"Pix4D_OpenMesh/src/Unittests/TestFiles/cube1Binary.stl", Format::Binary, 15048, 7526, 22572, 0, 0, 0, 0, 1, 2},
    {"amandaghassaei_stl-parser/test/stl/chair.stl", Format::Binary, 21760, 10882, 32640, 0, 0, 0, 0, 1, 2},
    {"amandaghassaei_stl-parser/test/stl/cubeAscii.stl", Format::Ascii, 12, 8, 18, 0, 0, 0, 0, 1, 2},
    {"amandaghassaei_stl-parser/test/stl/cubeBinary.stl", Format::Binary, 12, 8, 18, 0, 0, 0, 0, 1, 2},
    {"amandaghassaei_stl-parser/test/stl/skull.stl", Format::Binary, 2538, 1327, 3813, 12, 0, -1, 0, 34, 52},
    {"amandaghassaei_stl-parser/test/stl/teapot.stl", Format::Binary, 9438, 4719, 14157, 0, 0, 0, 0, 1, 0},
    {"amandaghassaei_stl-parser/test/stl/wrench.stl", Format::Binary, 65502, 32740, 98247, 0, 6, -1, 0, 3, -5},
    {"google_draco/testdata/STL/bunny.stl", Format::Binary, 69451, 34834, 104288, 223, 0, -1, 0, 1, -3},
    {"google_draco/testdata/STL/test_sphere.stl", Format::Binary, 224, 114, 336, 0, 0, 0, 0, 1, 2},
    {"google_draco/testdata/STL/test_sphere_ascii.stl", Format::Ascii, 224, 114, 336, 0, 0, 0, 0, 1, 2},
    {"nmwsharp_geometry-central/test/assets/stl_box_ascii.stl", Format::Ascii, 12, 8, 18, 0, 0, 0, 0, 1, 2},
    {"nmwsharp_geometry-central/test/assets/stl_box_binary.stl", Format::Binary, 12, 8, 18, 0, 0, 0, 0, 1, 2},
    {"hmeyer_stl_io/src/testdata/bunny_99.stl", Format::Binary, 99, 54, 152, 7, 0, -1, 0, 1, 1},
    {"hmeyer_stl_io/src/testdata/bunny_99_ascii.stl", Format::Ascii, 99, 54, 152, 7, 0, -1, 0, 1, 1},
};

}  // namespace

// ---------------------------------------------------------------------------
// The fixture set itself

TEST(Fixtures, AllSeventyOneFixturesArePresent) {
  const auto files = allFixtures();
  EXPECT_EQ(files.size(), 71u);
  std::set<std::string> have(files.begin(), files.end());
  for (const auto& row : kManifest) EXPECT_TRUE(have.count(row.path)) << row.path;
  EXPECT_TRUE(have.count(kBrokenHistoryBlob));
  EXPECT_TRUE(have.count(kZeroByteFile));
}

// ---------------------------------------------------------------------------
// Every fixture: reads as the MANIFEST says (or fails with the expected code),
// and its topology passes validate() and the navigation identities of the topology contract.

TEST(Fixtures, EveryReadableFixtureValidatesAndOnlyTheTwoBrokenOnesFail) {
  size_t readable = 0;
  for (const auto& rel : allFixtures()) {
    SCOPED_TRACE(rel);
    Loaded l = load(rel);
    if (rel == kBrokenHistoryBlob) {
      EXPECT_EQ(l.read.code, Code::Truncated);
      continue;
    }
    if (rel == kZeroByteFile) {
      EXPECT_EQ(l.read.code, Code::Empty);
      continue;
    }
    ASSERT_TRUE(l.read.ok()) << stltopo::codeName(l.read.code) << ": " << l.read.message;
    ASSERT_TRUE(l.topoStatus.ok()) << l.topoStatus.message;
    const stltopo::Status v = stltopo::validate(l.mesh, l.topo);
    EXPECT_TRUE(v.ok()) << v.message << " (element " << v.element << ")";
    // The report-only topology (the CLI's) equals it but for prev and face.
    EXPECT_EQ(gen::leanTopologyDifference(l.mesh, l.topo), "");
    ++readable;
  }
  EXPECT_EQ(readable, 69u);
}

TEST(Fixtures, NavigationIdentitiesHoldOnEveryReadableFixture) {
  using namespace stltopo;
  for (const auto& rel : allFixtures()) {
    if (rel == kBrokenHistoryBlob || rel == kZeroByteFile) continue;
    SCOPED_TRACE(rel);
    Loaded l = load(rel);
    ASSERT_LOADED(l, rel);
    const Topology& t = l.topo;
    ASSERT_EQ(t.vert.size(), t.nHalfedges());
    ASSERT_EQ(t.face.size(), t.nHalfedges());
    ASSERT_EQ(t.prev.size(), t.nHalfedges());
    uint32_t bad = 0;
    for (uint32_t e = 0; e < t.nHalfedges() && bad < 5; ++e) {
      bool ok = sym(sym(e)) == e && org(t, oNext(t, e)) == org(t, e) && lFace(t, lNext(t, e)) == lFace(t, e) &&
                dst(t, dNext(t, e)) == dst(t, e) && rFace(t, rNext(t, e)) == rFace(t, e) &&
                lPrev(t, lNext(t, e)) == e && oPrev(t, oNext(t, e)) == e && dPrev(t, dNext(t, e)) == e &&
                rPrev(t, rNext(t, e)) == e && org(t, vnext(t, e)) == org(t, e) && t.vert[t.next[e]] == t.vert[e ^ 1u];
      if (!ok) {
        ++bad;
        ADD_FAILURE() << "navigation identity broken at half-edge " << e;
      }
    }
    // every non-degenerate triangle has its 3 half-edges, degenerate ones have none
    for (uint32_t tri = 0; tri < l.mesh.nTriangles(); ++tri) {
      const uint32_t e = t.triangleHalfedge[tri];
      if (t.triangleDegenerate[tri]) {
        EXPECT_EQ(e, kInvalid);
        continue;
      }
      ASSERT_NE(e, kInvalid);
      EXPECT_EQ(t.face[e], tri);
      EXPECT_EQ(t.next[t.next[t.next[e]]], e);
      EXPECT_EQ(t.vert[e], l.mesh.triangles[3 * tri]);
    }
  }
}

TEST(Fixtures, FormatsCountsAndEdgesMatchTheManifest) {
  for (const auto& row : kManifest) {
    SCOPED_TRACE(row.path);
    Loaded l = load(row.path);
    ASSERT_LOADED(l, row.path);
    EXPECT_EQ(l.mesh.format, row.format);
    EXPECT_EQ(l.mesh.nTriangles(), row.triangles);
    EXPECT_EQ(l.mesh.nVertices(), row.vertices);
    EXPECT_EQ(l.topo.nEdges, row.edges);
    EXPECT_EQ(l.topo.nBoundaryEdges, row.boundaryEdges);
    EXPECT_EQ(l.topo.nNonManifoldEdges, row.nonManifoldEdges);
    if (row.inconsistentEdges >= 0) {
      EXPECT_EQ(l.topo.nInconsistentEdges, uint32_t(row.inconsistentEdges));
    }
    EXPECT_EQ(l.topo.nDegenerate, row.degenerate);
    EXPECT_EQ(l.topo.nShells, row.shells);
    const int64_t chi = int64_t(l.topo.nUsedVertices) - int64_t(l.topo.nEdges) + int64_t(l.mesh.nTriangles()) -
                        int64_t(l.topo.nDegenerate);
    EXPECT_EQ(chi, row.euler);
  }
}

TEST(Fixtures, EmptyFixturesReadAsZeroTriangles) {
  const std::pair<const char*, Format> empties[] = {
      {"mikedh_trimesh/models/empty.stl", Format::Ascii},
      {"mikedh_trimesh/models/emptyIO/stl_empty_ascii.stl", Format::Ascii},
      {"mikedh_trimesh/models/emptyIO/stl_empty_bin.stl", Format::Binary},
  };
  for (const auto& [rel, format] : empties) {
    SCOPED_TRACE(rel);
    Loaded l = load(rel);
    ASSERT_LOADED(l, rel);
    EXPECT_EQ(l.mesh.format, format);
    EXPECT_EQ(l.mesh.nTriangles(), 0u);
    EXPECT_EQ(l.mesh.nVertices(), 0u);
    EXPECT_EQ(l.topo.nEdges, 0u);
    ASSERT_EQ(l.mesh.solids.size(), 1u);
    EXPECT_EQ(l.mesh.solids[0].triangleCount, 0u);
  }
  EXPECT_EQ(load("mikedh_trimesh/models/empty.stl").mesh.solids[0].name, "Empty");
}

// ---------------------------------------------------------------------------
// Facts quoted from the source projects' own tests

TEST(Fixtures, OpenMeshCubeMatchesSourceCounts) {
  // OpenMesh unittests_read_write_STL.cc: 7526 vertices, 22572 edges, 15048 faces,
  // face 0 normal ~ (-0.038545, -0.004330, 0.999247); for the ASCII and the binary file.
  stltopo::ReadOptions keep;
  keep.keepNormals = true;
  for (const char* rel :
       {"Pix4D_OpenMesh/src/Unittests/TestFiles/cube1.stl", "Pix4D_OpenMesh/src/Unittests/TestFiles/cube1Binary.stl"}) {
    SCOPED_TRACE(rel);
    Loaded l = load(rel, keep);
    ASSERT_LOADED(l, rel);
    EXPECT_EQ(l.mesh.nVertices(), 7526u);
    EXPECT_EQ(l.topo.nEdges, 22572u);
    EXPECT_EQ(l.mesh.nTriangles(), 15048u);
    ASSERT_EQ(l.mesh.normals.size(), 3u * 15048u);
    EXPECT_NEAR(l.mesh.normals[0], -0.038545, 1e-5);
    EXPECT_NEAR(l.mesh.normals[1], -0.004330, 1e-5);
    EXPECT_NEAR(l.mesh.normals[2], 0.999247, 1e-5);
    EXPECT_TRUE(l.topo.nBoundaryEdges == 0 && l.topo.nNonManifoldEdges == 0);
  }
}

TEST(Fixtures, OpenMeshAsciiCubeWithoutEndsolidIsAcceptedWithAWarning) {
  Loaded a = load("Pix4D_OpenMesh/src/Unittests/TestFiles/cube1.stl");
  ASSERT_LOADED(a, "cube1.stl");
  EXPECT_EQ(a.mesh.format, Format::Ascii);
  EXPECT_TRUE(hasWarning(a.mesh, Code::MissingEndsolid));
  ASSERT_EQ(a.mesh.solids.size(), 1u);
  EXPECT_EQ(a.mesh.solids[0].name, "");  // `solid` with no name
  Loaded b = load("Pix4D_OpenMesh/src/Unittests/TestFiles/cube1Binary.stl");
  ASSERT_LOADED(b, "cube1Binary.stl");
  EXPECT_TRUE(b.mesh.warnings.empty());
}

TEST(Fixtures, GeometryCentralBoxesHaveEightVerticesAndTwelveFaces) {
  // geometry-central stl_reader_test.cpp: nVertices() == 8, nFaces() == 12.
  for (const char* rel : {"nmwsharp_geometry-central/test/assets/stl_box_ascii.stl",
                          "nmwsharp_geometry-central/test/assets/stl_box_binary.stl"}) {
    SCOPED_TRACE(rel);
    Loaded l = load(rel);
    ASSERT_LOADED(l, rel);
    EXPECT_EQ(l.mesh.nVertices(), 8u);
    EXPECT_EQ(l.mesh.nTriangles(), 12u);
  }
  Loaded a = load("nmwsharp_geometry-central/test/assets/stl_box_ascii.stl");
  ASSERT_EQ(a.mesh.solids.size(), 1u);
  EXPECT_EQ(a.mesh.solids[0].name, "\"Design1<stl unit=MM>\"");
}

TEST(Fixtures, NumpyStlVolumesMatchSourceTests) {
  // numpy-stl tests/test_mesh_properties.py: volumes 2.343149, 0.888723, 1.416599
  // (for the ASCII and the binary files).
  const std::pair<const char*, double> cases[] = {
      {"wolph_numpy-stl/tests/stl_ascii/HalfDonut.stl", 2.343149},
      {"wolph_numpy-stl/tests/stl_binary/HalfDonut.stl", 2.343149},
      {"wolph_numpy-stl/tests/stl_ascii/Moon.stl", 0.888723},
      {"wolph_numpy-stl/tests/stl_binary/Moon.stl", 0.888723},
      {"wolph_numpy-stl/tests/stl_ascii/Star.stl", 1.416599},
      {"wolph_numpy-stl/tests/stl_binary/Star.stl", 1.416599},
      {"wolph_numpy-stl/tests/stl_binary/StarWithEmptyHeader.stl", 1.416599},
  };
  for (const auto& [rel, volume] : cases) {
    SCOPED_TRACE(rel);
    Loaded l = load(rel);
    ASSERT_LOADED(l, rel);
    EXPECT_NEAR(l.mesh.volume, volume, 1e-5);
  }
}

TEST(Fixtures, TrimeshVolumesMatchSourceTests) {
  // trimesh tests/test_loaded.py: unit_cube volume 1.0; tests/test_stl.py: featuretype
  // volume 11.627733431196749 (atol 1e-6).
  Loaded cube = load("mikedh_trimesh/models/unit_cube.STL");
  ASSERT_LOADED(cube, "unit_cube.STL");
  EXPECT_NEAR(cube.mesh.volume, 1.0, 1e-9);
  Loaded ft = load("mikedh_trimesh/models/featuretype.STL");
  ASSERT_LOADED(ft, "featuretype.STL");
  EXPECT_NEAR(ft.mesh.volume, 11.627733431196749, 1e-6);
  EXPECT_EQ(ft.mesh.nTriangles() * 3, 10428u);  // test_loaded.py: 10428 unwelded vertices
}

TEST(Fixtures, SolidNamesMatchTheSources) {
  using Names = std::vector<std::pair<std::string, uint32_t>>;
  const std::pair<const char*, Names> cases[] = {
      // trimesh tests/test_stl.py: geometry keys {"bodyA", "bodyB"}; file order bodyB, bodyA
      {"mikedh_trimesh/models/multibody.stl", {{"bodyB", 12}, {"bodyA", 20}}},
      // numpy-stl: UTF-8 solid name 月球 ("moon")
      {"wolph_numpy-stl/tests/stl_ascii/Moon_Chinese.stl", {{"\xE6\x9C\x88\xE7\x90\x83", 116}}},
      // assimp issue 1970: a file with an empty second solid
      {"assimp_assimp/test/models/STL/triangle_with_empty_solid.stl", {{"testTriangle", 1}, {"emptySolid", 0}}},
      {"assimp_assimp/test/models/STL/triangle_with_two_solids.stl", {{"testTriangle_1", 1}, {"testTriangle_2", 1}}},
      {"mikedh_trimesh/models/two_objects_mixed_case_names.stl",
       {{"CubeExportedFromCAD", 12}, {"TranslatedCubeExportedFromCAD", 12}}},
      // trimesh fix #1720: keyword text inside the name
      {"mikedh_trimesh/models/ascii.stl.zip.extracted/fuji_obj.stl", {{"solidname", 344}}},
      {"assimp_assimp/test/models/STL/sphereWithHole.stl", {{"tinysphere_withhole", 285}}},
      {"wolph_numpy-stl/tests/stl_tests/bwb.stl", {{"\"bwb\"", 4464}}},
  };
  for (const auto& [rel, names] : cases) {
    SCOPED_TRACE(rel);
    Loaded l = load(rel);
    ASSERT_LOADED(l, rel);
    EXPECT_EQ(l.mesh.format, Format::Ascii);
    EXPECT_EQ(solidsOf(l.mesh), names);
    if (l.mesh.solids.size() == 2) {
      EXPECT_EQ(l.mesh.solids[0].firstTriangle, 0u);
      EXPECT_EQ(l.mesh.solids[1].firstTriangle, l.mesh.solids[0].triangleCount);
    }
  }
}

TEST(Fixtures, ExtensionlessAssimpFileIsDetectedAsAscii) {
  // assimp utSTLImportExport.cpp: `formatDetection` has no extension and must load.
  Loaded l = load("assimp_assimp/test/models/STL/formatDetection");
  ASSERT_LOADED(l, "formatDetection");
  EXPECT_EQ(l.mesh.format, Format::Ascii);
  EXPECT_EQ(l.mesh.nTriangles(), 1u);
  EXPECT_EQ(solidsOf(l.mesh), (std::vector<std::pair<std::string, uint32_t>>{{"testTriangle", 1}}));
}

TEST(Fixtures, BinaryFilesWhoseHeaderStartsWithSolidAreBinary) {
  // numpy-stl test_ascii_like_binary (rear_case.stl) and the other CAD exports whose
  // 80-byte header begins with "solid" while the size is exactly 84 + 50n.
  const std::pair<const char*, uint32_t> cases[] = {
      {"wolph_numpy-stl/tests/stl_binary/rear_case.stl", 18808},
      {"wolph_numpy-stl/tests/stl_binary/Cube.stl", 12},
      {"wolph_numpy-stl/tests/stl_binary/CubeInvalidUnicode.stl", 12},
      {"mikedh_trimesh/models/angle_block.STL", 704},
      {"mikedh_trimesh/models/idler_riser.STL", 1572},
      {"mikedh_trimesh/models/octagonal_pocket.stl", 3262},
      {"mikedh_trimesh/models/origin_inside.STL", 28},
      {"mikedh_trimesh/models/plate_holes.STL", 1252},
      {"mikedh_trimesh/models/torus.STL", 8700},
      {"mikedh_trimesh/models/unit_cube.STL", 12},
  };
  for (const auto& [rel, tris] : cases) {
    SCOPED_TRACE(rel);
    Loaded l = load(rel);
    ASSERT_LOADED(l, rel);
    EXPECT_EQ(l.mesh.format, Format::Binary);
    EXPECT_EQ(l.mesh.nTriangles(), tris);
    EXPECT_TRUE(l.mesh.warnings.empty());
  }
}

TEST(Fixtures, HalfDonutBinaryWithOneExtraByteWarnsTrailingBytes) {
  // numpy-stl stl_binary/HalfDonut.stl is 84 + 50*288 + 1 bytes (a trailing 0x0A)
  // and its header starts with "solid".
  Loaded l = load("wolph_numpy-stl/tests/stl_binary/HalfDonut.stl");
  ASSERT_LOADED(l, "HalfDonut.stl");
  EXPECT_EQ(l.mesh.format, Format::Binary);
  EXPECT_EQ(l.mesh.nTriangles(), 288u);
  EXPECT_TRUE(hasWarning(l.mesh, Code::TrailingBytes));
  EXPECT_EQ(l.mesh.warnings.size(), 1u);
}

TEST(Fixtures, BrokenAssimpHistoryBlobIsTruncated) {
  // assimp a8a1ca98 committed 3DSMaxExport.STL with one 0x0D byte removed:
  // 100083 bytes where the count (2000) promises 100084.
  Loaded l = load(kBrokenHistoryBlob);
  EXPECT_EQ(l.read.code, Code::Truncated);
  EXPECT_NE(l.read.offset, stltopo::kNoOffset);
  EXPECT_NE(l.read.message.find("2000"), std::string::npos) << l.read.message;
  EXPECT_NE(l.read.message.find("100083"), std::string::npos) << l.read.message;
  // the good version of the same file reads
  Loaded good = load("assimp_assimp/test/models/STL/3DSMaxExport.STL");
  ASSERT_LOADED(good, "3DSMaxExport.STL");
  EXPECT_EQ(good.mesh.nTriangles(), 2000u);
}

TEST(Fixtures, ZeroByteFileIsEmpty) {
  Loaded l = load(kZeroByteFile);
  EXPECT_EQ(l.read.code, Code::Empty);
  EXPECT_FALSE(l.read.message.empty());
}

TEST(Fixtures, BwbHas155NormalMismatches) {
  Loaded l = load("wolph_numpy-stl/tests/stl_tests/bwb.stl");
  ASSERT_LOADED(l, "bwb.stl");
  EXPECT_EQ(l.mesh.normalMismatches, 155u);
  EXPECT_EQ(l.mesh.nTriangles(), 4464u);
}

TEST(Fixtures, CubeBinaryMagicsColourIs19Of31PerChannel) {
  // stl-parser test/test.ts: colours read because the header contains COLOR=,
  // first face colour 0.6129032373428345 = 19/31 on each channel.
  Loaded l = load("amandaghassaei_stl-parser/test/stl/cubeBinary.stl");
  ASSERT_LOADED(l, "cubeBinary.stl");
  EXPECT_EQ(l.mesh.colorConvention, stltopo::ColorConvention::Magics);
  ASSERT_EQ(l.mesh.colors.size(), 3u * 12u);
  ASSERT_EQ(l.mesh.colorValid.size(), 12u);
  const int expected = int(std::lround(19.0 * 255.0 / 31.0));  // 156
  ASSERT_EQ(expected, 156);
  for (uint32_t t = 0; t < 12; ++t) {
    EXPECT_EQ(l.mesh.attributes[t], 0x4E73u);
    EXPECT_EQ(l.mesh.colorValid[t], 1u);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(int(l.mesh.colors[3 * t + c]), expected) << "t=" << t;
  }
  // stl-parser: 8 merged vertices, bbox [0,0,-10]-[10,10,0]
  EXPECT_EQ(l.mesh.nVertices(), 8u);
  EXPECT_FLOAT_EQ(l.mesh.bboxMin[2], -10.0f);
  EXPECT_FLOAT_EQ(l.mesh.bboxMax[0], 10.0f);
}

TEST(Fixtures, StlParserAsciiCubeHasNoColours) {
  Loaded l = load("amandaghassaei_stl-parser/test/stl/cubeAscii.stl");
  ASSERT_LOADED(l, "cubeAscii.stl");
  EXPECT_EQ(l.mesh.colorConvention, stltopo::ColorConvention::None);
  EXPECT_EQ(l.mesh.nVertices(), 8u);            // test.ts: 8 vertices after mergeVertices()
  EXPECT_EQ(l.topo.nEdges, 18u);                // merged edge list: 36 indices
  EXPECT_FLOAT_EQ(l.mesh.positions[0], 10.0f);  // first vertex [10, 0, -10]
  EXPECT_FLOAT_EQ(l.mesh.positions[1], 0.0f);
  EXPECT_FLOAT_EQ(l.mesh.positions[2], -10.0f);
}

TEST(Fixtures, TwentyMillimetreCubeUsesMagicsColourAndIs20mmWide) {
  // Header "STLB ATF 2.0.0.9000 COLOR=" + RGBA; trimesh test_units.py: extents 20 mm.
  Loaded l = load("mikedh_trimesh/models/20mm-xyz-cube.stl");
  ASSERT_LOADED(l, "20mm-xyz-cube.stl");
  EXPECT_EQ(l.mesh.colorConvention, stltopo::ColorConvention::Magics);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(l.mesh.bboxMax[k] - l.mesh.bboxMin[k], 20.0, 1e-3);
}

TEST(Fixtures, BlenderAttributeWordsWithoutBit15AreNotColours) {
  // Wuson.stl / trimesh teapot.stl: attribute 0x2020 on every facet, no COLOR= header;
  // wrench.stl: bit 15 clear and no COLOR=.
  for (const char* rel : {"assimp_assimp/test/models/STL/Wuson.stl", "mikedh_trimesh/models/teapot.stl",
                          "amandaghassaei_stl-parser/test/stl/wrench.stl"}) {
    SCOPED_TRACE(rel);
    Loaded l = load(rel);
    ASSERT_LOADED(l, rel);
    EXPECT_EQ(l.mesh.colorConvention, stltopo::ColorConvention::None);
  }
}

TEST(Fixtures, TrimeshSoupIsOneHoleOfThreeEdgesPerTriangle) {
  // trimesh test_graph.py: "a soup of random triangles, with no adjacent pairs".
  Loaded l = load("mikedh_trimesh/models/soup.stl");
  ASSERT_LOADED(l, "soup.stl");
  EXPECT_EQ(l.mesh.nTriangles(), 100u);
  EXPECT_EQ(l.topo.nBoundaryEdges, 300u);
  EXPECT_EQ(l.topo.nHoles, 100u);
  EXPECT_EQ(l.topo.nSeams, 0u);
  EXPECT_EQ(l.topo.nShells, 100u);
  EXPECT_EQ(holeSizes(l.topo), std::vector<uint32_t>(100, 3u));
}

TEST(Fixtures, TrimeshMultibodyHasTwoSolidsAndTwelveInconsistentEdges) {
  Loaded l = load("mikedh_trimesh/models/multibody.stl");
  ASSERT_LOADED(l, "multibody.stl");
  EXPECT_EQ(solidsOf(l.mesh), (std::vector<std::pair<std::string, uint32_t>>{{"bodyB", 12}, {"bodyA", 20}}));
  EXPECT_EQ(l.topo.nInconsistentEdges, 12u);
  EXPECT_EQ(l.topo.nBoundaryEdges, 0u);
  EXPECT_EQ(l.topo.nHoles, 0u);  // cut inconsistent sides form seams, not holes
  EXPECT_GT(l.topo.nSeams, 0u);
  EXPECT_EQ(l.topo.nShells, 2u);
}

TEST(Fixtures, NumpyStlTriamidHasThirteenInconsistentEdges) {
  Loaded l = load("wolph_numpy-stl/tests/stl_tests/triamid.stl");
  ASSERT_LOADED(l, "triamid.stl");
  EXPECT_EQ(l.mesh.nTriangles(), 10u);
  EXPECT_EQ(l.topo.nInconsistentEdges, 13u);
  EXPECT_EQ(l.topo.nBoundaryEdges, 0u);
  EXPECT_EQ(l.topo.nHoles, 0u);
}

TEST(Fixtures, TrimeshSharedHasOneNonManifoldEdgeAndNoHoles) {
  // trimesh test_graph.py loads it with its watertight assertions commented out.
  Loaded l = load("mikedh_trimesh/models/shared.STL");
  ASSERT_LOADED(l, "shared.STL");
  EXPECT_EQ(l.topo.nNonManifoldEdges, 1u);
  EXPECT_EQ(l.topo.nBoundaryEdges, 0u);
  EXPECT_EQ(l.topo.nHoles, 0u);
}

TEST(Fixtures, StlIoBunny99HasSevenBoundaryEdgesInOneHole) {
  // stl_io lib.rs: 99 faces, area 0.04998364 "according to blender", and validate()
  // fails (holes) -- exact welding leaves a 7-edge boundary.
  for (const char* rel : {"hmeyer_stl_io/src/testdata/bunny_99.stl", "hmeyer_stl_io/src/testdata/bunny_99_ascii.stl"}) {
    SCOPED_TRACE(rel);
    Loaded l = load(rel);
    ASSERT_LOADED(l, rel);
    EXPECT_EQ(l.mesh.nTriangles(), 99u);
    EXPECT_NEAR(l.mesh.area, 0.04998364, 1e-7);
    EXPECT_EQ(l.topo.nBoundaryEdges, 7u);
    EXPECT_EQ(l.topo.nHoles, 1u);
    EXPECT_EQ(holeSizes(l.topo), std::vector<uint32_t>{7u});
  }
}

TEST(Fixtures, DracoBunnyHasFiveHoles) {
  Loaded l = load("google_draco/testdata/STL/bunny.stl");
  ASSERT_LOADED(l, "bunny.stl");
  EXPECT_EQ(l.mesh.nTriangles(), 69451u);
  EXPECT_EQ(l.topo.nBoundaryEdges, 223u);
  EXPECT_EQ(l.topo.nHoles, 5u);
  uint32_t sum = 0;
  for (uint32_t s : holeSizes(l.topo)) sum += s;
  EXPECT_EQ(sum, 223u);
}

TEST(Fixtures, AssimpSphereWithHoleHasOneBoundaryOfNineEdges) {
  // The MANIFEST finds 9 boundary edges in one component with 2 pinch vertices;
  // under the fan rule that is one loop through both, and both are
  // non-manifold vertices.
  Loaded l = load("assimp_assimp/test/models/STL/sphereWithHole.stl");
  ASSERT_LOADED(l, "sphereWithHole.stl");
  EXPECT_EQ(l.topo.nBoundaryEdges, 9u);
  EXPECT_EQ(l.topo.nHoles, 1u);
  EXPECT_EQ(holeSizes(l.topo), std::vector<uint32_t>{9u});
  EXPECT_EQ(l.topo.nNonManifoldVertices, 2u);
}

TEST(Fixtures, AssimpSpiderHasFiftySixDegenerateTriangles) {
  for (const char* rel :
       {"assimp_assimp/test/models/STL/Spider_ascii.stl", "assimp_assimp/test/models/STL/Spider_binary.stl"}) {
    SCOPED_TRACE(rel);
    Loaded l = load(rel);
    ASSERT_LOADED(l, rel);
    EXPECT_EQ(l.topo.nDegenerate, 56u);
    uint32_t flagged = 0;
    for (uint32_t t = 0; t < l.mesh.nTriangles(); ++t) flagged += l.topo.triangleDegenerate[t] ? 1u : 0u;
    EXPECT_EQ(flagged, 56u);
    EXPECT_EQ(l.topo.nInconsistentEdges, 10u);
    EXPECT_EQ(l.mesh.normalMismatches, 1312u);
  }
}

// ---------------------------------------------------------------------------
// Binary and ASCII twins of the same mesh

TEST(Fixtures, BinaryAndAsciiTwinsGiveIdenticalPositionsAndTriangles) {
  // numpy-stl test_convert.py: ascii <-> binary conversions are byte-exact;
  // stl_io lib.rs:386: indexed ascii mesh == indexed binary mesh.
  const std::pair<const char*, const char*> exact[] = {
      {"wolph_numpy-stl/tests/stl_ascii/Cube.stl", "wolph_numpy-stl/tests/stl_binary/Cube.stl"},
      {"wolph_numpy-stl/tests/stl_ascii/HalfDonut.stl", "wolph_numpy-stl/tests/stl_binary/HalfDonut.stl"},
      {"wolph_numpy-stl/tests/stl_ascii/Moon.stl", "wolph_numpy-stl/tests/stl_binary/Moon.stl"},
      {"wolph_numpy-stl/tests/stl_ascii/Star.stl", "wolph_numpy-stl/tests/stl_binary/Star.stl"},
      {"hmeyer_stl_io/src/testdata/bunny_99_ascii.stl", "hmeyer_stl_io/src/testdata/bunny_99.stl"},
      {"Pix4D_OpenMesh/src/Unittests/TestFiles/cube1.stl", "Pix4D_OpenMesh/src/Unittests/TestFiles/cube1Binary.stl"},
      {"nmwsharp_geometry-central/test/assets/stl_box_ascii.stl",
       "nmwsharp_geometry-central/test/assets/stl_box_binary.stl"},
      {"amandaghassaei_stl-parser/test/stl/cubeAscii.stl", "amandaghassaei_stl-parser/test/stl/cubeBinary.stl"},
  };
  for (const auto& [a, b] : exact) {
    SCOPED_TRACE(std::string(a) + " vs " + b);
    Loaded la = load(a), lb = load(b);
    ASSERT_LOADED(la, a);
    ASSERT_LOADED(lb, b);
    EXPECT_EQ(la.mesh.format, Format::Ascii);
    EXPECT_EQ(lb.mesh.format, Format::Binary);
    ASSERT_EQ(la.mesh.positions.size(), lb.mesh.positions.size());
    ASSERT_EQ(la.mesh.triangles.size(), lb.mesh.triangles.size());
    EXPECT_TRUE(std::equal(la.mesh.positions.begin(), la.mesh.positions.end(), lb.mesh.positions.begin()));
    EXPECT_TRUE(std::equal(la.mesh.triangles.begin(), la.mesh.triangles.end(), lb.mesh.triangles.begin()));
  }
}

TEST(Fixtures, SixDecimalAsciiTwinsGiveIdenticalTrianglesAndNearlyEqualPositions) {
  // draco test_sphere_ascii.stl and assimp Spider_ascii.stl print coordinates with
  // 6 decimals, so positions agree with their binary twins to half a unit in the
  // 6th decimal (plus float32 rounding), and the welded triangles are identical.
  const std::pair<const char*, const char*> rounded[] = {
      {"google_draco/testdata/STL/test_sphere_ascii.stl", "google_draco/testdata/STL/test_sphere.stl"},
      {"assimp_assimp/test/models/STL/Spider_ascii.stl", "assimp_assimp/test/models/STL/Spider_binary.stl"},
  };
  for (const auto& [a, b] : rounded) {
    SCOPED_TRACE(std::string(a) + " vs " + b);
    Loaded la = load(a), lb = load(b);
    ASSERT_LOADED(la, a);
    ASSERT_LOADED(lb, b);
    ASSERT_EQ(la.mesh.positions.size(), lb.mesh.positions.size());
    ASSERT_EQ(la.mesh.triangles.size(), lb.mesh.triangles.size());
    EXPECT_TRUE(std::equal(la.mesh.triangles.begin(), la.mesh.triangles.end(), lb.mesh.triangles.begin()));
    for (size_t i = 0; i < la.mesh.positions.size(); ++i) {
      const double x = la.mesh.positions[i], y = lb.mesh.positions[i];
      ASSERT_NEAR(x, y, 5e-7 + 1.2e-7 * std::fabs(y)) << "coordinate " << i;
    }
  }
}

TEST(Fixtures, TwinsOfTheSameFileGiveTheSameTopology) {
  const std::pair<const char*, const char*> same[] = {
      {"wolph_numpy-stl/tests/stl_binary/Star.stl", "wolph_numpy-stl/tests/stl_binary/StarWithEmptyHeader.stl"},
      {"wolph_numpy-stl/tests/stl_ascii/Moon.stl", "wolph_numpy-stl/tests/stl_tests/dos.stl"},
      {"wolph_numpy-stl/tests/stl_ascii/Moon.stl", "wolph_numpy-stl/tests/stl_tests/unix.stl"},
      {"wolph_numpy-stl/tests/stl_ascii/Moon.stl", "wolph_numpy-stl/tests/stl_ascii/Moon_Chinese.stl"},
      {"assimp_assimp/test/models/STL/triangle.stl", "assimp_assimp/test/models/STL/formatDetection"},
  };
  for (const auto& [a, b] : same) {
    SCOPED_TRACE(std::string(a) + " vs " + b);
    Loaded la = load(a), lb = load(b);
    ASSERT_LOADED(la, a);
    ASSERT_LOADED(lb, b);
    ASSERT_EQ(la.topo.nHalfedges(), lb.topo.nHalfedges());
    EXPECT_TRUE(std::equal(la.mesh.positions.begin(), la.mesh.positions.end(), lb.mesh.positions.begin()));
    EXPECT_TRUE(std::equal(la.topo.next.begin(), la.topo.next.end(), lb.topo.next.begin()));
    EXPECT_TRUE(std::equal(la.topo.vert.begin(), la.topo.vert.end(), lb.topo.vert.begin()));
    EXPECT_TRUE(std::equal(la.topo.face.begin(), la.topo.face.end(), lb.topo.face.begin()));
  }
}

// ---------------------------------------------------------------------------
// Streaming on real files with different features (trailing byte, CRLF, UTF-8
// name, two solids, Magics colours, missing endsolid).

TEST(Fixtures, ChunkedReadingEqualsWholeBufferOnRealFiles) {
  const char* files[] = {
      "wolph_numpy-stl/tests/stl_binary/HalfDonut.stl",
      "wolph_numpy-stl/tests/stl_tests/dos.stl",
      "wolph_numpy-stl/tests/stl_ascii/Moon_Chinese.stl",
      "mikedh_trimesh/models/multibody.stl",
      "amandaghassaei_stl-parser/test/stl/cubeBinary.stl",
      "assimp_assimp/test/models/STL/triangle_with_empty_solid.stl",
      "assimp_assimp/test/models/STL/Spider_ascii.stl",
      kBrokenHistoryBlob,
  };
  for (const char* rel : files) {
    const std::vector<uint8_t> bytes = readBytes(fixturePath(rel));
    stltopo::Mesh whole;
    const stltopo::Status ws = stltopo::readStl(bytes.data(), bytes.size(), whole);
    for (size_t chunk : {size_t(1), size_t(7), size_t(50), size_t(4096)}) {
      SCOPED_TRACE(std::string(rel) + " chunk " + std::to_string(chunk));
      stltopo::Reader reader;
      stltopo::Status st;
      for (size_t off = 0; off < bytes.size() && st.ok(); off += chunk)
        st = reader.feed(bytes.data() + off, std::min(chunk, bytes.size() - off));
      stltopo::Mesh m;
      if (st.ok()) st = reader.finish(m);
      EXPECT_EQ(st.code, ws.code);
      if (!ws.ok()) continue;
      EXPECT_EQ(m.format, whole.format);
      EXPECT_EQ(solidsOf(m), solidsOf(whole));
      ASSERT_EQ(m.positions.size(), whole.positions.size());
      ASSERT_EQ(m.triangles.size(), whole.triangles.size());
      EXPECT_TRUE(std::equal(m.positions.begin(), m.positions.end(), whole.positions.begin()));
      EXPECT_TRUE(std::equal(m.triangles.begin(), m.triangles.end(), whole.triangles.begin()));
      EXPECT_TRUE(std::equal(m.colors.begin(), m.colors.end(), whole.colors.begin()));
      EXPECT_EQ(m.warnings.size(), whole.warnings.size());
    }
  }
}
