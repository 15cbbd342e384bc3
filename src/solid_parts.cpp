#include "solid_parts.h"

#include "stltopo/status.h"
#include "text_format.h"

namespace stltopo::detail {

Status solidParts(const Solid* solids, size_t nSolids, uint64_t nTriangles, Array<SolidPart>& out) {
  uint64_t covered = 0;
  for (size_t s = 0; s < nSolids; ++s) {
    uint64_t end = uint64_t(solids[s].firstTriangle) + solids[s].triangleCount;
    if (solids[s].firstTriangle < covered || end > nTriangles)
      return Status::error(
          Code::InvalidArgument,
          format("solid %zu (triangles %u..%llu) %s", s, solids[s].firstTriangle, (unsigned long long)end,
                 end > nTriangles ? format("runs past the last triangle (%llu)", (unsigned long long)nTriangles).c_str()
                                  : "overlaps the solid before it or is out of order"));
    covered = end;
  }
  out.clear();
  uint64_t at = 0;
  auto add = [&](uint64_t first, uint64_t count, uint32_t solid) {
    return out.push_back(SolidPart{uint32_t(first), uint32_t(count), solid});
  };
  for (size_t s = 0; s < nSolids; ++s) {
    const Solid& so = solids[s];
    if ((so.firstTriangle > at && !add(at, so.firstTriangle - at, kInvalid)) ||
        !add(so.firstTriangle, so.triangleCount, uint32_t(s))) {
      out.clear();
      return Status::error(Code::OutOfMemory, "could not allocate the solid list");
    }
    at = uint64_t(so.firstTriangle) + so.triangleCount;
  }
  if ((at < nTriangles || out.empty()) && !add(at, nTriangles - at, kInvalid)) {
    out.clear();
    return Status::error(Code::OutOfMemory, "could not allocate the solid list");
  }
  return Status{};
}

}  // namespace stltopo::detail
