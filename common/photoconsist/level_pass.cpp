#include "common/photoconsist/level_pass.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "common/error.h"
#include "common/log.h"
#include "common/photo/lattice.h"

namespace tetmvs::photoconsist {

FaceLat face_lat(const tet::TetMesh& m, std::int32_t f) {
  const auto fv = m.face_vertices(f);
  FaceLat l;
  for (int v = 0; v < 3; ++v)
    for (int k = 0; k < 3; ++k) l[3 * v + k] = m.vlat[3 * fv[v] + k];
  return l;
}

std::vector<std::int32_t> faces_of_new_cells(const tet::TetMesh& m) {
  std::vector<std::uint8_t> take(m.num_faces(), 0);
  for (std::int32_t c = 0; c < m.num_cells(); ++c)
    if (m.cell_new_red[c])
      for (int j = 0; j < 4; ++j) take[m.cell_face[c][j]] = 1;
  std::vector<std::int32_t> out;
  for (std::int32_t f = 0; f < m.num_faces(); ++f)
    if (take[f]) out.push_back(f);
  return out;
}

namespace {

struct FaceWork {
  int n = 0;
  bool reused = false;
  std::vector<std::uint16_t> codes;  // empty when every point is outside the hull (fresh faces)
};

// Point (i, j) of the lattice of (a, b, c) with n divisions.
inline Eigen::Vector3d lattice_point(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                                     int n, int i, int j) {
  return a + (static_cast<double>(i) / n) * (b - a) + (static_cast<double>(j) / n) * (c - a);
}

}  // namespace

std::int64_t best_point(const std::vector<std::uint16_t>& codes, int n, int radius) {
  // Window mean of the scores (samples only) around every consistent point.
  std::int64_t best = -1;
  double best_mean = -2;
  std::int64_t p = 0;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i + j <= n; ++i, ++p) {
      if (!code_is_consistent(codes[p])) continue;
      double sum = 0;
      int cnt = 0;
      for (int dj = -radius; dj <= radius; ++dj)
        for (int di = -radius; di <= radius; ++di) {
          const int ii = i + di, jj = j + dj;
          if (ii < 0 || jj < 0 || ii + jj > n || std::abs(di + dj) > radius) continue;
          const std::uint16_t c = codes[lattice_index(n, ii, jj)];
          if (!code_is_sample(c)) continue;
          sum += std::max(code_score(c), -1.f);
          ++cnt;
        }
      const double mean = sum / cnt;  // cnt >= 1: the point itself
      if (mean > best_mean) best_mean = mean, best = p;
    }
  return best;
}

LevelResult run_level(const LevelInput& in, const Options& opts) {
  require(in.mesh && in.views && in.hull, "photoconsist::run_level: missing mesh, views or hull");
  const tet::TetMesh& m = *in.mesh;
  const photo::Views& views = *in.views;
  const HullTest& hull = *in.hull;
  require(static_cast<std::int32_t>(m.cell_new_red.size()) == m.num_cells(),
          "photoconsist: the mesh has no cell_new_red flags");
  require(!in.prev || static_cast<std::int32_t>(m.face_parent.size()) == m.num_faces(),
          "photoconsist: the mesh has no face_parent map, so the cache cannot be used");

  LevelResult R;
  R.face = faces_of_new_cells(m);
  const std::int64_t T = static_cast<std::int64_t>(R.face.size());
  std::vector<FaceWork> work(T);
  R.divisions.assign(T, 0);
  R.samples.assign(T, 0);
  R.consistent.assign(T, 0);
  R.crossing.assign(T, 0);
  R.reused.assign(T, 0);
  R.best_score.assign(T, photo::kNoScore);
  std::vector<std::int64_t> scored(T, 0), best_index(T, -1), hidden_pts(T, 0), rescored(T, 0), hull_dropped(T, 0),
      hull_added(T, 0);
  const OcclusionMaps* occl = in.occl && !in.occl->empty() ? in.occl : nullptr;
  const OcclusionMaps* occl_prev = in.occl_prev && !in.occl_prev->empty() ? in.occl_prev : nullptr;
  require(!occl_prev || occl_prev->num_views() == views.size(), "photoconsist: previous occlusion maps of ",
          occl_prev ? occl_prev->num_views() : 0, " views for ", views.size(), " views");
  require(!occl || occl->num_views() == views.size(), "photoconsist: occlusion maps of ", occl ? occl->num_views() : 0,
          " views for ", views.size(), " views");

  Progress progress("photoconsist faces", in.progress ? T : 0);
#pragma omp parallel
  {
    photo::Scratch scratch;
    std::vector<std::int64_t> index;
    std::vector<std::uint8_t> mask(static_cast<std::size_t>(views.size()), 0), mask_prev(mask);
    // The code of lattice point X of face t (normal nf), scored without the views it is hidden in.
    const auto score_fresh = [&](const Eigen::Vector3d& X, const Eigen::Vector3d& nf, std::int64_t t) {
      scratch.hidden = nullptr;
      if (occl && occl->hidden_views(views, X, mask.data()) > 0) scratch.hidden = mask.data(), ++hidden_pts[t];
      const std::uint16_t code = encode_point(photo::score_point(views, X, nf, opts.line, scratch), opts.line);
      scratch.hidden = nullptr;
      return code;
    };
#pragma omp for schedule(dynamic, 16)
    for (std::int64_t t = 0; t < T; ++t) {
      const std::int32_t f = R.face[t];
      const auto fv = m.face_vertices(f);
      const Eigen::Vector3d a = m.vertex(fv[0]), b = m.vertex(fv[1]), c = m.vertex(fv[2]);
      const Eigen::Vector3d nf = (b - a).cross(c - a);
      const int need = photo::lattice_divisions(views, a, b, c, opts.lattice_px);
      FaceWork& w = work[t];
      // Reuse the previous level's lattice when this face is a cached face or a quarter of one.
      if (in.prev && m.face_parent[f] >= 0) {
        const std::int64_t e = in.prev->find(m.face_parent[f]);
        int cn = 0;
        if (e >= 0 && map_sub_lattice(in.prev->face_lat(e), in.prev->divisions[e], face_lat(m, f), &cn, index) &&
            cn >= need) {
          const std::uint16_t* pc = in.prev->codes_of(e);
          w.n = cn;
          w.reused = true;
          w.codes.resize(index.size());
          for (std::size_t p = 0; p < index.size(); ++p) w.codes[p] = pc[index[p]];
        }
      }
      // The cached codes were made with another hull (recheck_hull): apply this one.
      if (w.reused && in.recheck_hull) {
        const bool all_outside = hull.triangle_outside(a, b, c);
        std::int64_t p = 0;
        for (int j = 0; j <= w.n; ++j)
          for (int i = 0; i + j <= w.n; ++i, ++p) {
            const bool sample = code_is_sample(w.codes[p]);
            if (all_outside && !sample) continue;
            const Eigen::Vector3d X = lattice_point(a, b, c, w.n, i, j);
            const bool in_hull = !all_outside && hull.inside(X) && !hull.in_core(X);
            if (sample && !in_hull) {
              w.codes[p] = kCodeOutside;
              ++hull_dropped[t];
            } else if (!sample && in_hull) {
              w.codes[p] = score_fresh(X, nf, t);
              ++hull_added[t];
            }
          }
      }
      // A reused code was scored with the previous level's occluders (or none): score
      // again the points whose hidden views changed.
      if (w.reused && (occl || occl_prev)) {
        std::int64_t p = 0;
        for (int j = 0; j <= w.n; ++j)
          for (int i = 0; i + j <= w.n; ++i, ++p) {
            if (!code_is_sample(w.codes[p])) continue;
            const Eigen::Vector3d X = lattice_point(a, b, c, w.n, i, j);
            const int nh = occl ? occl->hidden_views(views, X, mask.data()) : 0;
            const int nh_prev = occl_prev ? occl_prev->hidden_views(views, X, mask_prev.data()) : 0;
            if (nh == 0 && nh_prev == 0) continue;
            if (nh == 0) std::fill(mask.begin(), mask.end(), 0);
            if (nh_prev == 0) std::fill(mask_prev.begin(), mask_prev.end(), 0);
            if (nh > 0) ++hidden_pts[t];
            if (mask == mask_prev) continue;
            scratch.hidden = nh > 0 ? mask.data() : nullptr;
            w.codes[p] = encode_point(photo::score_point(views, X, nf, opts.line, scratch), opts.line);
            scratch.hidden = nullptr;
            ++rescored[t];
          }
        scored[t] = rescored[t];
      }
      if (w.reused) scored[t] += hull_added[t];
      if (!w.reused) {
        const int n = reusable_divisions(need);
        w.n = n;
        std::int64_t p = 0, nscored = 0;
        const bool all_outside = hull.triangle_outside(a, b, c);
        for (int j = 0; j <= n && !all_outside; ++j)
          for (int i = 0; i + j <= n; ++i, ++p) {
            const Eigen::Vector3d X = lattice_point(a, b, c, n, i, j);
            if (!hull.inside(X) || hull.in_core(X)) continue;  // not a sample
            if (w.codes.empty()) w.codes.assign(static_cast<std::size_t>(lattice_size(n)), kCodeOutside);
            w.codes[p] = score_fresh(X, nf, t);
            ++nscored;
          }
        scored[t] = nscored;
      }
      // Counts and best point.
      std::int32_t ns = 0, nc = 0;
      std::uint16_t best = 0;
      for (std::size_t p = 0; p < w.codes.size(); ++p) {
        const std::uint16_t code = w.codes[p];
        ns += code_is_sample(code);
        nc += code_is_consistent(code);
        best = std::max(best, code);
      }
      R.divisions[t] = w.n;
      R.samples[t] = ns;
      R.consistent[t] = nc;
      R.reused[t] = w.reused;
      R.best_score[t] = best >= 2 ? code_score(best) : photo::kNoScore;
      R.crossing[t] = opts.rule.crossing(nc, ns);
      if (R.crossing[t]) best_index[t] = best_point(w.codes, w.n);
      progress.tick();
    }
  }
  progress.done();

  // Active cells.
  R.active.assign(m.num_cells(), 0);
  for (std::int64_t t = 0; t < T; ++t) {
    R.lattice_points += lattice_size(work[t].n);
    R.sample_points += R.samples[t];
    R.consistent_points += R.consistent[t];
    R.scored_points += scored[t];
    R.reused_faces += R.reused[t];
    R.hidden_points += hidden_pts[t];
    R.rescored_points += rescored[t];
    R.hull_dropped_points += hull_dropped[t];
    R.hull_added_points += hull_added[t];
    if (!R.crossing[t]) continue;
    ++R.crossing_faces;
    for (int k = 0; k < 2; ++k) {
      const std::int32_t c = m.face_cell(R.face[t], k);
      if (c >= 0) R.active[c] = 1;
    }
  }
  for (auto a : R.active) R.active_cells += a;

  // Q: the best point of each crossing face, scored again for its cameras and normal.
  std::vector<std::int64_t> cross;
  for (std::int64_t t = 0; t < T; ++t)
    if (R.crossing[t]) cross.push_back(t);
  std::vector<photo::PointResult> best(cross.size());
  std::vector<Eigen::Vector3d> bestX(cross.size());
#pragma omp parallel
  {
    photo::Scratch scratch;
    std::vector<std::uint8_t> mask(static_cast<std::size_t>(views.size()), 0);
#pragma omp for schedule(dynamic, 16)
    for (std::int64_t q = 0; q < static_cast<std::int64_t>(cross.size()); ++q) {
      const std::int64_t t = cross[q];
      const std::int32_t f = R.face[t];
      const auto fv = m.face_vertices(f);
      const Eigen::Vector3d a = m.vertex(fv[0]), b = m.vertex(fv[1]), c = m.vertex(fv[2]);
      const int n = work[t].n;
      // (i, j) of the best index.
      std::int64_t p = best_index[t];
      int j = 0;
      while (p > n - j) p -= n - j + 1, ++j;
      bestX[q] = lattice_point(a, b, c, n, static_cast<int>(p), j);
      scratch.hidden = occl && occl->hidden_views(views, bestX[q], mask.data()) > 0 ? mask.data() : nullptr;
      best[q] = photo::score_point(views, bestX[q], (b - a).cross(c - a), opts.line, scratch);
      scratch.hidden = nullptr;
    }
  }
  std::vector<std::int32_t> cams;
  for (std::size_t q = 0; q < cross.size(); ++q) {
    const photo::PointResult& r = best[q];
    if (!r.valid()) continue;  // cannot happen for a consistent point; never write an undefined point
    cams.assign(1, r.ref);
    for (int k = 0; k < r.num_partners; ++k) cams.push_back(r.partners[k]);
    R.points.add(bestX[q], r.normal(), r.score, cams, R.face[cross[q]]);
  }

  // Cache for the next level: faces of active cells whose lattice can be halved.
  R.cache.level = m.level;
  R.cache.lattice = lattice_key(m.lat);
  R.cache.signature = opts.cache_signature();
  std::vector<std::uint16_t> zeros;
  for (std::int64_t t = 0; t < T; ++t) {
    const std::int32_t f = R.face[t];
    const bool near_active = R.active[m.face_cell(f, 0)] || (m.face_cell(f, 1) >= 0 && R.active[m.face_cell(f, 1)]);
    if (!in.keep_all && !(near_active && work[t].n >= 2)) continue;
    const std::uint16_t* c = work[t].codes.data();
    if (work[t].codes.empty()) {
      zeros.assign(static_cast<std::size_t>(lattice_size(work[t].n)), kCodeOutside);
      c = zeros.data();
    }
    R.cache.append(f, face_lat(m, f), work[t].n, c);
  }
  return R;
}

}  // namespace tetmvs::photoconsist
