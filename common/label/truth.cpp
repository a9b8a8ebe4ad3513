#include "common/label/truth.h"

#include <algorithm>

#include "common/error.h"

namespace tetmvs::label {

namespace {
void add(LabelErrors& to, const LabelErrors& e) {
  to.cells += e.cells;
  to.wrong += e.wrong;
  to.wrong_whole += e.wrong_whole;
  for (int k = 0; k < 3; ++k) to.deeper_than[k] += e.deeper_than[k];
  to.deepest = std::max(to.deepest, e.deepest);
}

nlohmann::json errors_json(const LabelErrors& e) {
  return {{"cells", e.cells},
          {"wrong", e.wrong},
          {"wrong_whole", e.wrong_whole},
          {"wrong_deeper_than_1", e.deeper_than[0]},
          {"wrong_deeper_than_2", e.deeper_than[1]},
          {"wrong_deeper_than_4", e.deeper_than[2]},
          {"deepest", e.deepest}};
}
}  // namespace

LabelTruth check_labels(const tet::TetMesh& m, const std::vector<std::int8_t>& label,
                        const std::vector<std::uint8_t>& reason, const MeshBVH& gt) {
  const std::int32_t C = m.num_cells();
  require(static_cast<std::int64_t>(label.size()) == C, "check_labels: ", label.size(), " labels for ", C, " cells");
  require(reason.empty() || static_cast<std::int64_t>(reason.size()) == C, "check_labels: ", reason.size(),
          " reasons for ", C, " cells");
  require(gt.num_primitives() > 0 && !gt.points_only(), "check_labels: the ground truth has no triangles");
  LabelTruth t;
  t.cell = tet::red_edge_length(m.lat, m.max_cell_level());
  // Per cell: 0 unlabelled or right, 1 wrong, 2 wholly wrong; and the depth of a wrong one.
  std::vector<std::uint8_t> wrong(C, 0);
  std::vector<float> depth(C, 0);
#pragma omp parallel for schedule(dynamic, 4096)
  for (std::int32_t c = 0; c < C; ++c) {
    if (label[c] == 0) continue;
    const bool want_inside = label[c] > 0;
    if (gt.inside(m.cell_centroid(c)) == want_inside) continue;
    bool whole = true;
    for (int k = 0; k < 4 && whole; ++k) whole = gt.inside(m.vertex(m.cell_v[c][k])) != want_inside;
    wrong[c] = whole ? 2 : 1;
    depth[c] = static_cast<float>(gt.closest(m.cell_centroid(c)).dist() / t.cell);
  }
  for (std::int32_t c = 0; c < C; ++c) {  // sequential: the same sums whatever the threads
    if (label[c] == 0) continue;
    LabelErrors e;
    e.cells = 1;
    if (wrong[c]) {
      t.wrong_cells.push_back(c);
      if (wrong[c] == 2) t.wrong_whole_cells.push_back(c);
      e.wrong = 1;
      e.wrong_whole = wrong[c] == 2;
      for (int k = 0; k < 3; ++k) e.deeper_than[k] = depth[c] > kTruthDepths[k];
      e.deepest = depth[c];
    }
    add(label[c] > 0 ? t.interior : t.exterior, e);
    if (!reason.empty()) add(t.by_reason[reason[c]], e);
  }
  return t;
}

nlohmann::json to_json(const LabelTruth& t) {
  nlohmann::json by = nlohmann::json::array();
  for (const auto& [code, e] : t.by_reason) {
    nlohmann::json j = errors_json(e);
    j["reason"] = code;
    j["name"] = reason_name(code);
    by.push_back(j);
  }
  const std::size_t listed = std::min(t.wrong_cells.size(), kMaxWrongCellsListed);
  const std::size_t listed_whole = std::min(t.wrong_whole_cells.size(), kMaxWrongCellsListed);
  return {{"cell_size", t.cell},
          {"interior", errors_json(t.interior)},
          {"exterior", errors_json(t.exterior)},
          {"by_reason", by},
          {"wrong_cells", std::vector<std::int32_t>(t.wrong_cells.begin(), t.wrong_cells.begin() + listed)},
          {"wrong_whole_cells",
           std::vector<std::int32_t>(t.wrong_whole_cells.begin(), t.wrong_whole_cells.begin() + listed_whole)},
          {"wrong_cells_truncated", listed < t.wrong_cells.size() || listed_whole < t.wrong_whole_cells.size()}};
}

}  // namespace tetmvs::label
