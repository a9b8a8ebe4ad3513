#include "common/cut/inputs.h"

#include "common/error.h"
#include "common/h5io.h"

namespace tetmvs::cut {

std::vector<float> read_omega(const std::filesystem::path& scores_file, std::int64_t num_faces) {
  auto sf = h5::File::open(scores_file, "tetmvs.scores");
  auto omega = sf.read<float>("/faces/omega", {num_faces, 2}).data;
  for (float w : omega)
    require(w >= 0.0f && w <= 1.0f, scores_file.string(), ": /faces/omega values must lie in [0, 1]");
  return omega;
}

std::vector<std::int8_t> read_labels(const std::filesystem::path& labels_file, std::int64_t num_cells) {
  auto lf = h5::File::open(labels_file, "tetmvs.labels");
  auto labels = lf.read<std::int8_t>("/cells/label", {num_cells}).data;
  for (auto l : labels)
    require(l >= -1 && l <= 1, labels_file.string(), ": /cells/label values must be -1, 0 or 1");
  return labels;
}

}  // namespace tetmvs::cut
