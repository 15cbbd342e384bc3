// The `stltopo info --json` report. Shared by the native CLI and the wasm build,
// so both print byte-identical JSON.
#include <locale.h>
#include <clocale>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>

#include "float_format.h"
#include "report_json.h"
#include "text_format.h"
#include "triangle_figures.h"

namespace stltopo {
namespace {

using detail::Json;

void location(Json& j, const Status& st) {
  if (st.offset != kNoOffset) {
    j.key("offset");
    j.u(st.offset);
  }
  if (st.line != 0) {
    j.key("line");
    j.u(st.line);
  }
  if (st.triangle != kInvalid) {
    j.key("triangle");
    j.u(st.triangle);
  }
}

}  // namespace

std::string jsonString(const std::string& in) {
  std::string o = "\"";
  const unsigned char* p = reinterpret_cast<const unsigned char*>(in.data());
  size_t n = in.size();
  for (size_t i = 0; i < n;) {
    unsigned char c = p[i];
    if (c < 0x80) {
      switch (c) {
        case '"': o += "\\\""; break;
        case '\\': o += "\\\\"; break;
        case '\n': o += "\\n"; break;
        case '\r': o += "\\r"; break;
        case '\t': o += "\\t"; break;
        case '\b': o += "\\b"; break;
        case '\f': o += "\\f"; break;
        default:
          if (c < 0x20 || c == 0x7f) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", c);
            o += buf;
          } else {
            o += char(c);
          }
      }
      ++i;
      continue;
    }
    // Validate one UTF-8 sequence; invalid bytes become U+FFFD.
    int len = c >= 0xF0 && c <= 0xF4 ? 4 : c >= 0xE0 ? 3 : c >= 0xC2 && c <= 0xDF ? 2 : 0;
    bool ok = len > 0 && i + size_t(len) <= n;
    for (int k = 1; ok && k < len; ++k) ok = (p[i + k] & 0xC0) == 0x80;
    if (ok && len == 3) {
      unsigned cp = ((c & 0x0F) << 12) | ((p[i + 1] & 0x3F) << 6);
      ok = cp >= 0x800 && !(cp >= 0xD800 && cp <= 0xDFFF);
    }
    if (ok && len == 4) {
      unsigned cp = ((c & 0x07) << 18) | ((p[i + 1] & 0x3F) << 12);
      ok = cp >= 0x10000 && cp <= 0x10FFFF;
    }
    if (ok) {
      o.append(reinterpret_cast<const char*>(p + i), size_t(len));
      i += size_t(len);
    } else {
      o += "\xEF\xBF\xBD";
      ++i;
    }
  }
  o += '"';
  return o;
}

std::string infoJson(const std::string& file, const Mesh& mesh, const Topology* topo) {
  return detail::infoJsonWith(file, mesh, topo, nullptr);
}

// The report, and the extras' keys (shells_report.cpp) last when `extras` is given: a
// program that never asks for them links none of their code (the wasm core module).
std::string detail::infoJsonWith(const std::string& file, const Mesh& mesh, const Topology* topo,
                                 const ExtrasWriter* extras, const ReportSink* sink) {
  Json j;
  j.sink = sink;
  j.open('{');
  j.key("file");
  j.str(file);
  j.key("format");
  j.str(formatName(mesh.format));
  j.key("solids");
  j.open('[');
  for (const Solid& s : mesh.solids) {
    j.sep();
    j.open('{');
    j.key("name");
    j.str(s.name);
    j.key("triangles");
    j.u(s.triangleCount);
    j.close('}');
  }
  j.close(']');
  const uint32_t nt = mesh.nTriangles();
  j.key("triangles");
  j.u(nt);
  j.key("vertices");
  j.u(mesh.nVertices());
  if (topo && topo->tolerance > 0) {
    j.key("weldedVertices");
    j.u(topo->nWeldedVertices);
  }
  uint32_t degenerate = 0;
  if (topo) {
    degenerate = topo->nDegenerate;
  } else {
    for (uint32_t t = 0; t < nt; ++t) {
      const uint32_t* c = mesh.triangles.data() + 3 * size_t(t);
      degenerate += (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) ? 1 : 0;
    }
  }
  j.key("degenerateTriangles");
  j.u(degenerate);
  // The cheap geometric checks, always: computed here unless the caller has them, and then
  // handed to the extras' defect lists too (which list them), so they run once.
  TriangleChecks own;
  const TriangleChecks* checks = extras ? extras->extras.checks : nullptr;
  if (!checks && checkTriangles(mesh, topo, own).ok()) checks = &own;
  j.key("zeroAreaTriangles");
  if (checks)
    j.u(checks->zeroArea.size());
  else
    j.null();
  j.key("duplicateTriangles");
  if (checks)
    j.u(checks->nDuplicateTriangles);
  else
    j.null();
  j.key("colors");
  j.str(colorConventionName(mesh.colorConvention));
  j.key("normalMismatches");
  j.u(mesh.normalMismatches);
  j.key("bbox");
  if (mesh.nVertices() == 0) {
    j.s += "null";
    j.first = false;
  } else {
    j.bbox(mesh.bboxMin, mesh.bboxMax);
  }
  j.key("area");
  j.f64(mesh.area);
  j.key("volume");
  j.f64(mesh.volume);
  j.key("warnings");
  j.open('[');
  for (const Status& w : mesh.warnings) {
    j.sep();
    j.open('{');
    j.key("code");
    j.str(codeName(w.code));
    j.key("message");
    j.str(w.message);
    location(j, w);
    j.close('}');
  }
  j.close(']');
  if (topo) {
    const Topology& t = *topo;
#define STLTOPO_COUNT_KEY(count, name, doc) \
  j.key(#name);                             \
  j.u(t.count);
    STLTOPO_SURFACE_COUNTS(STLTOPO_COUNT_KEY)
#undef STLTOPO_COUNT_KEY
    j.key("holeSizes");
    j.open('[');
    for (uint32_t l = 0; l < t.nLoops(); ++l) {
      if (t.loopIsSeam[l]) continue;
      j.sep();
      j.u(t.loopOffsets[l + 1] - t.loopOffsets[l]);
    }
    j.close(']');
    j.key("shells");
    j.u(t.nShells);
    int64_t chi = t.eulerCharacteristic();
    j.key("eulerCharacteristic");
    j.i(chi);
    j.key("genus");
    if (t.watertight() && t.manifold()) {            // a pinched closed mesh is no surface: no genus
      int64_t twice = 2 * int64_t(t.nShells) - chi;  // genus = (2 shells - chi) / 2
      j.f64(double(twice) / 2);
    } else {
      j.s += "null";
    }
    j.key("watertight");
    j.b(t.watertight());
    j.key("manifold");
    j.b(t.manifold());
    // The geometry keys: null here; the extras' writer (the full module) fills them in.
    if (extras && extras->extras.intersections) {
      extras->geometryJson(j, extras->extras);
    } else {
      for (const char* k :
           {"selfIntersections", "intersectionKinds", "intersectingTriangles", "intersectionsComplete", "solid"}) {
        j.key(k);
        j.null();
      }
    }
    if (extras) {
      ReportExtras withChecks = extras->extras;
      withChecks.checks = checks;
      extras->json(j, mesh, t, withChecks);
    }
  }
  j.close('}');
  return std::move(j.s);
}

using detail::appendf;

std::string infoText(const std::string& file, const Mesh& m, const Topology* t) {
  return detail::infoTextWith(file, m, t, nullptr);
}

std::string detail::infoTextWith(const std::string& file, const Mesh& m, const Topology* t,
                                 const ExtrasWriter* extras, const ReportSink* sink) {
  std::string o;
  appendf(o, "%s: %s STL, %zu solid%s, %u triangles, %u vertices", file.c_str(), formatName(m.format), m.solids.size(),
          m.solids.size() == 1 ? "" : "s", m.nTriangles(), m.nVertices());
  if (t && t->tolerance > 0) appendf(o, " (%u after the tolerance weld)", t->nWeldedVertices);
  o += '\n';
  for (const auto& s : m.solids) appendf(o, "  solid \"%s\": %u triangles\n", s.name.c_str(), s.triangleCount);
  if (m.nVertices() > 0)
    appendf(o, "  bbox [%g, %g, %g] .. [%g, %g, %g]\n", m.bboxMin[0], m.bboxMin[1], m.bboxMin[2], m.bboxMax[0],
            m.bboxMax[1], m.bboxMax[2]);
  appendf(o, "  area %.9g, volume %.9g, colours %s, normals against winding %u\n", m.area, m.volume,
          colorConventionName(m.colorConvention), m.normalMismatches);
  if (t) {
    appendf(o, "  edges %u: boundary %u, non-manifold %u, inconsistent %u\n", t->nEdges, t->nBoundaryEdges,
            t->nNonManifoldEdges, t->nInconsistentEdges);
    appendf(o, "  holes %u, seams %u, non-manifold vertices %u, degenerate triangles %u\n", t->nHoles, t->nSeams,
            t->nNonManifoldVertices, t->nDegenerate);
    appendf(o, "  shells %u, Euler characteristic %lld, watertight %s, manifold %s\n", t->nShells,
            (long long)t->eulerCharacteristic(), t->watertight() ? "yes" : "no", t->manifold() ? "yes" : "no");
    TriangleChecks own;
    const TriangleChecks* checks = extras ? extras->extras.checks : nullptr;
    if (!checks && checkTriangles(m, t, own).ok()) checks = &own;
    if (checks)
      appendf(o, "  zero-area triangles %zu, duplicate triangles %u\n", checks->zeroArea.size(),
              checks->nDuplicateTriangles);
    if (extras && extras->extras.intersections) extras->geometryText(o, extras->extras);
    if (extras) extras->text(o, m, *t, extras->extras, sink);
  }
  for (const auto& w : m.warnings) appendf(o, "  warning %s\n", w.message.c_str());
  return o;
}

std::string errorJson(const std::string& file, const Status& error) {
  Json j;
  j.open('{');
  j.key("file");
  j.str(file);
  j.key("error");
  j.open('{');
  j.key("code");
  j.str(codeName(error.code));
  j.key("message");
  j.str(error.message);
  location(j, error);
  j.close('}');
  j.close('}');
  return std::move(j.s);
}

}  // namespace stltopo
