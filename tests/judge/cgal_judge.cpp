// stltopo_cgal_judge: the independent judge of issue 21 (zero-area, duplicate and
// self-intersecting triangles), built on CGAL. Test-only: never shipped, never linked into
// the library. See tests/judge/README.md.
//
// usage: stltopo_cgal_judge [--count-only] [--brute] FILE
//   Reads FILE with stltopo's reader (the exactly welded mesh), then prints
//   {"triangles":T,"zeroArea":[...],"duplicateGroups":[[...],...],"pairs":P,
//    "kinds":{"crossing":C,"touching":U,"coplanar":L},"seconds":S}
//   and one line "i j kind" per intersecting pair (i < j), sorted by (i, j).
//   --count-only prints the first line only. --brute tests every pair instead of the boxes
//   that CGAL's box_self_intersection_d reports (O(n^2): a check of the pair search on small
//   meshes). S is the wall time of the pair search (boxes + CGAL's intersection predicates),
//   without reading, the cheap per-triangle passes and the classification into kinds.
//   Exit status: 0 on success, 1 when the file cannot be read (the error on stderr), 2 on
//   usage errors.
//
// Definitions (issue 21), on the welded mesh, every predicate exact (CGAL Epick: exact
// predicates; Epeck for the one construction, the intersection of two coplanar triangles):
// - degenerate: a repeated vertex id (stltopo's degenerateTriangles); ignored here.
// - zero-area: three distinct ids whose positions are exactly collinear.
// - duplicate group: two or more triangles with three distinct ids and the same SET of ids
//   (either orientation). As in the text, zero-area triangles can form a group too
//   (they are "non-degenerate"); this changes no pair, since zero-area triangles are never
//   in a pair.
// - pair (i < j): both triangles neither degenerate nor zero-area, not in one duplicate group,
//   and sharing more than their common sub-face (CGAL's do_faces_intersect, by vertex id):
//     no shared id      -> do_intersect(Triangle_3, Triangle_3) (closed triangles);
//     one shared id a   -> the edge of either one opposite a meets the other (closed) triangle;
//     shared edge ab, (a,b,c) and (a,b,d) -> coplanar(a,b,c,d) and c, d strictly on the same
//                          side of ab (coplanar_orientation(a,b,c,d) == POSITIVE).
// - kind: coplanar when all six corners are coplanar and the intersection has positive area;
//   touching when not coplanar and one triangle has no corner strictly on each side of the
//   other's plane; crossing otherwise.
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/intersections.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <unordered_map>
#include <variant>
#include <vector>

#include "stltopo/stltopo.h"

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using EK = CGAL::Exact_predicates_exact_constructions_kernel;
using Point = K::Point_3;
using Triangle = K::Triangle_3;
using Segment = K::Segment_3;

enum Kind { kCrossing = 0, kTouching = 1, kCoplanar = 2 };
const char* kKindName[] = {"crossing", "touching", "coplanar"};

struct Judge {
  const stltopo::Mesh& mesh;
  std::vector<Point> pts;  // one per welded vertex; float32 -> double is exact

  explicit Judge(const stltopo::Mesh& m) : mesh(m) {
    const float* p = m.positions.data();
    pts.reserve(m.nVertices());
    for (uint32_t v = 0; v < m.nVertices(); ++v)
      pts.emplace_back(double(p[3 * v]), double(p[3 * v + 1]), double(p[3 * v + 2]));
  }

  const uint32_t* tri(uint32_t t) const { return mesh.triangles.data() + 3 * size_t(t); }
  const Point& P(uint32_t v) const { return pts[v]; }
  Triangle T(uint32_t t) const {
    const uint32_t* a = tri(t);
    return Triangle(P(a[0]), P(a[1]), P(a[2]));
  }

  // CGAL's "strict" intersection (do_faces_intersect), with the shared sub-face found by
  // vertex id instead of by half-edge adjacency.
  bool intersect(uint32_t ti, uint32_t tj) const {
    const uint32_t* a = tri(ti);
    const uint32_t* b = tri(tj);
    int sharedA[3], sharedB[3], n = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (a[i] == b[j]) {
          sharedA[n] = i;
          sharedB[n] = j;
          ++n;
        }
    if (n == 0) return CGAL::do_intersect(T(ti), T(tj));
    if (n == 1) {
      int i = sharedA[0], j = sharedB[0];
      Segment sa(P(a[(i + 1) % 3]), P(a[(i + 2) % 3]));
      Segment sb(P(b[(j + 1) % 3]), P(b[(j + 2) % 3]));
      return CGAL::do_intersect(T(ti), sb) || CGAL::do_intersect(T(tj), sa);
    }
    if (n == 2) {
      // The corner of each triangle that is not on the shared edge.
      int ci = 3 - sharedA[0] - sharedA[1], dj = 3 - sharedB[0] - sharedB[1];
      const Point& pa = P(a[sharedA[0]]);
      const Point& pb = P(a[sharedA[1]]);
      const Point& c = P(a[ci]);
      const Point& d = P(b[dj]);
      return CGAL::coplanar(pa, pb, c, d) && CGAL::coplanar_orientation(pa, pb, c, d) == CGAL::POSITIVE;
    }
    return false;  // the same set of ids: a duplicate group, never a pair (filtered before)
  }

  // Positive area of the intersection of two coplanar triangles: CGAL's exact construction.
  bool coplanarOverlap(uint32_t ti, uint32_t tj) const {
    auto ek = [&](uint32_t t) {
      const uint32_t* a = tri(t);
      auto q = [&](uint32_t v) { return EK::Point_3(pts[v].x(), pts[v].y(), pts[v].z()); };
      return EK::Triangle_3(q(a[0]), q(a[1]), q(a[2]));
    };
    auto res = CGAL::intersection(ek(ti), ek(tj));
    if (!res) return false;
    if (const EK::Triangle_3* t = boost::get<EK::Triangle_3>(&*res)) return !t->is_degenerate();
    if (const std::vector<EK::Point_3>* poly = boost::get<std::vector<EK::Point_3>>(&*res)) {
      const auto& v = *poly;
      for (size_t k = 2; k < v.size(); ++k)
        if (!CGAL::collinear(v[0], v[1], v[k])) return true;
      return false;
    }
    return false;  // a point or a segment
  }

  Kind kind(uint32_t ti, uint32_t tj) const {
    const uint32_t* a = tri(ti);
    const uint32_t* b = tri(tj);
    int pos[2] = {0, 0}, neg[2] = {0, 0};
    for (int k = 0; k < 3; ++k) {
      CGAL::Orientation oa = CGAL::orientation(P(b[0]), P(b[1]), P(b[2]), P(a[k]));
      CGAL::Orientation ob = CGAL::orientation(P(a[0]), P(a[1]), P(a[2]), P(b[k]));
      pos[0] += oa == CGAL::POSITIVE, neg[0] += oa == CGAL::NEGATIVE;
      pos[1] += ob == CGAL::POSITIVE, neg[1] += ob == CGAL::NEGATIVE;
    }
    if (pos[0] + neg[0] == 0) return coplanarOverlap(ti, tj) ? kCoplanar : kTouching;
    bool aBoth = pos[0] && neg[0], bBoth = pos[1] && neg[1];
    return aBoth && bBoth ? kCrossing : kTouching;
  }
};

struct Key {
  uint32_t v[3];
  bool operator==(const Key& o) const { return v[0] == o.v[0] && v[1] == o.v[1] && v[2] == o.v[2]; }
};
struct KeyHash {
  size_t operator()(const Key& k) const {
    uint64_t h = k.v[0] * 0x9E3779B97F4A7C15ull;
    h ^= (h >> 29) ^ (k.v[1] * 0xBF58476D1CE4E5B9ull);
    h ^= (h >> 31) ^ (k.v[2] * 0x94D049BB133111EBull);
    return size_t(h ^ (h >> 32));
  }
};

stltopo::Status readFile(const char* path, stltopo::Mesh& mesh) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return stltopo::Status::error(stltopo::Code::InvalidArgument, std::string("cannot open ") + path);
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return stltopo::readStl(bytes.data(), bytes.size(), mesh);
}

std::string jsonString(const std::string& s) {
  std::string o = "\"";
  for (unsigned char c : s) {
    if (c == '"' || c == '\\')
      o += '\\', o += char(c);
    else if (c < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      o += buf;
    } else
      o += char(c);
  }
  return o + "\"";
}

}  // namespace

int main(int argc, char** argv) {
  bool countOnly = false, brute = false;
  const char* file = nullptr;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--count-only"))
      countOnly = true;
    else if (!std::strcmp(argv[i], "--brute"))
      brute = true;
    else if (argv[i][0] == '-' && argv[i][1] != '\0')
      file = nullptr, argc = -1;
    else if (!file)
      file = argv[i];
    else
      argc = -1;
    if (argc < 0) break;
  }
  if (argc < 0 || !file) {
    std::fprintf(stderr, "usage: stltopo_cgal_judge [--count-only] [--brute] FILE\n");
    return 2;
  }

  stltopo::Mesh mesh;
  stltopo::Status s = readFile(file, mesh);
  if (!s.ok()) {
    std::fprintf(stderr, "{\"file\":%s,\"error\":\"%s\",\"message\":%s}\n", jsonString(file).c_str(),
                 stltopo::codeName(s.code), jsonString(s.message).c_str());
    return 1;
  }

  Judge judge(mesh);
  const uint32_t nt = mesh.nTriangles();

  // Per-triangle passes: degenerate (repeated id), zero-area (exactly collinear), duplicates.
  std::vector<uint8_t> candidate(nt, 0);
  std::vector<uint32_t> zeroArea;
  std::vector<uint32_t> group(nt, stltopo::kInvalid);  // duplicate group of t, if any
  std::vector<std::vector<uint32_t>> groups;
  {
    std::unordered_map<Key, uint32_t, KeyHash> first;  // sorted ids -> first triangle / group
    first.reserve(nt);
    for (uint32_t t = 0; t < nt; ++t) {
      const uint32_t* a = judge.tri(t);
      if (a[0] == a[1] || a[1] == a[2] || a[0] == a[2]) continue;  // degenerate
      if (CGAL::collinear(judge.P(a[0]), judge.P(a[1]), judge.P(a[2])))
        zeroArea.push_back(t);
      else
        candidate[t] = 1;
      Key k{{a[0], a[1], a[2]}};
      std::sort(k.v, k.v + 3);
      auto [it, inserted] = first.try_emplace(k, t);
      if (inserted) continue;
      uint32_t f = it->second;
      if (group[f] == stltopo::kInvalid) {
        group[f] = uint32_t(groups.size());
        groups.push_back({f});
      }
      group[t] = group[f];
      groups[group[f]].push_back(t);
    }
    // Members are in increasing id order; groups by their lowest id, as the issue lists them.
    std::sort(groups.begin(), groups.end());
    for (uint32_t g = 0; g < groups.size(); ++g)
      for (uint32_t t : groups[g]) group[t] = g;
  }

  // The pair search: CGAL's box_self_intersection_d over closed bounding boxes (as PMP's
  // self_intersections does), then the exact test.
  using Box =
      CGAL::Box_intersection_d::Box_with_info_d<double, 3, uint32_t, CGAL::Box_intersection_d::ID_FROM_BOX_ADDRESS>;
  std::vector<std::pair<uint32_t, uint32_t>> pairs;
  auto consider = [&](uint32_t i, uint32_t j) {
    if (i > j) std::swap(i, j);
    if (group[i] != stltopo::kInvalid && group[i] == group[j]) return;
    if (judge.intersect(i, j)) pairs.emplace_back(i, j);
  };
  auto t0 = std::chrono::steady_clock::now();
  if (brute) {
    for (uint32_t i = 0; i < nt; ++i)
      if (candidate[i])
        for (uint32_t j = i + 1; j < nt; ++j)
          if (candidate[j]) consider(i, j);
  } else {
    std::vector<Box> boxes;
    boxes.reserve(nt);
    for (uint32_t t = 0; t < nt; ++t) {
      if (!candidate[t]) continue;
      const uint32_t* a = judge.tri(t);
      boxes.emplace_back(judge.P(a[0]).bbox() + judge.P(a[1]).bbox() + judge.P(a[2]).bbox(), t);
    }
    std::vector<const Box*> ptrs;
    ptrs.reserve(boxes.size());
    for (const Box& b : boxes) ptrs.push_back(&b);
    CGAL::box_self_intersection_d<CGAL::Sequential_tag>(
        ptrs.begin(), ptrs.end(), [&](const Box* b, const Box* c) { consider(b->info(), c->info()); },
        std::ptrdiff_t(2000));
  }
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::sort(pairs.begin(), pairs.end());

  std::vector<uint8_t> kinds(pairs.size());
  size_t count[3] = {0, 0, 0};
  for (size_t k = 0; k < pairs.size(); ++k) {
    kinds[k] = uint8_t(judge.kind(pairs[k].first, pairs[k].second));
    ++count[kinds[k]];
  }

  std::string out = "{\"triangles\":" + std::to_string(nt) + ",\"zeroArea\":[";
  for (size_t k = 0; k < zeroArea.size(); ++k) out += (k ? "," : "") + std::to_string(zeroArea[k]);
  out += "],\"duplicateGroups\":[";
  for (size_t g = 0; g < groups.size(); ++g) {
    out += g ? ",[" : "[";
    for (size_t k = 0; k < groups[g].size(); ++k) out += (k ? "," : "") + std::to_string(groups[g][k]);
    out += "]";
  }
  char tail[256];
  std::snprintf(tail, sizeof tail,
                "],\"pairs\":%zu,\"kinds\":{\"crossing\":%zu,\"touching\":%zu,\"coplanar\":%zu},\"seconds\":%.6f}\n",
                pairs.size(), count[kCrossing], count[kTouching], count[kCoplanar], seconds);
  out += tail;
  std::fputs(out.c_str(), stdout);
  if (!countOnly)
    for (size_t k = 0; k < pairs.size(); ++k)
      std::printf("%u %u %s\n", pairs[k].first, pairs[k].second, kKindName[kinds[k]]);
  return std::fflush(stdout) == 0 ? 0 : 1;
}
