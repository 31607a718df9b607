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
//   VTK   legacy, written as polydata (binary): points, polygons, part ids, point scalar fields.
//         Read: file versions 2.0 to 5.1 (counted cell lists and OFFSETS/CONNECTIVITY), ascii
//         or binary (big-endian, as the format says), POLYDATA (POLYGONS, TRIANGLE_STRIPS) and
//         UNSTRUCTURED_GRID. One step per file; a list of files is a sequence.
//   VTU   VTK XML UnstructuredGrid, read: ascii, inline base64 and appended (raw or base64)
//         DataArrays, UInt32/UInt64 headers, either byte order, zlib compression (when built
//         with zlib; otherwise a clear error); one Piece. One step per file.
//   PVD   ParaView collection: its DataSets (one part per time step; files relative to the
//         .pvd) read as a sequence of .vtu/.vtk steps at the collection's timesteps.
//         VTK cells (all three): triangles, quads, pixels, polygons (> 4 corners need
//         split_polygons), triangle strips; quadratic and Lagrange triangles and quads keep
//         their corners (one warning); solids, vertices and lines are skipped with a warning
//         that counts them (no outer faces are made). One-component CELL_DATA named part,
//         part_id, PartId, pid, GeometryIds or gmsh:physical gives part ids, element_id the
//         element numbers (else cell number + 1), every other one-component cell array (but
//         gmsh:geometrical) is an element field (the faces of a split polygon repeat their
//         cell's value; skipped cells drop theirs); POINT_DATA node_id gives node numbers, every
//         other one-component point array is a node field; multi-component arrays are ignored
//         (one warning). No units (VTK names none). Times: "time <t>" in a legacy title,
//         TimeValue/TIME field data.
//   FRD   CalculiX result, read: node (2C), element (3C) and nodal result (100C) blocks, ASCII
//         short/long or binary (float/double, native byte order; what *NODE OUTPUT and
//         *ELEMENT OUTPUT write). Shells S3, S4/S4R, S6, S8/S8R are faces (quadratic ones by
//         their corners, one warning); solids and beams are skipped with one warning that
//         counts them (ccx writes shells as 20-node bricks unless *NODE FILE, OUTPUT=2D: a file
//         with no shell is an error saying so). Vertices are the nodes the shells use, in
//         ascending node number; faces in ascending element number; part id = the element's
//         material number (its group where that is set). Step 0 is the undeformed mesh at time
//         0, then one step per DISP block at its 100C time (as frame_000, frame_001, … of the
//         OBJ sequences made from .frd files). Fields: STRESS → "S_MISES" (von Mises), PE →
//         "PEEQ", any other one-component block by its name; zeros at step 0 and where a step
//         has no such block; blocks pair with a DISP block by step number and time; all
//         node fields, no units (FRD names none). Opening
//         scans the file once and keeps only where each block starts; a step is parsed when
//         read. A gzip-compressed file is refused ("gunzip it first").
//   d3plot  LS-DYNA binary database, read: the family d3plot, d3plot01, … (found beside the
//         first file, whatever its name: qd_d3plot, run.d3plot), 4- or 8-byte words in either
//         byte order, told apart by which reading gives a plausible control block. Shells (4
//         nodes + part; a repeated 4th node is a triangle) are faces; solids and thick shells
//         give their outer faces; beams are ignored with a warning. Ids come from the NARBS
//         section (node, element and part user numbers). Opening indexes where every state
//         starts (a state may run on into the next file; LS-DYNA's zero padding is skipped);
//         read_step() reads only that state's coordinates (IU; the geometry when IU = 0).
//         Fields: per node "temperature" (IT), "|V|" (IV); per face (element fields) "von
//         Mises" (from the stress tensor), "plastic strain" (effective) at the integration point
//         of ReadOptions::integration_point (MAXINT = 3 writes mid, bottom, top; others bottom to
//         top; max: the largest over the points), and "thickness" (IOSHL(4)); solid and thick
//         shell faces get their element's value where its words are understood (one point:
//         NV3D = 7 + NEIPH), else 0 with a warning. A shell layout whose words do not add up to
//         NV2D is refused. No units (d3plot has none). SPH, airbags, CFD, rigid-road and
//         rigid-body sections and higher-order solids are refused with a clear error.
//   Exodus II  read through netCDF (classic, 64-bit offset, netCDF-4/HDF5): coordx/y/z or
//         coord; connect<b> by elem_type: SHELL*, QUAD*, TRI* are faces; HEX, TETRA, WEDGE,
//         PYRAMID (and their higher-order forms, by corners) give the outer faces of the solid
//         blocks — faces used by exactly one element, outward; BEAM, BAR and others are ignored
//         with a warning. Part ids from eb_prop1, ids from node_num_map / elem_num_map, times
//         from time_whole. Nodal DISPL_X/Y/Z (or DISP_X…) displace the coordinates; the other
//         nodal variables are node fields; element variables (name_elem_var,
//         vals_elem_var<v>eb<b>, elem_var_tab) are element fields on the faces made from each
//         element (a solid's value on each of its outer faces), 0 with one warning on the faces
//         of blocks the truth table leaves out; no units. Classic files are checked against
//         the sizes their header declares (netCDF would read a cut file's missing bytes as
//         zeros).
//   Both: nodes no face uses are dropped (vertex i is the i-th used node, node_ids keeps the
//   original numbers); a file with no time step gives its mesh as one step at time 0.
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
// The formats write_mesh() writes: OBJ, PLY, VTK, VTU.
bool can_write(FileFormat format);
// By extension (case-insensitive): .obj, .ply, .vtk.
FileFormat format_from_extension(const std::string& path);
// By content where the format has a signature ("ply", "# vtk DataFile"), else by extension.
Result<FileFormat> detect_format(const std::string& path);

// Which through-thickness integration point of a shell an element field is read at (d3plot):
// the mid-surface, the top (outermost) or bottom (innermost) one, or the largest value over all.
enum class IntegrationPoint { kMid, kTop, kBottom, kMax };
const char* to_string(IntegrationPoint point);  // "mid", "top", "bottom", "max"

struct ReadOptions {
  // Faces with more than 4 corners are an error unless this is set; then they are split into
  // a fan of triangles around their first corner, with a warning.
  bool split_polygons = false;
  // Where shell element fields (stress, plastic strain) are taken through the thickness.
  IntegrationPoint integration_point = IntegrationPoint::kMid;
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
// nothing), its matches sorted naturally (frame_2 before frame_10), unless a file of that very
// name exists ("run[1].obj" opens as itself); other arguments are kept as given. A directory is
// an error.
Result<std::vector<std::string>> expand_inputs(std::span<const std::string> arguments);
// "Natural" order: digit runs compare by value, so frame_9.obj < frame_10.obj.
bool natural_less(const std::string& a, const std::string& b);

struct WriteOptions {
  bool binary = true;   // PLY and VTK; OBJ is always text
  std::string comment;  // a line of provenance written into the file's header
};

// One time step of a topology with its positions (3 · vertex_count floats). Scalar fields
// (name, values) per vertex (point data) and per face (cell data) are written where the format
// can hold them (VTK, VTU: point and cell data; PLY: vertex and face properties).
struct NamedValues {
  std::string name;
  std::span<const float> values;
};
Status write_mesh(const std::string& path, const Topology& topology,
                  std::span<const float> positions, const WriteOptions& options = {},
                  std::span<const NamedValues> point_fields = {},
                  std::span<const NamedValues> cell_fields = {});

// The file name of step t from a pattern holding one "{:03d}"-style field ("{}", "{:d}",
// "{:0Nd}"); an error if the pattern has none or a malformed one.
Result<std::string> step_path(const std::string& pattern, size_t step);
bool has_step_field(const std::string& pattern);

}  // namespace dynpm
