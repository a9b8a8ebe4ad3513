#include "common/photoconsist/files.h"

#include <algorithm>

#include <string>

#include "common/error.h"
#include "common/h5io.h"

namespace tetmvs::photoconsist {

void LeveledPoints::append(const QPoints& more, int lvl, bool keep_face) {
  for (std::int64_t p = 0; p < more.size(); ++p) {
    const std::vector<std::int32_t> cams(more.cams.begin() + more.cam_offsets[p],
                                         more.cams.begin() + more.cam_offsets[p + 1]);
    q.add(more.pos(p), more.nrm(p).cast<double>(), more.score[p], cams, keep_face ? more.face[p] : -1);
    level.push_back(lvl);
  }
}

QPoints LeveledPoints::of_level(int lvl) const {
  QPoints out;
  std::vector<std::int32_t> cams;
  for (std::int64_t p = 0; p < q.size(); ++p) {
    if (level[p] != lvl) continue;
    cams.assign(q.cams.begin() + q.cam_offsets[p], q.cams.begin() + q.cam_offsets[p + 1]);
    out.add(q.pos(p), q.nrm(p).cast<double>(), q.score[p], cams, -1);
  }
  return out;
}

int LeveledPoints::last_level() const {
  int last = -1;
  for (const std::int32_t l : level) last = std::max(last, static_cast<int>(l));
  return last;
}

const h5::Fields<LeveledPoints>& leveled_points_fields() {
  static const h5::Fields<LeveledPoints> t = h5::Fields<LeveledPoints>()
                                                 .group("", &LeveledPoints::q, qpoints_fields())
                                                 .dataset("level", &LeveledPoints::level);
  return t;
}

void write_leveled_points(h5::File& f, const LeveledPoints& p, const std::string& g) {
  f.create_group(g);
  leveled_points_fields().write(f, p, g);
}

namespace {

const h5::Fields<LevelEvalOutput>& eval_fields() {
  using E = LevelEvalOutput;
  static const h5::Fields<E> t =
      h5::Fields<E>()
          .dataset("face_gt_crossed", [](const E& e) -> const auto& { return e.eval.face_gt_crossed; })
          .dataset("face_gt_distance", [](const E& e) -> const auto& { return e.eval.face_gt_distance; })
          .attr("", "recall", [](const E& e) { return e.eval.recall(); }).show("recall", 4)
          .attr("", "precision", [](const E& e) { return e.eval.precision(); }).show("precision", 4)
          .attr("", "cell_recall", [](const E& e) { return e.eval.cell_recall(); }).show("cell_recall", 4)
          .attr("", "points_within_cell", [](const E& e) { return e.eval.points_accuracy(); }).show("Q_within_cell", 3)
          .attr("", "gt_crossed", [](const E& e) { return e.eval.gt_crossed; }).show()
          .attr("", "found", [](const E& e) { return e.eval.found; }).show()
          .attr("", "crossing", [](const E& e) { return e.eval.crossing; })
          .attr("", "crossing_near", [](const E& e) { return e.eval.crossing_near; })
          .attr("", "active", [](const E& e) { return e.eval.active; })
          .attr("", "active_far", [](const E& e) { return e.eval.active_far; })
          .attr("", "active_far_air", [](const E& e) { return e.eval.active_far_air; })
          .attr("", "active_far_share", [](const E& e) { return e.eval.active_far_share(); }).show("active_far", 3)
          .attr("", "cell_size", &E::cell_size)
          .attr("", "near_dist", [](const E& e) { return e.eval.near_dist; });
  return t;
}

}  // namespace

const h5::Fields<LevelOutput>& level_fields() {
  using L = LevelOutput;
  const auto occluded = [](const L& o) { return o.occlusion; };
  static const h5::Fields<L> t =
      h5::Fields<L>()
          .attr("/", "level", &L::level).show()
          .attr("/", "pyramid", &L::pyramid).show()
          .attr("/", "cell_px", &L::cell_px)
          .dataset("/cells/active", [](const L& o) -> const auto& { return o.pass.active; })
          .count("faces_tested", [](const L& o) { return o.pass.face.size(); })
          .count("reused", [](const L& o) { return o.pass.reused_faces; })
          .count("lattice_points", [](const L& o) { return o.pass.lattice_points; })
          .dataset("/faces/tested", [](const L& o) -> const auto& { return o.pass.face; })
          .dataset("/faces/divisions", [](const L& o) -> const auto& { return o.pass.divisions; })
          .dataset("/faces/samples", [](const L& o) -> const auto& { return o.pass.samples; })
          .dataset("/faces/consistent", [](const L& o) -> const auto& { return o.pass.consistent; })
          .dataset("/faces/crossing", [](const L& o) -> const auto& { return o.pass.crossing; })
          .dataset("/faces/reused", [](const L& o) -> const auto& { return o.pass.reused; })
          .dataset("/faces/best_score", [](const L& o) -> const auto& { return o.pass.best_score; })
          .attr("/faces", "distinct_points", [](const L& o) { return o.pass.distinct_points; }).show()
          .count("in_hull", [](const L& o) { return o.pass.sample_points; })
          .count("scored", [](const L& o) { return o.pass.scored_points; })
          .count("consistent", [](const L& o) { return o.pass.consistent_points; })
          .count("crossing_faces", [](const L& o) { return o.pass.crossing_faces; })
          .count("active_cells",
                 [](const L& o) { return std::to_string(o.pass.active_cells) + "/" + std::to_string(o.num_cells); })
          .count("points", [](const L& o) { return o.pass.points.size(); })
          .count("Q", [](const L& o) { return o.all.q.size(); })
          .attr("/faces", "occluders", &L::occluders).show().show_when(occluded)
          .attr("/faces", "occluders_dropped", &L::occluders_dropped).show().show_when(occluded)
          .attr("/faces", "hidden_points", [](const L& o) { return o.pass.hidden_points; }).show().show_when(occluded)
          .attr("/faces", "rescored_points", [](const L& o) { return o.pass.rescored_points; })
          .show("rescored").show_when(occluded)
          .attr("/faces", "hull_dropped_points", [](const L& o) { return o.pass.hull_dropped_points; })
          .show("hull_dropped").show_when([](const L& o) { return o.q_hull_views > 0; })
          .attr("/faces", "sight_faces", [](const L& o) { return o.pass.sight_faces; }).show("in_seen_air")
          .attr("/faces", "hull_added_points", [](const L& o) { return o.pass.hull_added_points; })
          .show("hull_added").show_when([](const L& o) { return o.q_hull_views > 0; })
          .group("/points", [](const L& o) -> const auto& { return o.pass.points; }, qpoints_fields())
          .group("/points_all", &L::all, leveled_points_fields())
          .group("/cache", [](const L& o) -> const auto& { return o.pass.cache; }, face_cache_fields())
          .attr("/", "q_hull_views", &L::q_hull_views).show().show_when([](const L& o) { return o.q_hull_views > 0; })
          .attr("/", "q_hull_gt_inside", &L::q_hull_gt_inside).show()
          .group("/eval", &L::eval, eval_fields());
  return t;
}

const h5::Fields<ScoresOutput>& scores_fields() {
  using S = ScoresOutput;
  const auto occluded = [](const S& o) { return o.occlusion; };
  static const h5::Fields<S> t =
      h5::Fields<S>()
          .count("faces", &S::num_faces)
          .dataset("/faces/omega", [](const S& o) -> const auto& { return o.scores.omega; }, 2)
          .dataset("/faces/scored", &S::scored)
          .attr("/faces", "scored_faces", [](const S& o) { return o.scores.scored_faces; }).show("scored")
          .attr("/faces", "outside_hull", [](const S& o) { return o.scores.outside_hull; }).show()
          .count("defined_orientations", [](const S& o) { return o.scores.defined; })
          .count("points", [](const S& o) { return o.q.q.size(); })
          .attr("/faces", "occluders", &S::occluders).show().show_when(occluded)
          .attr("/faces", "occluders_dropped", &S::occluders_dropped).show().show_when(occluded)
          .attr("/faces", "hidden_faces", [](const S& o) { return o.scores.hidden; }).show().show_when(occluded)
          .attr("/", "level", &S::level)
          .group("/points", &S::q, leveled_points_fields())
          .attr("/points", "within_final_cell_of_gt", &S::q_within_cell).show("Q_within_cell")
          .attr("/", "q_hull_views", &S::q_hull_views).show().show_when([](const S& o) { return o.q_hull_views > 0; })
          .attr("/", "q_hull_gt_inside", &S::q_hull_gt_inside).show();
  return t;
}

LeveledPoints read_leveled_points(const h5::File& f, int num_cameras, const std::string& g) {
  LeveledPoints p;
  p.q = read_qpoints(f, num_cameras, g);
  p.level = f.read<std::int32_t>(g + "/level", {p.q.size()}).data;
  return p;
}

}  // namespace tetmvs::photoconsist
