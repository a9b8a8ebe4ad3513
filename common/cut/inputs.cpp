#include "common/cut/inputs.h"

#include "common/error.h"
#include "common/h5io.h"
#include "common/reason.h"

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

LabelInput read_label_input(const std::filesystem::path& labels_file, std::int64_t num_cells, bool with_evidence) {
  LabelInput in;
  in.file = labels_file;
  in.label = read_labels(labels_file, num_cells);
  const std::int64_t C = num_cells;
  auto lf = h5::File::open(labels_file, "tetmvs.labels");  // its other datasets
  if (with_evidence && lf.has("/cells/inside_evidence") && lf.has("/cells/outside_evidence")) {
    in.inside_evidence = lf.read<float>("/cells/inside_evidence", {C}).data;
    in.outside_evidence = lf.read<float>("/cells/outside_evidence", {C}).data;
    for (std::int64_t c = 0; c < C; ++c)
      require(in.inside_evidence[c] >= 0 && in.inside_evidence[c] <= 1 && in.outside_evidence[c] >= 0 &&
                  in.outside_evidence[c] <= 1,
              labels_file.string(), ": evidence values must lie in [0, 1]");
  }
  in.weak.assign(C, 0);
  if (lf.has("/cells/reason")) {
    const auto reason = lf.read<std::uint8_t>("/cells/reason", {C});
    for (std::int64_t c = 0; c < C; ++c)
      in.weak[c] = in.label[c] > 0 && (reason.data[c] == kSilfixInterior || reason.data[c] == kHullCore);
  }
  return in;
}

}  // namespace tetmvs::cut
