#include "common/cut/cleanup.h"

#include <algorithm>

namespace tetmvs::cut {

namespace {
// Face-connected regions of cells with inside[c] == side; region id per cell (-1 other side).
std::int32_t regions(const tet::TetMesh& m, const std::vector<std::uint8_t>& inside, std::uint8_t side,
                     std::vector<std::int32_t>& region) {
  const std::int32_t C = m.num_cells();
  region.assign(C, -1);
  std::int32_t n = 0;
  std::vector<std::int32_t> stack;
  for (std::int32_t s = 0; s < C; ++s) {
    if (inside[s] != side || region[s] >= 0) continue;
    region[s] = n;
    stack.push_back(s);
    while (!stack.empty()) {
      const std::int32_t c = stack.back();
      stack.pop_back();
      for (int j = 0; j < 4; ++j) {
        const std::int32_t d = m.neighbour(c, j);
        if (d >= 0 && inside[d] == side && region[d] < 0) {
          region[d] = n;
          stack.push_back(d);
        }
      }
    }
    ++n;
  }
  return n;
}
}  // namespace

CleanupStats clean_up_regions(const tet::TetMesh& m, const std::vector<std::int8_t>& labels,
                              std::vector<std::uint8_t>& inside, double min_fraction,
                              const std::vector<std::uint8_t>* weak) {
  CleanupStats st;
  const std::int32_t C = m.num_cells();
  std::vector<std::int32_t> region;
  // voids
  {
    const std::int32_t n = regions(m, inside, 0, region);
    std::vector<std::uint8_t> open(n, 0);
    for (std::int32_t c = 0; c < C; ++c) {
      if (region[c] < 0) continue;
      for (int j = 0; j < 4; ++j)
        if (m.neighbour(c, j) < 0) open[region[c]] = 1;
    }
    for (std::int32_t r = 0; r < n; ++r) st.voids_filled += !open[r];
    for (std::int32_t c = 0; c < C; ++c)
      if (region[c] >= 0 && !open[region[c]]) {
        inside[c] = 1;
        ++st.void_cells;
        st.void_exterior_cells += labels[c] < 0;
      }
  }
  // specks
  {
    const std::int32_t n = regions(m, inside, 1, region);
    std::vector<double> volume(n, 0.0);
    std::vector<std::uint8_t> seeded(n, 0);
    for (std::int32_t c = 0; c < C; ++c)
      if (region[c] >= 0) {
        volume[region[c]] += m.cell_volume(c);
        if (labels[c] > 0 && !(weak && (*weak)[c])) seeded[region[c]] = 1;
      }
    const double largest = n ? *std::max_element(volume.begin(), volume.end()) : 0.0;
    std::vector<std::uint8_t> drop(n, 0);
    for (std::int32_t r = 0; r < n; ++r) drop[r] = !seeded[r] && volume[r] < min_fraction * largest;
    for (std::int32_t r = 0; r < n; ++r) st.specks_removed += drop[r];
    for (std::int32_t c = 0; c < C; ++c)
      if (region[c] >= 0 && drop[region[c]]) {
        inside[c] = 0;
        ++st.speck_cells;
      }
    st.inside_regions = n - st.specks_removed;
  }
  return st;
}

}  // namespace tetmvs::cut
