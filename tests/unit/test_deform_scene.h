// Synthetic scenes for the deform tests: an object of common/synth rendered in memory
// by a small ring of cameras (dino-scale: 7 cm box, cameras at 0.65 m), and a faceted
// start surface made the way the pipeline makes S2: the boundary of the cells of a BCC
// tetrahedral mesh whose centroids lie inside the ground truth (cut::cut_surface).
#pragma once
#include <Eigen/Geometry>
#include <cmath>
#include <string>
#include <vector>

#include "common/cut/surface.h"
#include "common/scene.h"
#include "common/synth/objects.h"
#include "common/synth/scene.h"
#include "common/synth/texture.h"
#include "common/tetmesh/tetmesh.h"
#include "common/trimesh/bvh.h"
#include "common/trimesh/evaluate.h"

namespace tetmvs::testing {

struct DeformScene {
  Scene scene;
  TriMesh gt;
  double px = 0;  // pixel footprint at the box centre (world units)
};

inline DeformScene make_deform_scene(const std::string& object, int views = 12, double texture = 1.0, int w = 320,
                                     int h = 240) {
  DeformScene d;
  Scene& s = d.scene;
  s.box = Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-0.035), Eigen::Vector3d::Constant(0.035));
  s.box_source = "given";
  s.dataset = object;
  const double R = 0.5 * s.box.sizes().norm();
  const double f = 0.5 * std::min(w, h) / std::tan(std::asin(R / 0.65));
  s.cams = synth::ring_cameras(views, 20, 0.65, s.box.center(), w, h, f);
  const Eigen::Vector3d up = synth::scene_up(s.cams, s.box.center());
  d.px = pixel_footprint(s.cams, s.box.center());
  d.gt = synth::make_placed_object(object, s.box, up, 0.85, 1.0 * d.px);
  synth::TextureOptions to;
  to.strength = texture;
  to.min_scale = 3 * d.px;
  to.max_scale = 40 * d.px;
  const synth::SolidTexture tex(to);
  synth::ShadingOptions sh;
  Eigen::Vector3d toward = s.cams[0].centre() - s.box.center();
  toward -= toward.dot(up) * up;
  sh.light = (up + toward.normalized()).normalized();
  s.rgb.resize(views);
  s.sil.resize(views);
#pragma omp parallel for schedule(dynamic, 1)
  for (int i = 0; i < views; ++i) {
    const synth::RenderedView rv = synth::render_view(d.gt, s.cams[i], tex, sh, i);
    s.rgb[i] = rv.rgb;
    s.sil[i] = rv.mask;
  }
  s.load_grey();
  return d;
}

// The faceted start surface: BCC cells of cube edge `cell` (world units) whose centroid
// is inside the ground truth; their boundary, made edge-manifold by cut_surface.
inline TriMesh bcc_start_surface(const TriMesh& gt, double cell) {
  auto [lo, hi] = bounds(gt);
  const Eigen::AlignedBox3d box(lo - Eigen::Vector3d::Constant(cell), hi + Eigen::Vector3d::Constant(cell));
  const int cells = static_cast<int>(std::ceil(box.sizes().maxCoeff() / cell));
  const tet::TetMesh m = tet::build_bcc(tet::lattice_for_box(box, cells));
  const MeshBVH bvh(gt);
  std::vector<std::uint8_t> inside(m.num_cells());
#pragma omp parallel for schedule(static)
  for (int c = 0; c < m.num_cells(); ++c) inside[c] = bvh.inside(m.cell_centroid(c));
  return cut::cut_surface(m, inside);
}

inline EvalResult evaluate_px(const TriMesh& rec, const DeformScene& d) {
  EvalOptions o;
  o.spacing = 0.5 * d.px;
  o.thresholds = {0.00125, 1.0 * d.px};
  return evaluate(rec, d.gt, d.scene.cams, o);
}

}  // namespace tetmvs::testing
