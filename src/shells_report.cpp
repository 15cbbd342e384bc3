// The shell list and the defect lists as report fragments: JSON for `info --json --shells
// --defects`, lines for the human-readable report. Same number format as infoJson.
#include <algorithm>

#include "report_json.h"
#include "stltopo/shells.h"
#include "text_format.h"
#include "try_alloc.h"

namespace stltopo {
namespace {

using detail::appendf;
using detail::Json;

const float* position(const Mesh& mesh, uint32_t v) { return mesh.positions.data() + size_t(v) * 3; }

// The bounding box of the vertices of loop h.
void loopBox(const Mesh& mesh, const Topology& t, uint32_t h, float* lo, float* hi) {
  for (uint32_t i = t.loopOffsets[h]; i < t.loopOffsets[h + 1]; ++i) {
    const float* p = position(mesh, t.vert[t.loopHalfedges[i]]);
    for (int k = 0; k < 3; ++k) {
      lo[k] = i == t.loopOffsets[h] ? p[k] : std::min(lo[k], p[k]);
      hi[k] = i == t.loopOffsets[h] ? p[k] : std::max(hi[k], p[k]);
    }
  }
}

bool isCut(const Topology& t, uint32_t e) { return t.pairKind[e >> 1] != uint8_t(EdgeKind::Boundary); }

// Holes (seams = false) or seams (true), each with its count and first `max` items.
void loops(Json& j, const Mesh& mesh, const Topology& t, const Defects& d, bool seams, uint32_t max) {
  j.open('{');
  j.key("count");
  j.u(seams ? t.nSeams : t.nHoles);
  j.key("items");
  j.open('[');
  uint32_t printed = 0;
  for (uint32_t h = 0; h < t.nLoops() && printed < max; ++h) {
    if (bool(t.loopIsSeam[h]) != seams) continue;
    ++printed;
    uint32_t b = t.loopOffsets[h], n = t.loopOffsets[h + 1] - b;
    j.sep();
    j.open('{');
    j.key("id");
    j.u(h);
    j.key("edges");
    j.u(n);
    j.key("perimeter");
    j.f64(t.loopPerimeter[h]);
    j.key("vertices");
    j.open('[');
    for (uint32_t i = 0; i < std::min(n, max); ++i) {
      j.sep();
      j.u(t.vert[t.loopHalfedges[b + i]]);
    }
    j.close(']');
    float lo[3], hi[3];
    loopBox(mesh, t, h, lo, hi);
    j.key("bbox");
    j.bbox(lo, hi);
    j.key("shell");
    j.u(d.loopShell[h]);
    if (seams) {
      j.key("cutEdges");
      j.open('[');
      uint32_t cut = 0;
      for (uint32_t i = 0; i < n && cut < max; ++i) {
        uint32_t e = t.loopHalfedges[b + i];
        if (!isCut(t, e)) continue;
        ++cut;
        j.sep();
        j.s += '[' + std::to_string(t.vert[e]) + ',' + std::to_string(t.vert[twin(e)]) + ']';
      }
      j.close(']');
    }
    j.close('}');
    j.spill();
  }
  j.close(']');
  j.close('}');
}

void edgeVertices(Json& j, const Array<uint32_t>& vertices, size_t i) {
  j.key("vertices");
  j.s += '[' + std::to_string(vertices[2 * i]) + ',' + std::to_string(vertices[2 * i + 1]) + ']';
}

void uintList(Json& j, const uint32_t* p, size_t n) {
  j.open('[');
  for (size_t i = 0; i < n; ++i) {
    j.sep();
    j.u(p[i]);
  }
  j.close(']');
}

// The corners that coincide, as a list of corner indices.
std::string cornerList(uint8_t mask, const char* sep) {
  if (mask == 7) return std::string("0") + sep + "1" + sep + "2";
  int i = mask == 2 ? 1 : 0, k = mask == 1 ? 1 : 2;
  return std::to_string(i) + sep + std::to_string(k);
}

void appendPoint(std::string& o, const float* p) { appendf(o, "[%g, %g, %g]", p[0], p[1], p[2]); }

}  // namespace

namespace {

void writeShell(Json& j, const Shell& s, uint32_t id, const ShellNesting* nest = nullptr) {
  j.open('{');
  j.key("id");
  j.u(id);
  j.key("triangles");
  j.u(s.triangles);
  j.key("vertices");
  j.u(s.vertices);
#define STLTOPO_COUNT_KEY(count, name, doc) \
  j.key(#name);                             \
  j.u(s.name);
  STLTOPO_SURFACE_COUNTS(STLTOPO_COUNT_KEY)
#undef STLTOPO_COUNT_KEY
  j.key("eulerCharacteristic");
  j.i(s.eulerCharacteristic());
  j.key("genus");
  if (s.hasGenus())
    j.f64(s.genus());
  else
    j.null();
  j.key("closed");
  j.b(s.closed());
  j.key("manifold");
  j.b(s.manifold());
  j.key("consistent");
  j.b(s.consistent());
  j.key("orientation");
  j.str(orientationName(s.orientation()));
  j.key("solid");
  if (s.solid == kMixedSolid)
    j.str("mixed");
  else if (s.solid == kInvalid)
    j.null();
  else
    j.u(s.solid);
  j.key("bbox");
  j.bbox(s.bboxMin, s.bboxMax);
  j.key("area");
  j.f64(s.area);
  j.key("volume");
  j.f64(s.volume);
  if (nest) {
    j.key("selfIntersects");
    j.b(nest->selfIntersects[id] != 0);
    j.key("intersectsShells");
    uintList(j, nest->intersectsShells.data() + nest->intersectsOffsets[id],
             nest->intersectsOffsets[id + 1] - nest->intersectsOffsets[id]);
    j.key("parent");
    if (nest->parent[id] == kInvalid)
      j.null();
    else
      j.u(nest->parent[id]);
    j.key("depth");
    if (nest->depth[id] == kInvalid)
      j.null();
    else
      j.u(nest->depth[id]);
  }
  j.close('}');
}

}  // namespace

void detail::writeShellList(Json& j, const Array<Shell>& shells, const ShellNesting* nesting) {
  if (nesting && !nesting->isOf(shells.size())) nesting = nullptr;
  j.key("shellList");
  // About 410 bytes a shell (480 with its nesting): room for them at once (pages not written
  // to are never touched), instead of the string's doublings, each a copy into fresh memory (a
  // fifth of `info --json --shells` of 20,000 shells; bench/PROFILE.md, *Stop 50*). Without
  // the room, the list grows as before.
  // In pieces (a sink), room for a piece and a shell.
  const size_t room = shells.size() * (nesting ? 576 : 512);
  (void)detail::tryReserve(j.s, j.s.size() + (j.sink ? std::min(room, kReportPiece + 4096) : room));
  j.open('[');
  for (size_t i = 0; i < shells.size(); ++i) {
    j.sep();
    writeShell(j, shells[i], uint32_t(i), nesting);
    j.spill();
  }
  j.close(']');
}

std::string shellJson(const Shell& shell, uint32_t id) {
  Json j;
  writeShell(j, shell, id);
  return std::move(j.s);
}

std::string splitLineJson(const std::string& file, const Shell& shell, uint32_t id) {
  Json j;
  j.open('{');
  j.key("file");
  j.str(file);
  j.key("shell");
  writeShell(j, shell, id);
  j.close('}');
  return std::move(j.s);
}

std::string shellListJson(const Array<Shell>& shells, const ShellNesting* nesting) {
  Json j;
  detail::writeShellList(j, shells, nesting);
  return std::move(j.s);
}

std::string shellRangeJson(const Array<Shell>& shells, const ShellNesting* nesting, size_t first, size_t count) {
  if (nesting && !nesting->isOf(shells.size())) nesting = nullptr;
  const size_t end = first >= shells.size() ? first : first + std::min(count, shells.size() - first);
  Json j;
  (void)detail::tryReserve(j.s, (end - first) * (nesting ? 576 : 512) + 2);
  j.open('[');
  for (size_t i = first; i < end; ++i) {
    j.sep();
    writeShell(j, shells[i], uint32_t(i), nesting);
  }
  j.close(']');
  return std::move(j.s);
}

void detail::writeDefects(Json& j, const Mesh& mesh, const Topology& t, const Defects& d, uint32_t max,
                          const TriangleChecks* checks, const Intersections* x) {
  j.key("defects");
  j.open('{');
  j.key("holes");
  loops(j, mesh, t, d, false, max);
  j.key("seams");
  loops(j, mesh, t, d, true, max);
  for (int inconsistent = 0; inconsistent < 2; ++inconsistent) {
    const Array<uint32_t>& vertices = inconsistent ? d.inconsistentEdgeVertices : d.nonManifoldEdgeVertices;
    size_t n = vertices.size() / 2;
    j.key(inconsistent ? "inconsistentEdges" : "nonManifoldEdges");
    j.open('{');
    j.key("count");
    j.u(n);
    j.key("items");
    j.open('[');
    for (size_t i = 0; i < std::min<size_t>(n, max); ++i) {
      j.sep();
      j.open('{');
      edgeVertices(j, vertices, i);
      if (!inconsistent) {
        j.key("positions");
        j.s += '[';
        j.point(position(mesh, vertices[2 * i]));
        j.s += ',';
        j.point(position(mesh, vertices[2 * i + 1]));
        j.s += ']';
        uint32_t b = d.nonManifoldEdgeOffsets[i], e = d.nonManifoldEdgeOffsets[i + 1];
        j.key("triangles");
        uintList(j, d.nonManifoldEdgeTriangles.data() + b, e - b);
      } else {
        j.key("triangles");
        uintList(j, d.inconsistentEdgeTriangles.data() + 2 * i, 2);
      }
      j.close('}');
      j.spill();
    }
    j.close(']');
    j.close('}');
  }
  j.key("nonManifoldVertices");
  j.open('{');
  j.key("count");
  j.u(d.nonManifoldVertices.size());
  j.key("items");
  j.open('[');
  for (size_t i = 0; i < std::min<size_t>(d.nonManifoldVertices.size(), max); ++i) {
    j.sep();
    j.open('{');
    j.key("vertex");
    j.u(d.nonManifoldVertices[i]);
    j.key("position");
    j.point(position(mesh, d.nonManifoldVertices[i]));
    j.key("cycles");
    j.u(d.nonManifoldVertexCycles[i]);
    j.close('}');
    j.spill();
  }
  j.close(']');
  j.close('}');
  j.key("degenerateTriangles");
  j.open('{');
  j.key("count");
  j.u(d.degenerateTriangles.size());
  j.key("items");
  j.open('[');
  for (size_t i = 0; i < std::min<size_t>(d.degenerateTriangles.size(), max); ++i) {
    j.sep();
    j.open('{');
    j.key("triangle");
    j.u(d.degenerateTriangles[i]);
    j.key("corners");
    j.s += '[' + cornerList(d.degenerateCorners[i], ",") + ']';
    j.close('}');
    j.spill();
  }
  j.close(']');
  j.close('}');
  TriangleChecks own;
  if (!checks && checkTriangles(mesh, &t, own).ok()) checks = &own;
  j.key("zeroAreaTriangles");
  if (checks) {
    j.open('{');
    j.key("count");
    j.u(checks->zeroArea.size());
    j.key("items");
    j.open('[');
    for (size_t i = 0; i < std::min<size_t>(checks->zeroArea.size(), max); ++i) {
      j.sep();
      j.open('{');
      j.key("triangle");
      j.u(checks->zeroArea[i]);
      j.close('}');
      j.spill();
    }
    j.close(']');
    j.close('}');
  } else {
    j.null();
  }
  j.key("duplicateTriangles");
  if (checks) {
    const uint32_t groups = checks->nDuplicateGroups();
    j.open('{');
    j.key("count");
    j.u(groups);
    j.key("items");
    j.open('[');
    for (uint32_t g = 0; g < std::min(groups, max); ++g) {
      j.sep();
      j.open('{');
      const uint32_t b = checks->duplicateOffsets[g], e = checks->duplicateOffsets[g + 1];
      j.key("triangles");
      uintList(j, checks->duplicateTriangles.data() + b, e - b);
      j.key("orientation");
      j.str(duplicateOrientationName(DuplicateOrientation(checks->duplicateOrientation[g])));
      j.close('}');
      j.spill();
    }
    j.close(']');
    j.close('}');
  } else {
    j.null();
  }
  j.key("selfIntersections");
  if (x) {
    j.open('{');
    j.key("count");
    j.u(x->nPairs());
    j.key("items");
    j.open('[');
    for (size_t i = 0; i < std::min<uint64_t>(x->nPairs(), max); ++i) {
      j.sep();
      j.open('{');
      j.key("triangles");
      uintList(j, x->pairs.data() + 2 * i, 2);
      j.key("kind");
      j.str(intersectionKindName(IntersectionKind(x->kinds[i])));
      j.key("point");
      j.open('[');
      for (int c = 0; c < 3; ++c) {
        j.sep();
        j.f64(x->points[3 * i + c] + 0.0);
      }
      j.close(']');
      j.close('}');
      j.spill();
    }
    j.close(']');
    j.close('}');
  } else {
    j.null();
  }
  j.close('}');
}

std::string defectsJson(const Mesh& mesh, const Topology& t, const Defects& d, uint32_t max) {
  Json j;
  detail::writeDefects(j, mesh, t, d, max);
  return std::move(j.s);
}

std::string defectsText(const Mesh& mesh, const Topology& t, const Defects& d, uint32_t max) {
  std::string o;
  auto more = [&](size_t count, size_t shown, const char* what) {
    if (count > shown) appendf(o, "    ... and %zu more %s\n", count - shown, what);
  };
  for (int seams = 0; seams < 2; ++seams) {
    uint32_t shown = 0;
    for (uint32_t h = 0; h < t.nLoops() && shown < max; ++h) {
      if (bool(t.loopIsSeam[h]) != bool(seams)) continue;
      ++shown;
      uint32_t b = t.loopOffsets[h], n = t.loopOffsets[h + 1] - b, cut = 0;
      for (uint32_t i = b; i < b + n; ++i) cut += isCut(t, t.loopHalfedges[i]);
      float lo[3], hi[3];
      loopBox(mesh, t, h, lo, hi);
      appendf(o, "  %s %u: %u edges", seams ? "seam" : "hole", h, n);
      if (seams) appendf(o, " (%u cut)", cut);
      appendf(o, ", perimeter %.9g, shell %u, bbox ", t.loopPerimeter[h], d.loopShell[h]);
      appendPoint(o, lo);
      o += " .. ";
      appendPoint(o, hi);
      o += '\n';
    }
    more(seams ? t.nSeams : t.nHoles, shown, seams ? "seams" : "holes");
  }
  size_t nNme = d.nonManifoldEdgeVertices.size() / 2, nIe = d.inconsistentEdgeVertices.size() / 2;
  for (size_t i = 0; i < std::min<size_t>(nNme, max); ++i) {
    uint32_t a = d.nonManifoldEdgeVertices[2 * i], b = d.nonManifoldEdgeVertices[2 * i + 1];
    uint32_t t0 = d.nonManifoldEdgeOffsets[i], t1 = d.nonManifoldEdgeOffsets[i + 1];
    appendf(o, "  non-manifold edge %u-%u: ", a, b);
    appendPoint(o, position(mesh, a));
    o += " - ";
    appendPoint(o, position(mesh, b));
    appendf(o, ", %u triangles:", t1 - t0);
    for (uint32_t k = t0; k < std::min(t1, t0 + 8); ++k) appendf(o, " %u", d.nonManifoldEdgeTriangles[k]);
    o += t1 - t0 > 8 ? " ...\n" : "\n";
  }
  more(nNme, std::min<size_t>(nNme, max), "non-manifold edges");
  for (size_t i = 0; i < std::min<size_t>(nIe, max); ++i) {
    uint32_t a = d.inconsistentEdgeVertices[2 * i], b = d.inconsistentEdgeVertices[2 * i + 1];
    appendf(o, "  inconsistent edge %u-%u: ", a, b);
    appendPoint(o, position(mesh, a));
    o += " - ";
    appendPoint(o, position(mesh, b));
    appendf(o, ", triangles %u and %u\n", d.inconsistentEdgeTriangles[2 * i], d.inconsistentEdgeTriangles[2 * i + 1]);
  }
  more(nIe, std::min<size_t>(nIe, max), "inconsistent edges");
  size_t nNmv = d.nonManifoldVertices.size();
  for (size_t i = 0; i < std::min<size_t>(nNmv, max); ++i) {
    appendf(o, "  non-manifold vertex %u at ", d.nonManifoldVertices[i]);
    appendPoint(o, position(mesh, d.nonManifoldVertices[i]));
    appendf(o, ": %u vertex cycles\n", d.nonManifoldVertexCycles[i]);
  }
  more(nNmv, std::min<size_t>(nNmv, max), "non-manifold vertices");
  size_t nDeg = d.degenerateTriangles.size();
  for (size_t i = 0; i < std::min<size_t>(nDeg, max); ++i) {
    uint32_t tri = d.degenerateTriangles[i];
    uint8_t mask = d.degenerateCorners[i];
    appendf(o, "  degenerate triangle %u: corners %s coincide at ", tri,
            mask == 7 ? "0, 1 and 2" : cornerList(mask, " and ").c_str());
    appendPoint(o, position(mesh, mesh.triangles[size_t(tri) * 3 + (mask == 2 ? 1 : 0)]));
    o += '\n';
  }
  more(nDeg, std::min<size_t>(nDeg, max), "degenerate triangles");
  return o;
}

namespace {

// The line of each shell, appended to o; with a sink, o goes to it whenever it holds a piece.
void appendShellsText(std::string& o, const Array<Shell>& shells, const ReportSink* sink) {
  for (size_t i = 0; i < shells.size(); ++i) {
    const Shell& s = shells[i];
    appendf(o, "  shell %zu: %u triangles, %s, %s, %s, volume %.9g, area %.9g, bbox ", i, s.triangles,
            s.closed() ? "closed" : "not closed", s.manifold() ? "manifold" : "non-manifold",
            orientationName(s.orientation()), s.volume, s.area);
    appendPoint(o, s.bboxMin);
    o += " .. ";
    appendPoint(o, s.bboxMax);
    o += '\n';
    detail::spillPiece(o, sink);
  }
}

}  // namespace

std::string shellsText(const Array<Shell>& shells) {
  std::string o;
  appendShellsText(o, shells, nullptr);
  return o;
}

namespace {

void extrasJson(Json& j, const Mesh& mesh, const Topology& t, const ReportExtras& x) {
  if (x.shells) detail::writeShellList(j, *x.shells, x.intersections ? x.nesting : nullptr);
  if (x.defects) detail::writeDefects(j, mesh, t, *x.defects, x.maxDefects, x.checks, x.intersections);
}
void extrasText(std::string& o, const Mesh& mesh, const Topology& t, const ReportExtras& x, const ReportSink* sink) {
  if (x.shells) appendShellsText(o, *x.shells, sink);
  if (x.defects) o += defectsText(mesh, t, *x.defects, x.maxDefects);
  if (x.defects && x.intersections) {
    const Intersections& f = *x.intersections;
    const uint64_t shown = std::min<uint64_t>(f.nPairs(), x.maxDefects);
    for (uint64_t i = 0; i < shown; ++i)
      appendf(o, "  self-intersection: triangles %u and %u, %s, at [%g, %g, %g]\n", f.pairs[2 * i], f.pairs[2 * i + 1],
              intersectionKindName(IntersectionKind(f.kinds[i])), f.points[3 * i], f.points[3 * i + 1],
              f.points[3 * i + 2]);
    if (f.nPairs() > shown)
      appendf(o, "  ... and %llu more self-intersections\n", (unsigned long long)(f.nPairs() - shown));
  }
}

void geometryJson(Json& j, const ReportExtras& e) {
  const Intersections& x = *e.intersections;
  j.key("selfIntersections");
  j.u(x.nPairs());
  j.key("intersectionKinds");
  j.open('{');
  j.key("crossing");
  j.u(x.nCrossing);
  j.key("touching");
  j.u(x.nTouching);
  j.key("coplanar");
  j.u(x.nCoplanar);
  j.close('}');
  j.key("intersectingTriangles");
  j.u(x.nIntersectingTriangles);
  j.key("intersectionsComplete");
  j.b(x.complete);
  j.key("solid");
  j.b(e.solid && x.complete);
}

void geometryText(std::string& o, const ReportExtras& e) {
  const Intersections& x = *e.intersections;
  appendf(o, "  self-intersections %s%llu (crossing %llu, touching %llu, coplanar %llu) over %u triangles, solid %s\n",
          x.complete ? "" : "at least ", (unsigned long long)x.nPairs(), (unsigned long long)x.nCrossing,
          (unsigned long long)x.nTouching, (unsigned long long)x.nCoplanar, x.nIntersectingTriangles,
          e.solid && x.complete ? "yes" : "no");
}

}  // namespace

namespace {

// The writer of the extras (the shell list, the defects, the geometry) for the reports.
detail::ExtrasWriter writerOf(const ReportExtras& extras) {
  return {extras, extrasJson, extrasText, geometryJson, geometryText};
}

// A report in pieces: what its writer left after the pieces it handed on, handed on too.
void handOn(const ReportSink& sink, const std::string& rest) {
  if (!rest.empty()) sink(rest.data(), rest.size());
}

}  // namespace

std::string infoJson(const std::string& file, const Mesh& mesh, const Topology* topo, const ReportExtras& extras) {
  const detail::ExtrasWriter w = writerOf(extras);
  return detail::infoJsonWith(file, mesh, topo, &w);
}

void infoJson(const ReportSink& sink, const std::string& file, const Mesh& mesh, const Topology* topo,
              const ReportExtras& extras) {
  const detail::ExtrasWriter w = writerOf(extras);
  handOn(sink, detail::infoJsonWith(file, mesh, topo, &w, &sink));
}

std::string infoText(const std::string& file, const Mesh& mesh, const Topology* topo, const ReportExtras& extras) {
  const detail::ExtrasWriter w = writerOf(extras);
  return detail::infoTextWith(file, mesh, topo, &w);
}

void infoText(const ReportSink& sink, const std::string& file, const Mesh& mesh, const Topology* topo,
              const ReportExtras& extras) {
  const detail::ExtrasWriter w = writerOf(extras);
  handOn(sink, detail::infoTextWith(file, mesh, topo, &w, &sink));
}

}  // namespace stltopo
