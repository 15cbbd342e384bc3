// stltopo: read STL files into an indexed triangle mesh and libstl-style topology.
//
// One public header. Everything here is plain data plus a few functions; the
// core never prints, never touches files and never starts threads. Allocation
// failure is reported as Code::OutOfMemory, never thrown across the API.
//
// Layout (all indices are uint32, kInvalid = ~0u means "none"):
//   positions[3*v + k]     coordinate k of vertex v            (Mesh)
//   triangles[3*t + c]     vertex of corner c of triangle t     (Mesh)
//   next[e], vert[e], face[e]  half-edge arrays                 (Topology)
//   twin(e) = e ^ 1;  vnext(e) = next[e ^ 1]
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace stltopo {

inline constexpr uint32_t kInvalid = ~0u;
inline constexpr uint64_t kNoOffset = ~uint64_t(0);

// ---------------------------------------------------------------------------
// Status codes. The string names (codeName) are stable and shared with JS.
enum class Code : uint8_t {
  Ok = 0,
  // errors
  Empty,           // "empty": zero bytes
  NotStl,          // "not-stl": neither binary nor ASCII STL
  Truncated,       // "truncated": binary data shorter than its count promises
  UnexpectedEnd,   // "unexpected-end": ASCII file ends inside a facet
  AsciiSyntax,     // "ascii-syntax": malformed ASCII (bad keyword, number, vertex count)
  NonFinite,       // "non-finite": NaN or Inf coordinate
  TooLarge,        // "too-large": more than maxTriangles / maxBytes
  OutOfMemory,     // "out-of-memory": an allocation failed
  InvalidArgument, // "invalid-argument": API misuse (e.g. feed after finish)
  Aborted,         // "aborted": cancelled by the caller (JS AbortSignal)
  Invalid,         // "invalid": validate() found a broken invariant
  // warnings
  TrailingBytes,   // "trailing-bytes": < 84 extra bytes after the last binary triangle
  MissingEndsolid, // "missing-endsolid": ASCII file ends without endsolid
  NameTruncated,   // "name-truncated": a solid name longer than kMaxNameBytes
  // errors (continued)
  EditRefused,     // "edit-refused": an EditableMesh edit was refused; nothing changed
  // New codes go above this line; kCodeCount and the name table in status.cpp follow.
};
inline constexpr int kCodeCount = int(Code::EditRefused) + 1;

// The stable name of a code ("truncated"), "unknown" for a value outside the enum.
const char* codeName(Code c);
// The code whose name is `name`; false (and `out` unchanged) when no code has that name.
bool codeFromName(const char* name, Code& out);

// A status: a code, a human message and where it happened. Fields that do not
// apply are kNoOffset / 0 (line numbers start at 1) / kInvalid.
struct Status {
  Code code = Code::Ok;
  std::string message;
  uint64_t offset = kNoOffset;  // byte offset in the input
  uint64_t line = 0;            // 1-based ASCII line, 0 = not applicable
  uint32_t triangle = kInvalid; // triangle index, kInvalid = not applicable
  uint32_t element = kInvalid;  // validate(): the offending half-edge/vertex/face id
  bool ok() const { return code == Code::Ok; }

  // An error or warning whose message starts with the code's name: "truncated: <message>".
  static Status error(Code c, const std::string& message, uint64_t offset = kNoOffset, uint64_t line = 0,
                      uint32_t triangle = kInvalid);
};

namespace detail {
// Asks the OS to back a large array with huge pages (Linux, native builds; a no-op
// elsewhere): fewer page faults and TLB misses on the big, randomly accessed arrays.
void adviseHugePages(void* p, size_t bytes);
}  // namespace detail

// ---------------------------------------------------------------------------
// A minimal owning array of trivially copyable T (malloc-backed so that an
// allocation failure is a return value, not an exception or a wasm abort).
template <class T>
class Array {
 public:
  Array() = default;
  Array(const Array&) = delete;
  Array& operator=(const Array&) = delete;
  Array(Array&& o) noexcept : p_(o.p_), n_(o.n_), cap_(o.cap_) { o.p_ = nullptr; o.n_ = o.cap_ = 0; }
  Array& operator=(Array&& o) noexcept {
    if (this != &o) { std::free(p_); p_ = o.p_; n_ = o.n_; cap_ = o.cap_; o.p_ = nullptr; o.n_ = o.cap_ = 0; }
    return *this;
  }
  ~Array() { std::free(p_); }

  T* data() { return p_; }
  const T* data() const { return p_; }
  size_t size() const { return n_; }
  bool empty() const { return n_ == 0; }
  size_t capacity() const { return cap_; }
  T& operator[](size_t i) { return p_[i]; }
  const T& operator[](size_t i) const { return p_[i]; }
  T* begin() { return p_; }
  T* end() { return p_ + n_; }
  const T* begin() const { return p_; }
  const T* end() const { return p_ + n_; }

  // All fallible operations return false on allocation failure and leave the
  // array unchanged.
  [[nodiscard]] bool reserve(size_t n) {
    if (n <= cap_) return true;
    if (n > SIZE_MAX / sizeof(T)) return false;
    void* q = std::realloc(p_, n * sizeof(T));
    if (!q) return false;
    p_ = static_cast<T*>(q);
    cap_ = n;
    if (n * sizeof(T) >= (size_t(4) << 20)) detail::adviseHugePages(p_, n * sizeof(T));
    return true;
  }
  [[nodiscard]] bool resize(size_t n) {
    if (!reserve(n)) return false;
    n_ = n;
    return true;
  }
  [[nodiscard]] bool assign(size_t n, T value) {
    if (!resize(n)) return false;
    for (size_t i = 0; i < n; ++i) p_[i] = value;
    return true;
  }
  [[nodiscard]] bool push_back(const T& v) {
    if (n_ == cap_ && !reserve(cap_ < 8 ? 16 : cap_ * 2)) return false;
    p_[n_++] = v;
    return true;
  }
  void clear() { n_ = 0; }
  void release() { std::free(p_); p_ = nullptr; n_ = cap_ = 0; }
  void shrink(size_t n) { if (n < n_) n_ = n; }

 private:
  T* p_ = nullptr;
  size_t n_ = 0;
  size_t cap_ = 0;
};

// ---------------------------------------------------------------------------
// Reading

enum class Format : uint8_t { Unknown, Binary, Ascii };
enum class ColorConvention : uint8_t { None, VisCam, Magics };
const char* formatName(Format f);           // "binary", "ascii", "unknown"
const char* colorConventionName(ColorConvention c);  // "none", "viscam", "magics"

inline constexpr size_t kMaxNameBytes = 4096;      // longer solid names are cut (warning)
inline constexpr size_t kMaxNumberChars = 4096;    // longer ASCII numbers are an error

struct ReadOptions {
  uint32_t maxTriangles = 1u << 28;  // more gives Code::TooLarge
  uint64_t maxBytes = 0;             // 0 = unlimited; more gives Code::TooLarge
  uint64_t sizeHint = 0;             // total input size if known (lets the reader reserve
                                     // and fail early); 0 = unknown. Never trusted beyond
                                     // what arrives.
  bool keepNormals = false;          // store the facet normals in Mesh::normals
};

// A solid: one `solid ... endsolid` block or one binary part of a concatenation.
struct Solid {
  std::string name;          // ASCII: text after `solid`; binary: header up to first NUL; trimmed
  uint32_t firstTriangle = 0;
  uint32_t triangleCount = 0;
};

// The welded mesh. Vertex ids follow first appearance in corner order.
struct Mesh {
  Format format = Format::Unknown;
  Array<float> positions;       // 3*nVertices: x,y,z of vertex v at 3v..3v+2
  Array<uint32_t> triangles;    // 3*nTriangles: vertex ids of corner c of triangle t at 3t+c
  Array<uint16_t> attributes;   // nTriangles: binary attribute word (0 for ASCII)
  Array<float> normals;         // 3*nTriangles if ReadOptions::keepNormals, else empty
  Array<uint8_t> colors;        // 3*nTriangles RGB if colorConvention != None, else empty
  Array<uint8_t> colorValid;    // nTriangles: 1 when the triangle has a colour
  ColorConvention colorConvention = ColorConvention::None;
  std::vector<Solid> solids;
  std::vector<Status> warnings;  // same shape as errors; code is a warning code

  // Figures gathered while reading (over all triangles, degenerate ones too).
  uint32_t normalMismatches = 0;  // stored non-zero normal points against the winding
  double area = 0;                // sum of triangle areas
  double volume = 0;              // signed volume (divergence theorem)
  float bboxMin[3] = {0, 0, 0}, bboxMax[3] = {0, 0, 0};  // valid when nVertices() > 0

  uint32_t nVertices() const { return uint32_t(positions.size() / 3); }
  uint32_t nTriangles() const { return uint32_t(triangles.size() / 3); }
};

// Streaming reader. Feed bytes in chunks of any size (down to 1 byte), then call
// finish(). The result is identical for every chunking. After an error, feed()
// and finish() keep returning that error; reset() starts over.
class Reader {
 public:
  explicit Reader(const ReadOptions& options = {});
  ~Reader();
  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;

  Status feed(const uint8_t* data, size_t size);
  // Completes the read and moves the mesh into `out` on success.
  Status finish(Mesh& out);
  void reset();
  uint64_t bytesRead() const;

  struct Impl;
 private:
  Impl* impl_;
};

// Whole-buffer convenience: same as one feed() plus finish().
Status readStl(const uint8_t* data, size_t size, Mesh& out, const ReadOptions& options = {});

// ---------------------------------------------------------------------------
// Topology

struct TopologyOptions {
  // 0 = exact weld (default). > 0: vertices within this absolute distance are
  // merged for the topology only (see README: deterministic, grid-based).
  double tolerance = 0;
  // false: leave Topology::prev and Topology::face empty; every other array, every count
  // and every loop is the same. For callers that only need the report (the CLIs): 8 fewer
  // bytes per half-edge, about 24 per triangle. Navigation through prev or face (lPrev,
  // oNext, lFace, rFace, ...) and validate() need them.
  bool prevAndFace = true;
};

// Edge classes per half-edge pair (index k = e >> 1).
enum class EdgeKind : uint8_t {
  Interior = 0,     // paired: the edge is used by exactly two opposite sides
  Boundary = 1,     // edge used by exactly one triangle side
  Inconsistent = 2, // edge used by two sides running the same way (cut)
  NonManifold = 3,  // edge used by three or more sides (paired or cut)
};

struct Topology {
  uint32_t nTriangles = 0;      // = mesh.nTriangles(); boundary face h has id nTriangles + h
  uint32_t nVertices = 0;

  // Half-edges: length nHalfedges() = 2 * number of pairs.
  Array<uint32_t> next;   // next half-edge around the same face (triangle or boundary loop)
  Array<uint32_t> prev;   // inverse of next (O(1) lPrev on long boundary loops)
  Array<uint32_t> vert;   // origin vertex
  Array<uint32_t> face;   // triangle id, or nTriangles + loop id
  Array<uint8_t> pairKind;  // per pair k: EdgeKind of the side(s) in the pair

  // Lookups.
  Array<uint32_t> triangleHalfedge;  // per triangle: half-edge of side corner0->corner1, kInvalid if degenerate
  Array<uint32_t> vertexHalfedge;    // per vertex: an outgoing half-edge (kInvalid if unused); on a
                                     // boundary it is the lowest-id boundary half-edge leaving it
  Array<uint32_t> vertexWeld;        // per vertex: representative vertex used by the topology
                                     // (identity for exact weld)

  // Boundary loops ("hole faces"): loop h is face nTriangles + h.
  Array<uint32_t> loopHalfedge;      // per loop: its lowest-id half-edge
  Array<uint32_t> loopOffsets;       // nLoops + 1: loop h's half-edges are loopHalfedges[off[h]..off[h+1])
  Array<uint32_t> loopHalfedges;     // in next order, starting at loopHalfedge[h]
  Array<uint8_t> loopIsSeam;         // 1 when the loop contains a cut (inconsistent/non-manifold) side
  Array<double> loopPerimeter;       // per loop: sum of edge lengths

  // Per-element problem flags.
  Array<uint8_t> triangleDegenerate;   // per triangle: 1 if two corners weld together
  Array<uint8_t> vertexNonManifold;    // per vertex: 1 if its outgoing half-edges form > 1 vnext cycle

  // Undirected-edge counts (an undirected edge may hold several pairs when cut).
  uint32_t nEdges = 0, nBoundaryEdges = 0, nNonManifoldEdges = 0, nInconsistentEdges = 0;
  uint32_t nNonManifoldVertices = 0, nDegenerate = 0, nShells = 0, nUsedVertices = 0;
  uint32_t nHoles = 0, nSeams = 0;

  uint32_t nHalfedges() const { return uint32_t(next.size()); }
  uint32_t nLoops() const { return uint32_t(loopHalfedge.size()); }
  // V - E + F over the non-degenerate triangles and the vertices they use.
  int64_t eulerCharacteristic() const {
    return int64_t(nUsedVertices) - int64_t(nEdges) + int64_t(nTriangles - nDegenerate);
  }
  // At least one non-degenerate triangle and no boundary, non-manifold or inconsistent edge.
  bool watertight() const {
    return nTriangles > nDegenerate && nBoundaryEdges == 0 && nNonManifoldEdges == 0 && nInconsistentEdges == 0;
  }
  bool manifold() const { return nNonManifoldEdges == 0 && nNonManifoldVertices == 0; }
  uint32_t nFaces() const { return nTriangles + nLoops(); }
  bool isLoopFace(uint32_t f) const { return f >= nTriangles; }
};

Status buildTopology(const Mesh& mesh, Topology& out, const TopologyOptions& options = {});

// Checks every invariant; returns the first violation (Code::Invalid, element set).
Status validate(const Mesh& mesh, const Topology& topo);

// Navigation. face[e] is the left face of e.
inline uint32_t twin(uint32_t e) { return e ^ 1u; }
inline uint32_t sym(uint32_t e) { return e ^ 1u; }
inline uint32_t org(const Topology& t, uint32_t e) { return t.vert[e]; }
inline uint32_t dst(const Topology& t, uint32_t e) { return t.vert[e ^ 1u]; }
inline uint32_t lFace(const Topology& t, uint32_t e) { return t.face[e]; }
inline uint32_t rFace(const Topology& t, uint32_t e) { return t.face[e ^ 1u]; }
inline uint32_t lNext(const Topology& t, uint32_t e) { return t.next[e]; }
inline uint32_t lPrev(const Topology& t, uint32_t e) { return t.prev[e]; }
inline uint32_t vnext(const Topology& t, uint32_t e) { return t.next[e ^ 1u]; }
inline uint32_t oPrev(const Topology& t, uint32_t e) { return t.next[e ^ 1u]; }   // = vnext
inline uint32_t oNext(const Topology& t, uint32_t e) { return t.prev[e] ^ 1u; }   // sym(lPrev e)
inline uint32_t rPrev(const Topology& t, uint32_t e) { return oNext(t, e ^ 1u); }  // oNext(sym e)
inline uint32_t rNext(const Topology& t, uint32_t e) { return oPrev(t, e) ^ 1u; }  // sym(oPrev e)
inline uint32_t dNext(const Topology& t, uint32_t e) { return rPrev(t, e) ^ 1u; }  // sym(rPrev e)
inline uint32_t dPrev(const Topology& t, uint32_t e) { return t.next[e] ^ 1u; }    // sym(lNext e)

// Visit the half-edges of face f (triangle or loop) in next order.
template <class F>
void forEachFaceHalfedge(const Topology& t, uint32_t e0, F&& f) {
  uint32_t e = e0;
  do { f(e); e = t.next[e]; } while (e != e0);
}
// Visit the outgoing half-edges of the vnext cycle that contains e0.
template <class F>
void forEachOutgoing(const Topology& t, uint32_t e0, F&& f) {
  uint32_t e = e0;
  do { f(e); e = vnext(t, e); } while (e != e0);
}

// ---------------------------------------------------------------------------
// The report: what `stltopo info --json` prints.

// JSON object (one line, no trailing newline) for a successfully read file.
std::string infoJson(const std::string& file, const Mesh& mesh, const Topology* topo);
// The CLI's human-readable report (several lines, each ending in a newline).
std::string infoText(const std::string& file, const Mesh& mesh, const Topology* topo);
// JSON object for a failed file: {"file":..,"error":{code,message,location}}.
std::string errorJson(const std::string& file, const Status& error);
// Escapes a string as a JSON string literal (with quotes); invalid UTF-8 becomes U+FFFD.
std::string jsonString(const std::string& s);

}  // namespace stltopo
