// Mesh files (schema "tetmvs.mesh", schemas/mesh.md) and ParaView export.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/h5fields.h"
#include "common/tetmesh/tetmesh.h"

namespace tetmvs::tet {

inline constexpr const char* kMeshSchema = "tetmvs.mesh";
inline constexpr int kMeshVersion = 1;

// The datasets and attributes of a mesh file: the lattice on the root group, vertices,
// cells, faces and the refinement tree (/tree/*).
const h5::Fields<TetMesh>& mesh_fields();
// Writes mesh_<i>.h5 (atomically) from mesh_fields(). `params`/`inputs` go into the standard header.
void write_mesh(const std::filesystem::path& file, const TetMesh& m, const std::string& stage,
                const nlohmann::json& params, const std::vector<std::filesystem::path>& inputs);
// Reads and validates a mesh file (schema, shapes, tree links; faces rebuilt and compared).
TetMesh read_mesh(const std::filesystem::path& file);

// A per-cell field for the .vtu export / slices.
struct CellField {
  std::string name;
  std::vector<double> values;  // one per cell
};

// ParaView unstructured grid (binary appended data): the leaf cells with cell data
// level, colour, new_red, node and the given fields.
void write_vtu(const std::filesystem::path& file, const TetMesh& m,
               const std::vector<CellField>& fields = {});

// Reads a per-cell uint8 flag dataset (e.g. /cells/active of photoconsist's file) of
// length num_cells.
std::vector<std::uint8_t> read_cell_flags(const std::filesystem::path& file, const std::string& dataset,
                                          std::int64_t num_cells);

}  // namespace tetmvs::tet
