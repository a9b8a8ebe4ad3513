// Groups of cells joined by faces.
#include <algorithm>

#include "common/error.h"
#include "common/label/geometry.h"
#include "common/label/labels.h"

namespace tetmvs::label {

std::vector<std::int32_t> group_sizes(const tet::TetMesh& m, const std::vector<std::uint8_t>& in) {
  const std::int32_t C = m.num_cells();
  require(static_cast<std::int64_t>(in.size()) == C, "group_sizes: ", in.size(), " flags for ", C, " cells");
  std::vector<std::int32_t> parent(C);
  for (std::int32_t c = 0; c < C; ++c) parent[c] = c;
  const auto find = [&](std::int32_t c) {
    while (parent[c] != c) c = parent[c] = parent[parent[c]];
    return c;
  };
  for (std::int32_t f = 0; f < m.num_faces(); ++f) {  // union by the smaller root: deterministic
    const std::int32_t a = m.face_cell(f, 0), b = m.face_cell(f, 1);
    if (b < 0 || !in[a] || !in[b]) continue;
    const std::int32_t ra = find(a), rb = find(b);
    if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
  }
  std::vector<std::int32_t> size(C, 0);
  for (std::int32_t c = 0; c < C; ++c)
    if (in[c]) ++size[find(c)];
  std::vector<std::int32_t> out(C, 0);
  for (std::int32_t c = 0; c < C; ++c)
    if (in[c]) out[c] = size[find(c)];
  return out;
}

std::vector<std::uint8_t> small_groups(const tet::TetMesh& m, const std::vector<std::uint8_t>& in, double share) {
  const auto size = group_sizes(m, in);
  const std::int32_t largest = size.empty() ? 0 : *std::max_element(size.begin(), size.end());
  std::vector<std::uint8_t> small(size.size(), 0);
  for (std::size_t c = 0; c < size.size(); ++c) small[c] = in[c] && size[c] < share * largest;
  return small;
}

}  // namespace tetmvs::label
