// stltopo/write.h: writing a Mesh as binary or ASCII STL, streamed in bounded chunks.
//
// What is written (see README, "Writing STL"):
//   - one binary part, or one `solid ... endsolid` block, per Mesh::solids entry, in
//     triangle order (triangles that no solid covers become unnamed solids of their own;
//     a mesh without solids is one solid), so that reading the output gives back the same
//     solids, with positions bit for bit, the same triangles (vertex ids included), the
//     same attribute words and the same colours;
//   - normals: Mesh::normals when the mesh kept them, else computed from the winding
//     (float32, unit length, zero for a degenerate triangle);
//   - names: cut before the first byte the format cannot carry (binary: NUL; ASCII: any
//     control byte except tab, vertical tab and form feed), at 80 bytes in a binary header
//     (69 when it also holds COLOR=) or kMaxNameBytes in ASCII (at a UTF-8 character
//     boundary), and trimmed of blanks as the reader trims them;
//   - ASCII numbers: the shortest decimal that reads back as the same float32 (the JSON
//     report's digits), "nan"/"inf" for stored non-finite normals.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "stltopo/mesh.h"
#include "stltopo/status.h"

namespace stltopo {

// Colours of binary output. AsMesh keeps the mesh's convention and attribute words
// unchanged. Another convention re-encodes the colours (5 bits per channel, rounded), and
// the attribute words then hold only the colour. None writes zero attribute words when the
// mesh has colours. A mesh without colours is written with its attribute words whatever
// is asked (there are no colours to write). ASCII output has no colours.
enum class WriteColors : uint8_t { AsMesh, None, VisCam, Magics };

inline constexpr size_t kMinChunkBytes = 16384;  // room for the longest ASCII name line

struct WriteOptions {
  Format format = Format::Binary;  // Binary or Ascii (Unknown writes binary)
  WriteColors colors = WriteColors::AsMesh;
  // When set, every solid is written with this name (cut and trimmed as above).
  std::optional<std::string> name;
  // false: always compute the normals from the winding, even when the mesh kept them.
  bool storedNormals = true;
  // Magics output: the default colour (COLOR= in a part's header) of the parts where no
  // triangle says what it is (none uses it, or the mesh had VisCAM colours).
  uint8_t defaultColor[3] = {255, 255, 255};
  // Largest chunk handed out; values below kMinChunkBytes are raised to it.
  size_t chunkBytes = size_t(1) << 20;
};

// A pull writer: each next() hands out the following chunk of the file. The mesh must
// stay alive and unchanged until the last chunk. The whole mesh is checked on the first
// call, before any byte is handed out; the codes:
//   invalid-argument  array lengths that do not match (positions or triangles not a
//                     multiple of 3, attributes/normals/colours of another length than
//                     the triangles), solids that overlap, are out of order or run past
//                     the end;
//   invalid-index     a triangle corner >= nVertices (Status::triangle says which);
//   too-large         more than 2^32 - 1 triangles (a binary count is 32 bits);
//   out-of-memory     the chunk buffer could not be allocated.
// After an error next() keeps returning it.
class StlWriter {
 public:
  explicit StlWriter(const Mesh& mesh, const WriteOptions& options = {});
  ~StlWriter();
  StlWriter(const StlWriter&) = delete;
  StlWriter& operator=(const StlWriter&) = delete;

  // The next chunk: data/size stay valid until the next call or the destructor. size is 0
  // (and the status ok) once the file is complete.
  Status next(const uint8_t*& data, size_t& size);
  uint64_t bytesWritten() const;

  struct Impl;

 private:
  Impl* impl_;
};

// Receives the file in order, one chunk per call; returns false to stop the write.
using WriteSink = bool (*)(void* user, const uint8_t* data, size_t size);

// Writes the whole file through sink: the codes of StlWriter::next(), and write-failed
// when the sink returns false (nothing more is handed to it then).
Status writeStl(const Mesh& mesh, WriteSink sink, void* user, const WriteOptions& options = {});

}  // namespace stltopo
