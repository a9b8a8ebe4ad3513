// The silhouette-fix stage's computation around fix_silhouettes (silfix.h): what it takes
// from labels.h5 and the first cut, and everything silfix.h5 holds (silfix_file.h writes it).
#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "common/render/shaded.h"
#include "common/silfix/silfix.h"

namespace tetmvs::silfix {

// What silhouette-fix takes from labels.h5: the labels it starts from, and what it passes
// on unchanged (the cut's evidence and some counts, when the file has them).
struct LabelsIn {
  std::vector<std::int8_t> label;    // /cells/label (values -1, 0, 1)
  std::vector<std::uint8_t> reason;  // /cells/reason
  std::vector<std::int32_t> votes;   // /cells/votes
  std::optional<std::vector<float>> inside_evidence, outside_evidence;
  std::optional<double> low_votes, high_votes;
  std::optional<std::int64_t> rays, boundary, hull_exterior, voted_out;
};
LabelsIn read_labels_in(const std::filesystem::path& labels_file, std::int64_t num_cells);

// S1: rebuilt from the first cut's /cells/inside (cut_file, a tetmvs.cut file) or read from
// a PLY (surface_file); exactly one of them is non-empty.
TriMesh read_first_surface(const tet::TetMesh& mesh, const std::filesystem::path& cut_file,
                           const std::filesystem::path& surface_file);

// Everything silfix.h5 holds.
struct Outcome {
  LabelsIn in;                     // the labels the fix started from
  Result fix;                      // the updated labels, the constraints, per view numbers
  SilhouetteAgreement s1;          // S1's agreement with the silhouettes (zeros when passed through)
  std::int64_t interior = 0, exterior = 0;  // cells labelled so after the fix
  std::optional<std::string> note;  // set when the labels were passed through unchanged
};

// The note of a scene without any silhouette.
inline constexpr const char* kPassThroughNote =
    "no view has a silhouette: silhouette-fix skipped, labels passed through unchanged";

// fix_silhouettes and S1's silhouette agreement; without any silhouette in the scene there is
// nothing to fix: the labels pass through unchanged (no constraints, `note` set), so that the
// second cut still has its input.
Outcome fix_labels(const tet::TetMesh& mesh, const Scene& scene, const TriMesh& s1, const std::vector<float>& omega,
                   LabelsIn in, const Options& o);

}  // namespace tetmvs::silfix
