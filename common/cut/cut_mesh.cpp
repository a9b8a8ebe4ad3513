#include "common/cut/cut_mesh.h"

#include "common/error.h"

namespace tetmvs::cut {

Cut cut_mesh(const tet::TetMesh& mesh, const std::vector<float>& omega, const LabelInput& labels, CutOptions opt,
             double min_region_fraction) {
  if (!labels.inside_evidence.empty()) {
    opt.inside_evidence = &labels.inside_evidence;
    opt.outside_evidence = &labels.outside_evidence;
  }
  Cut c;
  c.flow = min_cut(mesh, omega, labels.label, opt);
  c.cleanup = clean_up_regions(mesh, labels.label, c.flow.inside, min_region_fraction, &labels.weak);
  require(c.flow.cut_faces > 0, labels.file.string(),
          ": the cut is empty (no interior cells survive); check the labels");
  c.surface = cut_surface(mesh, c.flow.inside, &c.surface_stats, &c.face_ids);
  c.check = check_mesh(c.surface);
  return c;
}

}  // namespace tetmvs::cut
