// PLY input/output of triangle meshes and point clouds (common/trimesh/trimesh.h).
//
// Writer: binary little-endian. Elements and properties, in this order:
//   element vertex N: float x y z (double with PlyWriteOptions::double_coords),
//                     [float nx ny nz], [uchar red green blue], [float <vprop>]...
//   element face F:   list uchar int vertex_indices, [float <fprop>]...
//   (no face element for a point cloud)
// Reader: ascii, binary_little_endian and binary_big_endian; any scalar types; vertex
// properties x y z (required), nx ny nz, red green blue (uchar, or float in [0,1]),
// any other scalar vertex property becomes a float vprop; face list "vertex_indices"
// or "vertex_index" (polygons are fan-triangulated, face props repeated), other scalar
// face properties become float fprops; other elements are skipped. Every problem is an
// Error naming the file.
#pragma once
#include <filesystem>
#include <string>

#include "common/trimesh/trimesh.h"

namespace tetmvs {

struct PlyWriteOptions {
  bool double_coords = false;  // x y z as double instead of float
  std::string comment;         // one "comment" header line when non-empty
};

TriMesh read_ply(const std::filesystem::path& file);
// Reads only the header and checks that the file is long enough for the element counts it
// declares; an Error names the file and the problem.
void check_ply_header(const std::filesystem::path& file);
// Atomic write (temporary file renamed into place).
void write_ply(const std::filesystem::path& file, const TriMesh& mesh, const PlyWriteOptions& opt = {});

}  // namespace tetmvs
