// stltopo_cgal_pmp: CGAL's own PMP::self_intersections on the welded mesh, for comparing the
// judge (cgal_judge.cpp) with the real CGAL function and for timing it in the bench.
// Test-only, never shipped. See tests/judge/README.md.
//
// usage: stltopo_cgal_pmp FILE [--reps N]
//   Builds a CGAL::Surface_mesh from stltopo's welded mesh (vertex ids kept; faces added in
//   triangle order). When a face cannot be added (a non-manifold edge or vertex, a
//   same-direction duplicate, a repeated id), prints {"mesh":false,"face":t} and exits 3: CGAL
//   5.5 has no soup entry point. Otherwise prints
//   {"mesh":true,"triangles":T,"degenerate":[t…],"pairs":P,"seconds":S}
//   then "i j" per pair (i < j, sorted): the pairs of PMP::self_intersections (Epick), with its
//   (f, f) entries for degenerate faces listed apart. S: the wall time of self_intersections.
//   With --reps N (N >= 2), self_intersections runs N times and the JSON also has
//   "warmSeconds": the median of calls 2..N (the first call pays the process's fresh pages).
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "stltopo/stltopo.h"

namespace PMP = CGAL::Polygon_mesh_processing;
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using SM = CGAL::Surface_mesh<K::Point_3>;

int main(int argc, char** argv) {
  int reps = 1;
  if (argc == 4 && std::string(argv[2]) == "--reps") reps = std::max(1, std::atoi(argv[3]));
  if (argc != 2 && !(argc == 4 && reps >= 1)) {
    std::fprintf(stderr, "usage: stltopo_cgal_pmp FILE [--reps N]\n");
    return 2;
  }
  std::ifstream in(argv[1], std::ios::binary);
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  stltopo::Mesh mesh;
  stltopo::Status s = in ? stltopo::readStl(bytes.data(), bytes.size(), mesh)
                         : stltopo::Status::error(stltopo::Code::InvalidArgument, "cannot open");
  if (!s.ok()) {
    std::fprintf(stderr, "{\"error\":\"%s\"}\n", stltopo::codeName(s.code));
    return 1;
  }
  SM sm;
  const float* p = mesh.positions.data();
  for (uint32_t v = 0; v < mesh.nVertices(); ++v) sm.add_vertex(K::Point_3(p[3 * v], p[3 * v + 1], p[3 * v + 2]));
  for (uint32_t t = 0; t < mesh.nTriangles(); ++t) {
    const uint32_t* a = mesh.triangles.data() + 3 * size_t(t);
    SM::Face_index f = sm.add_face(SM::Vertex_index(a[0]), SM::Vertex_index(a[1]), SM::Vertex_index(a[2]));
    if (f == SM::null_face()) {
      std::printf("{\"mesh\":false,\"face\":%u}\n", t);
      return 3;
    }
  }
  std::vector<std::pair<SM::Face_index, SM::Face_index>> out;
  auto t0 = std::chrono::steady_clock::now();
  PMP::self_intersections<CGAL::Sequential_tag>(sm, std::back_inserter(out));
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::vector<double> warm;
  for (int r = 1; r < reps; ++r) {
    std::vector<std::pair<SM::Face_index, SM::Face_index>> again;
    auto a = std::chrono::steady_clock::now();
    PMP::self_intersections<CGAL::Sequential_tag>(sm, std::back_inserter(again));
    warm.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count());
  }
  std::sort(warm.begin(), warm.end());
  std::vector<uint32_t> degenerate;
  std::vector<std::pair<uint32_t, uint32_t>> pairs;
  for (auto [f, g] : out) {
    uint32_t i = uint32_t(f), j = uint32_t(g);  // faces are numbered in the order added
    if (i == j)
      degenerate.push_back(i);
    else
      pairs.emplace_back(std::min(i, j), std::max(i, j));
  }
  std::sort(degenerate.begin(), degenerate.end());
  std::sort(pairs.begin(), pairs.end());
  std::string d;
  for (size_t k = 0; k < degenerate.size(); ++k) d += (k ? "," : "") + std::to_string(degenerate[k]);
  std::string w = warm.empty() ? "" : ",\"warmSeconds\":" + std::to_string(warm[warm.size() / 2]);
  std::printf("{\"mesh\":true,\"triangles\":%u,\"degenerate\":[%s],\"pairs\":%zu,\"seconds\":%.6f%s}\n",
              mesh.nTriangles(), d.c_str(), pairs.size(), seconds, w.c_str());
  for (auto [i, j] : pairs) std::printf("%u %u\n", i, j);
  return 0;
}
