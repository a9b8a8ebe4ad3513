// Hard labels checked against the ground truth (synthetic scenes): how many cells label
// (or silhouette-fix) tied to the source lie outside the true object, and how many tied to
// the sink lie inside it, per label and per reason. The "labels are never wrong"
// counted by `evaluate --labels` (schemas/evaluate.md, "labels object").
//
// A cell is wrong when its centroid is on the wrong side of the truth; "wholly" wrong when
// its four corners are too (a cell that straddles the true surface is only partly wrong:
// with cells of 4 px, the truth cuts through the finest cells along the whole surface).
// Depth: distance from the wrong centroid to the true surface, in finest cell edges.
#pragma once
#include <cstdint>
#include <map>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/reason.h"
#include "common/tetmesh/tetmesh.h"
#include "common/trimesh/bvh.h"

namespace tetmvs::label {

struct LabelErrors {
  std::int64_t cells = 0;
  std::int64_t wrong = 0;        // centroid on the wrong side of the truth
  std::int64_t wrong_whole = 0;  // ... and all four corners too
  std::int64_t deeper_than[3] = {0, 0, 0};  // wrong, centroid more than 1, 2, 4 cells from the surface
  double deepest = 0;            // largest depth of a wrong centroid (finest cells)
};
inline constexpr double kTruthDepths[3] = {1, 2, 4};

struct LabelTruth {
  double cell = 0;  // finest cell edge (world units), the unit of the depths
  LabelErrors interior, exterior;
  std::map<int, LabelErrors> by_reason;  // reason code -> its cells (only reasons present)
  std::vector<std::int32_t> wrong_cells;        // every wrong cell, ascending
  std::vector<std::int32_t> wrong_whole_cells;  // those wholly wrong, ascending
};
inline constexpr std::size_t kMaxWrongCellsListed = 100000;  // in the JSON

// label: per cell 1 / -1 / 0; reason: per cell (empty: no breakdown). gt: BVH of the closed
// ground-truth mesh. Deterministic; OpenMP over cells.
LabelTruth check_labels(const tet::TetMesh& m, const std::vector<std::int8_t>& label,
                        const std::vector<std::uint8_t>& reason, const MeshBVH& gt);

nlohmann::json to_json(const LabelTruth& t);

}  // namespace tetmvs::label
