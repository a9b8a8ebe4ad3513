#include "common/silfix/fix_labels.h"

#include "common/cut/inputs.h"
#include "common/cut/surface.h"
#include "common/error.h"
#include "common/h5io.h"
#include "common/log.h"
#include "common/ply.h"

namespace tetmvs::silfix {

LabelsIn read_labels_in(const std::filesystem::path& labels_file, std::int64_t num_cells) {
  const std::int64_t C = num_cells;
  LabelsIn in;
  in.label = cut::read_labels(labels_file, C);
  auto lf = h5::File::open(labels_file, "tetmvs.labels");  // its other datasets
  in.reason = lf.read<std::uint8_t>("/cells/reason", {C}).data;
  in.votes = lf.read<std::int32_t>("/cells/votes", {C}).data;
  // for the cut's visibility term
  if (lf.has("/cells/inside_evidence")) in.inside_evidence = lf.read<float>("/cells/inside_evidence", {C}).data;
  if (lf.has("/cells/outside_evidence")) in.outside_evidence = lf.read<float>("/cells/outside_evidence", {C}).data;
  for (auto [a, v] : {std::pair{"low_votes", &in.low_votes}, std::pair{"high_votes", &in.high_votes}})
    if (lf.has_attr("/", a)) *v = lf.attr_double("/", a);
  for (auto [a, v] : {std::pair{"rays", &in.rays}, std::pair{"boundary", &in.boundary},
                      std::pair{"hull_exterior", &in.hull_exterior}, std::pair{"voted_out", &in.voted_out}})
    if (lf.has_attr("/", a)) *v = lf.attr_int("/", a);
  return in;
}

TriMesh read_first_surface(const tet::TetMesh& mesh, const std::filesystem::path& cut_file,
                           const std::filesystem::path& surface_file) {
  if (!cut_file.empty()) {
    auto cf = h5::File::open(cut_file, "tetmvs.cut");
    const auto inside = cf.read<std::uint8_t>("/cells/inside", {mesh.num_cells()});
    return cut::cut_surface(mesh, inside.data);
  }
  return read_ply(surface_file);
}

Outcome fix_labels(const tet::TetMesh& mesh, const Scene& scene, const TriMesh& s1, const std::vector<float>& omega,
                   LabelsIn in, const Options& o) {
  Outcome out;
  if (scene.num_silhouettes() == 0) {
    info("silhouette-fix: ", kPassThroughNote);
    out.fix.label = in.label;
    out.fix.reason = in.reason;
    out.fix.s1_masks.resize(scene.size());
    out.note = kPassThroughNote;
  } else {
    out.fix = fix_silhouettes(mesh, scene, s1, omega, in.label, in.reason, o);
    out.s1 = silhouette_agreement(s1, scene);
  }
  for (auto l : out.fix.label) out.interior += l > 0, out.exterior += l < 0;
  out.in = std::move(in);
  return out;
}

}  // namespace tetmvs::silfix
