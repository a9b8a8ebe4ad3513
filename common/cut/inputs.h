// Reading the cut's inputs with their validation (shared by `cut` and `silhouette-fix`):
// the face scores omega of scores.h5 and the hard labels of labels.h5 / silfix.h5.
#pragma once
#include <cstdint>
#include <filesystem>
#include <vector>

namespace tetmvs::cut {

// /faces/omega of a tetmvs.scores file: 2 values per face, each in [0, 1].
std::vector<float> read_omega(const std::filesystem::path& scores_file, std::int64_t num_faces);

// /cells/label of a tetmvs.labels file (values -1, 0, 1).
std::vector<std::int8_t> read_labels(const std::filesystem::path& labels_file, std::int64_t num_cells);

}  // namespace tetmvs::cut
