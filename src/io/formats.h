// The readers and writers behind dynpm/io.h, one file per format. Each parser turns the bytes of
// one file into a ParsedMesh (one topology, one step of positions) or an error naming the file
// and place; each writer turns a mesh into bytes that write_file_atomically() puts in place.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "dynpm/io.h"
#include "dynpm/text.h"

namespace dynpm::io {

// A scalar of one file: VTK point data (vertex_count values) or cell data (one per face).
struct MeshField {
  std::string name;
  std::vector<float> values;
  FieldLocation location = FieldLocation::kNode;
};

// A 64-bit hash of bytes, 8 at a time. Not cryptographic: it only tells a later file of a
// sequence that repeats the first file's face bytes from one that may not (which is then parsed
// and compared face by face).
class ByteHash {
 public:
  void add(std::string_view bytes) {
    size_t i = 0;
    for (; i + 8 <= bytes.size(); i += 8) {
      uint64_t word;
      std::memcpy(&word, bytes.data() + i, 8);
      mix(word);
    }
    uint64_t tail = 0;
    if (i < bytes.size()) std::memcpy(&tail, bytes.data() + i, bytes.size() - i);
    mix(tail ^ (uint64_t{bytes.size() - i} << 56));
    length_ += bytes.size();
  }
  uint64_t value() const { return (state_ ^ length_) * 0x9e3779b97f4a7c15ull; }

 private:
  void mix(uint64_t word) {
    state_ += word * 0xc2b2ae3d27d4eb4full;
    state_ = ((state_ << 31) | (state_ >> 33)) * 0x9e3779b97f4a7c15ull;
  }
  uint64_t state_ = 0x27d4eb2f165667c5ull;
  uint64_t length_ = 0;
};

// How a parser treats the faces. kHashOnly is for the later files of a sequence: the bytes that
// give the faces (OBJ: the f and g lines; PLY: the face element's records) are hashed into
// ParsedMesh::faces_hash but not parsed, and topology.faces stays empty.
enum class FaceParsing { kParse, kHashOnly };

struct ParsedMesh {
  Topology topology;
  std::vector<float> positions;  // 3 · vertex_count
  std::vector<MeshField> fields;
  std::vector<uint32_t>
      face_places;  // per face, the line (text) or byte offset (binary) it came from
  bool places_are_lines = true;
  std::optional<double> time;  // from a "time <t>" note in the header comments
  // The hash of the bytes that give the faces, by OBJ and PLY (either FaceParsing): two files
  // with the same hash repeat the same face bytes.
  std::optional<uint64_t> faces_hash;
};

Result<ParsedMesh> parse_obj(std::string_view text, const std::string& path,
                             const ReadOptions& options, FaceParsing faces = FaceParsing::kParse);
Result<ParsedMesh> parse_ply(std::string_view bytes, const std::string& path,
                             const ReadOptions& options, FaceParsing faces = FaceParsing::kParse);
// Legacy VTK (ascii or big-endian binary, file versions 2 to 5.1): POLYDATA or UNSTRUCTURED_GRID.
Result<ParsedMesh> parse_vtk(std::string_view bytes, const std::string& path,
                             const ReadOptions& options);
// VTK XML UnstructuredGrid (.vtu): ascii, base64 and appended DataArrays, zlib-compressed or not.
Result<ParsedMesh> parse_vtu(std::string_view bytes, const std::string& path,
                             const ReadOptions& options);

// The data sets of a ParaView collection (.pvd): files resolved against the .pvd's folder, in
// ascending time (the file order where times tie).
struct PvdStep {
  std::string path;
  double time = 0;
};
Result<std::vector<PvdStep>> parse_pvd(std::string_view bytes, const std::string& path);

// open_animation() with the step times given (one per path) instead of read from the files.
Result<AnimationStream> open_file_sequence(std::span<const std::string> paths,
                                           std::span<const double> times,
                                           const ReadOptions& options);

std::string write_obj(const Topology& topology, std::span<const float> positions,
                      const WriteOptions& options);
// Fields per vertex (point data) and per face (cell data), names made safe for the format
// (spaces become '_', as array names and PLY properties cannot hold them).
std::string write_ply(const Topology& topology, std::span<const float> positions,
                      const WriteOptions& options, std::span<const NamedValues> point_fields,
                      std::span<const NamedValues> cell_fields);
std::string write_vtk(const Topology& topology, std::span<const float> positions,
                      const WriteOptions& options, std::span<const NamedValues> point_fields,
                      std::span<const NamedValues> cell_fields);
std::string write_vtu(const Topology& topology, std::span<const float> positions,
                      const WriteOptions& options, std::span<const NamedValues> point_fields,
                      std::span<const NamedValues> cell_fields);
// A name a VTK array or a PLY property can hold: spaces become '_', "" becomes "field".
std::string safe_field_name(std::string name);

// Solver results that hold every time step in one file (or one family of files). Each opens
// the file, reads the mesh at once and streams the steps through the returned FrameSource.
Result<AnimationStream> open_frd(const std::string& path, const ReadOptions& options);
Result<AnimationStream> open_exodus(const std::string& path, const ReadOptions& options);
Result<AnimationStream> open_d3plot(const std::string& path, const ReadOptions& options);
// .pvd collections, .vtu files and legacy .vtk unstructured grids.
Result<AnimationStream> open_vtk_series(const std::string& path, const ReadOptions& options);

// "time <number>" in a header comment ("# cb5.frd frame 3: time 0.12 (frd block 3)"): the
// number (a whole token, text.h's parse_real; a ',', ';' or ')' after it is punctuation), nullopt
// without such a note, an error without a place (the caller adds it) when it is not finite.
Result<std::optional<double>> time_from_comment(std::string_view comment);

// The face of an element's corners (at most 4) with repeats dropped, in order: LS-DYNA and
// Exodus write a triangle as a quad whose last node repeats. nullopt when fewer than 3 distinct
// corners are left (a degenerate element, which the readers count and skip).
inline std::optional<Face> distinct_corner_face(std::span<const uint32_t> corners) {
  Face face;
  int distinct = 0;
  for (uint32_t c : corners)
    if (std::find(face.v.begin(), face.v.begin() + distinct, c) == face.v.begin() + distinct)
      face.v[size_t(distinct++)] = c;
  if (distinct < 3) return std::nullopt;
  return face;
}

// Adds a face of n ≥ 3 corners: as is when n ≤ 4; as a fan of triangles around corner 0 when
// options.split_polygons is set; otherwise an error naming the place.
Status add_polygon(std::span<const uint32_t> corners, int32_t part, int64_t element_id,
                   uint32_t place, const std::string& where, const ReadOptions& options,
                   ParsedMesh& mesh, size_t& split_count);

}  // namespace dynpm::io
