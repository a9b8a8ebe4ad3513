#include "common/deform/stats_file.h"

#include <string>

namespace tetmvs::deform {

namespace {

// The getter of /iterations/<member>: the member of every iteration.
template <typename M>
auto per_iteration(M IterationStats::*member) {
  return [member](const Result& r) { return h5::column(r.iterations, member); };
}

h5::Fields<Result> make_stats_fields() {
  h5::Fields<Result> t;
  t.dataset("/iterations/iteration", per_iteration(&IterationStats::iteration))
      .dataset("/iterations/vertices", per_iteration(&IterationStats::vertices))
      .dataset("/iterations/faces", per_iteration(&IterationStats::faces))
      .dataset("/iterations/mean_move", per_iteration(&IterationStats::mean_move))
      .dataset("/iterations/mean_move_px", per_iteration(&IterationStats::mean_move_px))
      .dataset("/iterations/max_move_px", per_iteration(&IterationStats::max_move_px))
      .dataset("/iterations/photo_level", per_iteration(&IterationStats::photo_level))
      .dataset("/iterations/photo_pixels", per_iteration(&IterationStats::photo_pixels))
      .dataset("/iterations/mean_ncc", per_iteration(&IterationStats::mean_ncc))
      .dataset("/iterations/photo_moved", per_iteration(&IterationStats::photo_moved))
      .dataset("/iterations/mean_photo_step_px", per_iteration(&IterationStats::mean_photo_step_px))
      .dataset("/iterations/rim_vertices", per_iteration(&IterationStats::rim_vertices))
      .dataset("/iterations/spread_vertices", per_iteration(&IterationStats::spread_vertices))
      .dataset("/iterations/silhouette_iou", per_iteration(&IterationStats::silhouette_iou))
      .dataset("/iterations/splits", per_iteration(&IterationStats::splits))
      .dataset("/iterations/collapses", per_iteration(&IterationStats::collapses))
      .dataset("/iterations/flips", per_iteration(&IterationStats::flips))
      .dataset("/iterations/reduced_vertices", per_iteration(&IterationStats::reduced_vertices))
      .dataset("/iterations/intersections", per_iteration(&IterationStats::intersections))
      .attr("/", "start_intersections", &Result::start_intersections)
      .attr("/", "final_intersections", &Result::final_intersections)
      .attr("/", "start_iou", &Result::start_iou)
      .attr("/", "final_iou", &Result::final_iou)
      .attr("/", "final_vertices", [](const Result& r) { return r.mesh.nv(); })
      .attr("/", "final_faces", [](const Result& r) { return r.mesh.nf(); })
      .attr("/", "footprint", &Result::footprint);
  return t;
}

}  // namespace

const h5::Fields<Result>& stats_fields() {
  static const h5::Fields<Result> t = make_stats_fields();
  return t;
}

}  // namespace tetmvs::deform
