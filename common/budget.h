// Memory budget: a stage estimates the memory of its big allocations BEFORE making them
// and refuses with a one-line Error (estimate, budget, which parameter to change) when the
// estimate exceeds the budget, instead of being killed by the system half way.
//
// The budget is the parameter resource.memory_gb (GiB; make MEMORY_GB=...); the
// environment variable TETMVS_MEMORY_GB, when set, takes its place (a machine-wide
// setting, e.g. for CI).
//
//   check_memory_budget(ctx.params, bytes, "refine: mesh_2.h5 refined to ~1.2e8 cells",
//                       "refine fewer levels (LEVELS) or a coarser mesh.cells");
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "common/params.h"

namespace tetmvs {

// The budget in bytes, and where it comes from ("resource.memory_gb" or "TETMVS_MEMORY_GB").
struct MemoryBudget {
  double bytes = 0;
  std::string source;
};
MemoryBudget memory_budget(const Params& p);

// Throws Error "<what>: needs about X GiB, over the memory budget of Y GiB (<source>): <hint>;
// or raise the budget (...)" when estimated_bytes > budget (or NaN); else logs the estimate (info).
void check_memory_budget(const Params& p, double estimated_bytes, std::string_view what,
                         std::string_view hint);

// The largest estimate check_memory_budget was given in this process (0: none), which the
// stage's run log records next to the measured peak (a test compares the two).
double largest_memory_estimate();

// The budget of the running stage, set by StageCli from its parameters (none outside a
// stage: unit tests). The readers check the sizes a file DECLARES (an HDF5 dataset's shape,
// an image header's pixels, a PLY element count) against it before allocating, so that a
// hostile or damaged header is refused naming the file instead of exhausting memory.
void set_stage_memory_budget(const MemoryBudget& b);
// Throws Error "<what> declares about X GiB, over the memory budget of Y GiB (<source>)"
// when bytes exceeds the stage's budget (or is NaN); nothing without a stage budget.
void check_declared_bytes(double bytes, std::string_view what);

// In-memory size of a tetrahedral mesh (TetMesh arrays) with these counts.
double mesh_bytes(double cells, double faces, double vertices, double nodes);
// The same for a mesh of `cells` cells with the usual BCC proportions (faces ~ 2 per
// cell, vertices ~ 1/5, nodes ~ 1.2): about 110 bytes a cell.
double mesh_bytes(double cells);

// Counts of a mesh file read from its dataset shapes (no data read).
struct MeshCounts {
  std::int64_t cells = 0, faces = 0, vertices = 0, nodes = 0;
  // Peak bytes of tet::read_mesh (arrays, HDF5 buffers, face rebuild).
  double read_bytes() const;
};
MeshCounts mesh_counts(const std::filesystem::path& mesh_file);

// "1.5 GiB", "230 MiB"
std::string format_bytes(double bytes);

}  // namespace tetmvs
