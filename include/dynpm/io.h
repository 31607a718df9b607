// dynpm/io.h — reading and writing meshes and animations.
//
// Readers take untrusted bytes and never crash on them: every failure is a Result carrying
// "file:line: cause" (text formats) or "file: byte N: cause" (binary formats). Writers write to a
// temporary name beside the target and rename it, so a failure never leaves a half-written file.
//
//   OBJ   read and write; triangles and quads kept as they are; `v`, `f` with the v/vt/vn forms,
//         negative (relative) indices, comments, CRLF; `g` groups become part ids.
//   PLY   read ascii and binary little/big-endian, write ascii and binary little-endian; the
//         face properties part_id and element_id and the vertex property node_id round-trip.
//   VTK   legacy polydata, written (binary): points, polygons, part ids, point scalar fields.
//
// An animation is a sequence of per-step files over one face list (frame_000.obj,
// frame_001.obj, …). open_animation() reads the first file's faces and streams the positions
// of each step from its file when asked, checking that the file repeats the same faces.
#pragma once

#include <functional>
#include <span>
#include <string>
#include <vector>

#include "dynpm/core.h"

namespace dynpm {

enum class FileFormat {
  kUnknown,
  kObj,
  kPly,
  kVtk,     // legacy VTK: polydata (mesh per file) or unstructured grid
  kVtu,     // VTK XML unstructured grid
  kPvd,     // ParaView collection of per-step VTU/VTK files
  kFrd,     // CalculiX result (all steps in one file)
  kExodus,  // Exodus II (netCDF), all steps in one file
  kD3plot,  // LS-DYNA d3plot family (d3plot, d3plot01, …)
};

const char* to_string(FileFormat format);
// By extension (case-insensitive): .obj, .ply, .vtk.
FileFormat format_from_extension(const std::string& path);
// By content where the format has a signature ("ply", "# vtk DataFile"), else by extension.
Result<FileFormat> detect_format(const std::string& path);

struct ReadOptions {
  // Faces with more than 4 corners are an error unless this is set; then they are split into
  // a fan of triangles around their first corner, with a warning.
  bool split_polygons = false;
  // Receives notes about the input (ignored OBJ statements, split polygons, …). src/ never
  // prints: the caller decides where these go. May be empty.
  std::function<void(const std::string&)> warn;
};

// One mesh file as an animation of one step (time 0).
Result<Animation> read_mesh(const std::string& path, const ReadOptions& options = {});

// One file per time step, in the given order, all over the same faces. Step t's time is t
// unless the files say otherwise. The first file is read at once; the others when a step is
// asked for (FrameSource::read_step), which fails with a clear message if that file's faces
// or vertex count differ from the first file's.
Result<AnimationStream> open_animation(std::span<const std::string> paths,
                                       const ReadOptions& options = {});
// open_animation() followed by reading every step.
Result<Animation> read_animation(std::span<const std::string> paths,
                                 const ReadOptions& options = {});

// Any input the command line accepts: one solver result holding every step (FRD, Exodus,
// d3plot family, PVD, VTU, legacy VTK unstructured grid), or one mesh file per step (OBJ, PLY,
// VTK polydata), told apart by content. Steps stay on disk until asked for.
Result<AnimationStream> open_input(std::span<const std::string> paths,
                                   const ReadOptions& options = {});

// Command-line inputs to files: an argument with * ? or [ is a glob (error if it matches
// nothing), its matches sorted naturally (frame_2 before frame_10); other arguments are kept
// as given. A directory is an error.
Result<std::vector<std::string>> expand_inputs(std::span<const std::string> arguments);
// "Natural" order: digit runs compare by value, so frame_9.obj < frame_10.obj.
bool natural_less(const std::string& a, const std::string& b);

struct WriteOptions {
  bool binary = true;   // PLY and VTK; OBJ is always text
  std::string comment;  // a line of provenance written into the file's header
};

// One time step of a topology with its positions (3 · vertex_count floats). Per-vertex scalar
// fields (name, values) are written where the format can hold them (VTK).
struct NamedValues {
  std::string name;
  std::span<const float> values;
};
Status write_mesh(const std::string& path, const Topology& topology,
                  std::span<const float> positions, const WriteOptions& options = {},
                  std::span<const NamedValues> point_fields = {});

// The file name of step t from a pattern holding one "{:03d}"-style field ("{}", "{:d}",
// "{:0Nd}"); an error if the pattern has none or a malformed one.
Result<std::string> step_path(const std::string& pattern, size_t step);
bool has_step_field(const std::string& pattern);

}  // namespace dynpm
