// Reading the cut's inputs with their validation (shared by `cut` and `silhouette-fix`):
// the face scores omega of scores.h5 and the hard labels of labels.h5 / silfix.h5, with the
// rest of what `cut` takes from a labels file.
#pragma once
#include <cstdint>
#include <filesystem>
#include <vector>

namespace tetmvs::cut {

// /faces/omega of a tetmvs.scores file: 2 values per face, each in [0, 1].
std::vector<float> read_omega(const std::filesystem::path& scores_file, std::int64_t num_faces);

// /cells/label of a tetmvs.labels file (values -1, 0, 1).
std::vector<std::int8_t> read_labels(const std::filesystem::path& labels_file, std::int64_t num_cells);

// What `cut` takes from a labels file.
struct LabelInput {
  std::filesystem::path file;
  std::vector<std::int8_t> label;  // read_labels
  // /cells/inside_evidence and /cells/outside_evidence (each in [0, 1]) for the visibility
  // term; empty unless asked for and the file has both
  std::vector<float> inside_evidence, outside_evidence;
  // per cell, 1 for an interior label that does not protect a speck from the clean-up:
  // silhouette-fix's constraints (kSilfixInterior) and the hull-core prior's (kHullCore; a
  // core cell cut off from the body by the band is a single-cell shell, not a part of the
  // object); all 0 when the file has no /cells/reason
  std::vector<std::uint8_t> weak;
};
LabelInput read_label_input(const std::filesystem::path& labels_file, std::int64_t num_cells, bool with_evidence);

}  // namespace tetmvs::cut
