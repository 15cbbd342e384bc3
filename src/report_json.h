// The JSON writer of the reports and the hooks between the plain report (report.cpp) and
// the shell and defect report (shells_report.cpp). Private (not installed).
#pragma once

#include <cstdint>
#include <string>
#include <utility>

#include "float_format.h"
#include "stltopo/mesh.h"
#include "stltopo/report.h"
#include "stltopo/shells.h"
#include "stltopo/topology.h"

namespace stltopo::detail {

// With a sink, hands o to it once o holds a piece (kReportPiece bytes), and empties it: the
// reports in pieces call it after each list item, so a piece is a little over a MiB.
inline void spillPiece(std::string& o, const ReportSink* sink) {
  if (sink && o.size() >= kReportPiece) {
    (*sink)(o.data(), o.size());
    o.clear();
  }
}

// A JSON writer for the reports: s holds the text, `first` whether the next key or
// element is the first of its object or array. With a sink (the reports in pieces), spill()
// hands s to it once it holds a piece, and empties it: the lists call it after each item.
// A function that returns the text returns std::move(j.s): a member is returned by copy
// (a second 320 MB at the peak of a 1M-triangle soup's repair plan).
struct Json {
  std::string s;
  bool first = true;
  const ReportSink* sink = nullptr;
  void spill() { spillPiece(s, sink); }
  void open(char c) {
    s += c;
    first = true;
  }
  void close(char c) {
    s += c;
    first = false;
  }
  void key(const char* k) {
    if (!first) s += ',';
    first = false;
    s += '"';
    s += k;
    s += "\":";
  }
  void sep() {
    if (!first) s += ',';
    first = false;
  }
  void u(uint64_t v) { s += std::to_string(v); }
  void i(int64_t v) { s += std::to_string(v); }
  void str(const std::string& v) { s += jsonString(v); }
  void b(bool v) { s += v ? "true" : "false"; }
  void null() {
    s += "null";
    first = false;
  }
  // A float32 coordinate (-0 printed as 0) or a float64 figure, in shortest form.
  void f32(float v) {
    char b[kMaxFloatChars];
    s.append(b, formatShortest(v + 0.0f, b));
  }
  void f64(double v) {
    char b[kMaxDoubleChars];
    s.append(b, formatShortest(v, b));
  }
  // [x,y,z] of float32 coordinates, and {"min":[..],"max":[..]}.
  void point(const float* p) {
    s += '[';
    for (int k = 0; k < 3; ++k) {
      if (k) s += ',';
      f32(p[k]);
    }
    s += ']';
  }
  void bbox(const float* lo, const float* hi) {
    open('{');
    key("min");
    point(lo);
    key("max");
    point(hi);
    close('}');
  }
};

// The report's "shellList" and "defects" keys with their values (shells_report.cpp).
// With `nesting` (of these shells), each shell also gets its intersection and nesting keys.
void writeShellList(Json& j, const Array<Shell>& shells, const ShellNesting* nesting = nullptr);
// `checks` null: computed here; `intersections` null: "selfIntersections" is null.
void writeDefects(Json& j, const Mesh& mesh, const Topology& topo, const Defects& defects, uint32_t maxPerKind,
                  const TriangleChecks* checks = nullptr, const Intersections* intersections = nullptr);
// How infoJson/infoText write the ReportExtras (shells_report.cpp), handed to the report
// (report.cpp) so that the plain report does not depend on them.
struct ExtrasWriter {
  const ReportExtras& extras;
  void (*json)(Json& j, const Mesh& mesh, const Topology& topo, const ReportExtras& extras);
  // With a sink, the lines of a long list are handed to it from `out` as they are written.
  void (*text)(std::string& out, const Mesh& mesh, const Topology& topo, const ReportExtras& extras,
               const ReportSink* sink);
  // The intersection keys / line, when extras.intersections is given.
  void (*geometryJson)(Json& j, const ReportExtras& extras);
  void (*geometryText)(std::string& out, const ReportExtras& extras);
};
// The report; with a sink, what is left of it (the pieces spill() handed on come before).
std::string infoJsonWith(const std::string& file, const Mesh& mesh, const Topology* topo, const ExtrasWriter* extras,
                         const ReportSink* sink = nullptr);
std::string infoTextWith(const std::string& file, const Mesh& mesh, const Topology* topo, const ExtrasWriter* extras,
                         const ReportSink* sink = nullptr);

}  // namespace stltopo::detail
