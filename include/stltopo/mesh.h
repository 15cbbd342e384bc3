// stltopo/mesh.h: the welded triangle mesh a read produces.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "stltopo/array.h"
#include "stltopo/status.h"

namespace stltopo {

enum class Format : uint8_t { Unknown, Binary, Ascii };
enum class ColorConvention : uint8_t { None, VisCam, Magics };
const char* formatName(Format f);                    // "binary", "ascii", "unknown"
const char* colorConventionName(ColorConvention c);  // "none", "viscam", "magics"

inline constexpr size_t kMaxNameBytes = 4096;  // longer solid names are cut (warning)

// A solid: one `solid ... endsolid` block or one binary part of a concatenation.
struct Solid {
  std::string name;  // ASCII: text after `solid`; binary: header up to first NUL; trimmed
  uint32_t firstTriangle = 0;
  uint32_t triangleCount = 0;
};

// The welded mesh. Vertex ids follow first appearance in corner order.
struct Mesh {
  Format format = Format::Unknown;
  Array<float> positions;      // 3*nVertices: x,y,z of vertex v at 3v..3v+2
  Array<uint32_t> triangles;   // 3*nTriangles: vertex ids of corner c of triangle t at 3t+c
  Array<uint16_t> attributes;  // nTriangles: binary attribute word (0 for ASCII)
  Array<float> normals;        // 3*nTriangles if ReadOptions::keepNormals, else empty
  Array<uint8_t> colors;       // 3*nTriangles RGB if colorConvention != None, else empty
  Array<uint8_t> colorValid;   // nTriangles: 1 when the triangle has a colour
  ColorConvention colorConvention = ColorConvention::None;
  std::vector<Solid> solids;
  std::vector<Status> warnings;  // same shape as errors; code is a warning code

  // Figures gathered while reading (over all triangles, degenerate ones too).
  uint32_t normalMismatches = 0;                         // stored non-zero normal points against the winding (exactly)
  double area = 0;                                       // sum of triangle areas
  double volume = 0;                                     // signed volume (divergence theorem)
  float bboxMin[3] = {0, 0, 0}, bboxMax[3] = {0, 0, 0};  // valid when nVertices() > 0

  uint32_t nVertices() const { return uint32_t(positions.size() / 3); }
  uint32_t nTriangles() const { return uint32_t(triangles.size() / 3); }
};

}  // namespace stltopo
