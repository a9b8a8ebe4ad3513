#include "common/photoconsist/face_scores.h"

#include "common/error.h"
#include "common/log.h"
#include "common/photo/camera_select.h"
#include "common/photo/face_score.h"

namespace tetmvs::photoconsist {

std::vector<std::uint8_t> faces_to_score(const tet::TetMesh& m) {
  const std::int32_t C = m.num_cells();
  require(static_cast<std::int32_t>(m.cell_new_red.size()) == C, "photoconsist: the mesh has no cell_new_red flags");
  std::vector<std::uint8_t> near(C, 0);
  for (std::int32_t c = 0; c < C; ++c) {
    if (!m.cell_new_red[c]) continue;
    near[c] = 1;
    for (int j = 0; j < 4; ++j) {
      const std::int32_t o = m.neighbour(c, j);
      if (o >= 0) near[o] = 1;
    }
  }
  std::vector<std::uint8_t> sel(m.num_faces(), 0);
  for (std::int32_t c = 0; c < C; ++c)
    if (near[c])
      for (int j = 0; j < 4; ++j) sel[m.cell_face[c][j]] = 1;
  return sel;
}

ScoresResult score_faces(const tet::TetMesh& m, const photo::Views& views, const HullTest& hull,
                         const photo::Options& opts, const std::vector<std::uint8_t>& selected, bool progress,
                         const OcclusionMaps* occl) {
  const std::int32_t F = m.num_faces();
  require(static_cast<std::int32_t>(selected.size()) == F, "photoconsist: face selection has ", selected.size(),
          " flags for ", F, " faces");
  ScoresResult R;
  R.omega.assign(2 * static_cast<std::size_t>(F), 0.f);
  std::vector<std::int32_t> list;
  for (std::int32_t f = 0; f < F; ++f)
    if (selected[f]) list.push_back(f);
  R.scored_faces = static_cast<std::int64_t>(list.size());
  std::vector<std::uint8_t> outside(list.size(), 0), defined(list.size(), 0), hidden(list.size(), 0);
  require(hull.views() == &views, "photoconsist: the hull test of the face scores must be made on their views");
  if (occl && occl->empty()) occl = nullptr;
  require(!occl || occl->num_views() == views.size(), "photoconsist: occlusion maps of ",
          occl ? occl->num_views() : 0, " views for ", views.size(), " views");
  Progress bar("photoconsist face scores", progress ? R.scored_faces : 0);
#pragma omp parallel
  {
    photo::Scratch scratch;
    std::vector<std::uint8_t> mask(static_cast<std::size_t>(views.size()), 0);
#pragma omp for schedule(dynamic, 64)
    for (std::int64_t q = 0; q < R.scored_faces; ++q) {
      const std::int32_t f = list[q];
      const auto fv = m.face_vertices(f);
      const Eigen::Vector3d a = m.vertex(fv[0]), b = m.vertex(fv[1]), c = m.vertex(fv[2]);
      const Eigen::Vector3d X = photo::face_centroid(a, b, c);
      // the views' projections of the centroid, for the hull test and the patches
      scratch.hidden = nullptr;
      photo::detail::prepare_centre(views, X, opts, scratch);
      if (!hull.inside_projected([&](int v) -> const Eigen::Vector3d& { return scratch.cache[v].h0; })) {
        outside[q] = 1;
      } else {
        if (occl && occl->hidden_views(views, X, mask.data()) > 0) {
          scratch.hidden = mask.data(), hidden[q] = 1;
          photo::detail::prepare_centre(views, X, opts, scratch);  // without the hidden views
        }
        photo::PatchResult p0, p1;
        photo::face_patches_prepared(views, a, b, c, opts, scratch, p0, p1);
        R.omega[2 * static_cast<std::size_t>(f)] = p0.omega();
        R.omega[2 * static_cast<std::size_t>(f) + 1] = p1.omega();
        defined[q] = static_cast<std::uint8_t>(p0.valid() + p1.valid());
        scratch.hidden = nullptr;
      }
      if (progress) bar.tick();
    }
  }
  bar.done();
  for (std::size_t q = 0; q < list.size(); ++q) R.outside_hull += outside[q], R.defined += defined[q], R.hidden += hidden[q];
  return R;
}

}  // namespace tetmvs::photoconsist
