#include "common/silfix/silfix.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <unordered_map>

#include <opencv2/imgproc.hpp>

#include "common/error.h"
#include "common/silhouette/border.h"
#include "common/trimesh/raster.h"

namespace tetmvs::silfix {

void Options::check() const { check_param_ranges(*this); }

Options Options::from_params(const Params& p) {
  Options o;
  read_params(p, o);
  o.check();
  return o;
}

cv::Mat surface_mask(const TriMesh& surface, const Camera& cam) {
  const Raster r = rasterize(surface, cam, {});
  cv::Mat mask = r.tri >= 0;  // CV_8U 255 / 0
  return mask;
}

namespace {

// Convex hull of up to a few 2-D points (Andrew's monotone chain), counter-clockwise in
// (x, y); duplicates collapse, so 1 or 2 points are returned for degenerate input.
std::vector<Eigen::Vector2d> convex_hull(std::vector<Eigen::Vector2d> p) {
  std::sort(p.begin(), p.end(), [](const auto& a, const auto& b) { return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y()); });
  p.erase(std::unique(p.begin(), p.end()), p.end());
  if (p.size() < 3) return p;
  auto cross = [](const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
  };
  std::vector<Eigen::Vector2d> h(2 * p.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  for (std::size_t i = p.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  h.resize(k - 1);
  return h;
}

double dist_to_segment(const Eigen::Vector2d& q, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double l2 = ab.squaredNorm();
  const double t = l2 > 0 ? std::clamp((q - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
  return (a + t * ab - q).norm();
}

// Distance from q to a convex polygon (0 inside). hull is counter-clockwise.
double dist_to_hull(const Eigen::Vector2d& q, const std::vector<Eigen::Vector2d>& h) {
  if (h.size() == 1) return (q - h[0]).norm();
  if (h.size() == 2) return dist_to_segment(q, h[0], h[1]);
  bool inside = true;
  double d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < h.size(); ++i) {
    const Eigen::Vector2d& a = h[i];
    const Eigen::Vector2d& b = h[(i + 1) % h.size()];
    const double c = (b.x() - a.x()) * (q.y() - a.y()) - (b.y() - a.y()) * (q.x() - a.x());
    if (c < 0) inside = false;
    d = std::min(d, dist_to_segment(q, a, b));
  }
  return inside ? 0.0 : d;
}

// True when X projects inside every silhouette of the scene it falls in (views where it
// is behind the camera or outside the image do not count).
bool in_all_silhouettes(const Scene& s, const Eigen::Vector3d& X) {
  for (int v = 0; v < s.size(); ++v) {
    if (!s.has_silhouette(v)) continue;
    const Camera& cam = s.cams[v];
    if (cam.depth(X) <= 0) continue;
    const Eigen::Vector2d p = cam.project(X);
    if (!s.in_silhouette(v, p.x(), p.y(), true)) return false;
  }
  return true;
}

void cell_corners(const tet::TetMesh& m, std::int32_t c, Eigen::Vector3d X[4]) {
  for (int k = 0; k < 4; ++k) X[k] = m.vertex(m.cell_v[c][k]);
}

struct PixelCand {
  float dist;
  std::int32_t x, y;
};

struct ViewWork {
  ViewStats st;
  std::vector<Constraint> ext, intr;
};

}  // namespace

bool projection_clear_of_mask(const Camera& cam, const cv::Mat& mask, const Eigen::Vector3d* X, int n,
                              double pad_px) {
  std::vector<Eigen::Vector2d> p(n);
  for (int k = 0; k < n; ++k) {
    if (!(cam.depth(X[k]) > 0)) return false;
    p[k] = cam.project(X[k]);
    if (!p[k].allFinite()) return false;
  }
  const auto h = convex_hull(p);
  Eigen::Vector2d lo = h[0], hi = h[0];
  for (const auto& q : h) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
  lo.array() -= pad_px;
  hi.array() += pad_px;
  if (lo.x() < 0 || lo.y() < 0 || hi.x() > mask.cols - 1 || hi.y() > mask.rows - 1) return false;
  const int x0 = static_cast<int>(std::ceil(lo.x())), x1 = static_cast<int>(std::floor(hi.x()));
  const int y0 = static_cast<int>(std::ceil(lo.y())), y1 = static_cast<int>(std::floor(hi.y()));
  for (int y = y0; y <= y1; ++y) {
    const std::uint8_t* row = mask.ptr<std::uint8_t>(y);
    for (int x = x0; x <= x1; ++x)
      if (row[x] && dist_to_hull(Eigen::Vector2d(x, y), h) <= pad_px) return false;
  }
  return true;
}

int interior_hit_on_ray(const tet::TetMesh& m, const std::vector<float>& omega,
                        const std::vector<tet::WalkHit>& hits, const std::vector<std::uint8_t>& outside,
                        const Options& o, RayPeaks& pk) {
  pk = RayPeaks{};
  const int n = static_cast<int>(hits.size());
  int segments = 0, a = -1, b = -1;
  for (int i = 0; i < n; ++i) {
    if (outside[i]) continue;
    // Continues the current segment when the walk is unbroken from its last inside cell b
    // and at most max_gap_cells outside cells lie in between.
    bool cont = b >= 0 && i - b - 1 <= o.max_gap_cells;
    for (int j = b + 1; cont && j <= i; ++j)
      cont = hits[j].face_in >= 0 && hits[j].face_in == hits[j - 1].face_out;
    if (!cont) {
      ++segments;
      a = i;
    }
    b = i;
  }
  if (segments == 0) return pk.status = 1, -1;
  if (segments > 1) return pk.status = 2, -1;
  struct Crossing {
    double t;
    float front, back;
  };
  std::vector<Crossing> xs;
  // behind: the cell on the far side of face f (seen from the camera); front-facing means
  // the normal points from it toward the camera.
  auto add = [&](std::int32_t f, std::int32_t behind, std::int32_t in_front, double t) {
    const bool first_is_behind = behind >= 0 ? m.face_cell(f, 0) == behind : m.face_cell(f, 0) != in_front;
    const float fr = omega[2 * static_cast<std::size_t>(f) + (first_is_behind ? 0 : 1)];
    const float bk = omega[2 * static_cast<std::size_t>(f) + (first_is_behind ? 1 : 0)];
    xs.push_back({t, fr, bk});
  };
  for (int i = a; i <= b; ++i)
    if (hits[i].face_in >= 0) add(hits[i].face_in, hits[i].cell, -1, hits[i].t_in);
  if (hits[b].face_out >= 0) add(hits[b].face_out, -1, hits[b].cell, hits[b].t_out);
  if (xs.empty()) return pk.status = 3, -1;
  std::size_t fi = 0;
  for (std::size_t i = 1; i < xs.size(); ++i)
    if (xs[i].front > xs[fi].front) fi = i;
  if (xs[fi].front < o.min_peak) return pk.status = 3, -1;
  float best_back = -1;
  for (std::size_t j = fi + 1; j < xs.size(); ++j) best_back = std::max(best_back, xs[j].back);
  if (best_back < o.min_peak) return pk.status = 3, -1;
  std::size_t bj = fi + 1;
  while (xs[bj].back < o.peak_ratio * best_back) ++bj;
  pk.omega_front = xs[fi].front;
  pk.omega_back = xs[bj].back;
  pk.t_front = xs[fi].t;
  pk.t_back = xs[bj].t;
  const double tm = 0.5 * (pk.t_front + pk.t_back);
  for (int i = a; i <= b; ++i)
    if (hits[i].t_in <= tm && (tm < hits[i].t_out || i == b)) return i;
  return pk.status = 3, -1;  // not reached: the interval lies inside the segment
}

Result fix_silhouettes(const tet::TetMesh& m, const Scene& s, const TriMesh& s1, const std::vector<float>& omega,
                       const std::vector<std::int8_t>& label, const std::vector<std::uint8_t>& reason,
                       const Options& o) {
  o.check();
  const std::int32_t C = m.num_cells();
  require(static_cast<std::int64_t>(omega.size()) == 2 * static_cast<std::int64_t>(m.num_faces()),
          "silhouette-fix: omega needs 2 values per face (", 2 * static_cast<std::int64_t>(m.num_faces()), "), got ",
          omega.size());
  require(static_cast<std::int32_t>(label.size()) == C && static_cast<std::int32_t>(reason.size()) == C,
          "silhouette-fix: labels and reasons need one value per cell (", C, ")");
  require(s.num_silhouettes() > 0, "silhouette-fix: the scene has no silhouettes");

  for (int v = 0; v < s.size(); ++v)
    if (s.has_silhouette(v))
      require(s.sil[v].type() == CV_8U && s.sil[v].rows == s.cams[v].height && s.sil[v].cols == s.cams[v].width,
              "silhouette-fix: the silhouette of view ", v, " is not a CV_8U mask of its camera's size");

  Result res;
  res.s1_masks.assign(s.size(), cv::Mat());
  std::vector<ViewWork> work(s.size());

  std::vector<std::string> errors(s.size());  // exceptions must not leave the parallel loop
#pragma omp parallel for schedule(dynamic, 1)
  for (int v = 0; v < s.size(); ++v) {
    if (!s.has_silhouette(v)) continue;
    try {
      const Camera& cam = s.cams[v];
      const cv::Mat& truth = s.sil[v];
      ViewWork& w = work[v];
      w.st.view = v;
      const cv::Mat mine = surface_mask(s1, cam);
      res.s1_masks[v] = mine;
      // distances to the outline, which the image border is not (common/silhouette/border.h)
      const cv::Mat dist_in = silhouette::distance_inside(truth), dist_out = silhouette::distance_outside(truth);
      cv::Mat too_big(truth.size(), CV_8U, cv::Scalar(0)), too_small(truth.size(), CV_8U, cv::Scalar(0));
      std::int64_t inter = 0, uni = 0;
      for (int y = 0; y < truth.rows; ++y)
        for (int x = 0; x < truth.cols; ++x) {
          const bool t = truth.at<std::uint8_t>(y, x) != 0, s1in = mine.at<std::uint8_t>(y, x) != 0;
          w.st.true_px += t;
          w.st.s1_px += s1in;
          inter += t && s1in;
          uni += t || s1in;
          if (s1in && !t && dist_out.at<float>(y, x) >= o.margin_px) {
            too_big.at<std::uint8_t>(y, x) = 255;
            ++w.st.too_big_px;
          }
          if (t && !s1in && dist_in.at<float>(y, x) >= o.margin_px) {
            too_small.at<std::uint8_t>(y, x) = 255;
            ++w.st.too_small_px;
          }
        }
      w.st.iou = uni > 0 ? static_cast<double>(inter) / uni : 1.0;
      const Eigen::Vector3d centre = cam.centre();
      std::vector<tet::WalkHit> hits;

      // S1 too big: cells on the ray that are provably outside become exterior.
      if (o.exterior && w.st.too_big_px > 0) {
        std::unordered_map<std::int32_t, bool> seen;
        for (int y = 0; y < truth.rows; ++y)
          for (int x = 0; x < truth.cols; ++x) {
            if (!too_big.at<std::uint8_t>(y, x)) continue;
            tet::walk_ray(m, centre, cam.ray_direction(x, y), hits);
            ++w.st.exterior_rays;
            for (const auto& h : hits) {
              const std::int32_t c = h.cell;
              if (label[c] < 0 || seen.count(c)) continue;
              Eigen::Vector3d X[4];
              cell_corners(m, c, X);
              const bool clear = projection_clear_of_mask(cam, truth, X, 4, o.pad_px);
              seen.emplace(c, clear);
              if (!clear) {
                w.st.straddling += label[c] == 0;
                continue;
              }
              Constraint k;
              k.view = v, k.u = x, k.v = y, k.cell = c, k.kind = kExteriorKind, k.why = kWhyOutsideSilhouette;
              w.ext.push_back(k);
            }
          }
      }

      // S1 too small: a few sure interior cells per connected region.
      if (o.interior && w.st.too_small_px > 0) {
        cv::Mat comp, stats, cents;
        const int ncomp = cv::connectedComponentsWithStats(too_small, comp, stats, cents, 8, CV_32S);
        std::vector<std::vector<PixelCand>> regions(ncomp);
        for (int y = 0; y < comp.rows; ++y)
          for (int x = 0; x < comp.cols; ++x) {
            const int r = comp.at<std::int32_t>(y, x);
            if (r > 0) regions[r].push_back({dist_in.at<float>(y, x), x, y});
          }
        std::unordered_map<std::int32_t, std::uint8_t> outside_cache;
        auto cell_outside = [&](std::int32_t c) -> std::uint8_t {
          if (reason[c] == kBoundary || reason[c] == kOutsideHull) return 1;
          auto it = outside_cache.find(c);
          if (it != outside_cache.end()) return it->second;
          const std::uint8_t out = !in_all_silhouettes(s, m.cell_centroid(c));
          outside_cache.emplace(c, out);
          return out;
        };
        const double sp2 = o.spacing_px * o.spacing_px;
        const int max_attempts = 20 * o.max_per_region;
        std::vector<std::uint8_t> outside;
        std::vector<double> mind;
        for (int r = 1; r < ncomp; ++r) {
          const auto& px = regions[r];
          if (static_cast<int>(px.size()) < o.min_region_px) continue;
          ++w.st.small_regions;
          // Farthest-point order: first the pixel deepest inside the true silhouette, then
          // each time the pixel farthest from all tried ones (ties: deeper, then raster
          // order), so a few samples spread over the whole region (a horn's base and tip).
          mind.assign(px.size(), std::numeric_limits<double>::infinity());
          int added = 0, attempts = 0;
          while (added < o.max_per_region && attempts < max_attempts) {
            std::size_t best = 0;
            for (std::size_t i = 1; i < px.size(); ++i)
              if (mind[i] > mind[best] || (mind[i] == mind[best] && px[i].dist > px[best].dist)) best = i;
            if (mind[best] < sp2 || mind[best] == 0) break;  // every pixel is near a tried one
            const PixelCand p = px[best];
            for (std::size_t i = 0; i < px.size(); ++i) {
              const double dx = px[i].x - p.x, dy = px[i].y - p.y;
              mind[i] = std::min(mind[i], dx * dx + dy * dy);
            }
            ++attempts;
            const Eigen::Vector3d dir = cam.ray_direction(p.x, p.y);
            tet::walk_ray(m, centre, dir, hits);
            ++w.st.interior_rays;
            outside.resize(hits.size());
            for (std::size_t i = 0; i < hits.size(); ++i) outside[i] = cell_outside(hits[i].cell);
            RayPeaks pk;
            const int k = interior_hit_on_ray(m, omega, hits, outside, o, pk);
            if (k < 0) {
              if (pk.status == 1) ++w.st.no_segment;
              else if (pk.status == 2) ++w.st.multi_segment;
              else ++w.st.weak_peaks;
              continue;
            }
            // The interval's middle cell if its four corners project inside every
            // silhouette; else, with search_interval, the nearest hit to it (ties: nearer
            // the camera) that overlaps the interval, is inside the hull and passes that
            // corner test. (The corner test also rejects a middle cell that fell in a gap
            // joined by max_gap_cells.)
            auto corners_in = [&](std::int32_t c) {
              Eigen::Vector3d X[4];
              cell_corners(m, c, X);
              for (int j = 0; j < 4; ++j)
                if (!in_all_silhouettes(s, X[j])) return false;
              return true;
            };
            std::int32_t c = corners_in(hits[k].cell) ? hits[k].cell : -1;
            const int nh = static_cast<int>(hits.size());
            for (int d = 1; c < 0 && o.search_interval && d < nh; ++d)
              for (const int i : {k - d, k + d})
                if (c < 0 && i >= 0 && i < nh && !outside[i] && hits[i].t_out > pk.t_front &&
                    hits[i].t_in < pk.t_back && corners_in(hits[i].cell))
                  c = hits[i].cell;
            if (c < 0) {
              ++w.st.corner_outside;
              continue;
            }
            Constraint kc;
            kc.view = v, kc.u = p.x, kc.v = p.y, kc.cell = c, kc.kind = kInteriorKind, kc.why = kWhyPeakInterval;
            kc.omega_front = pk.omega_front, kc.omega_back = pk.omega_back;
            kc.depth_front = static_cast<float>(pk.t_front), kc.depth_back = static_cast<float>(pk.t_back);
            w.intr.push_back(kc);
            ++added;
          }
        }
      }
    } catch (const std::exception& e) {
      errors[v] = e.what();
    }
  }
  for (const auto& e : errors)
    if (!e.empty()) fail(e);

  // Merge in view order: exterior first, then interior; never overturn a hard label.
  res.label = label;
  res.reason = reason;
  std::vector<int> view_slot(s.size(), -1);
  for (int v = 0; v < s.size(); ++v)
    if (s.has_silhouette(v)) {
      view_slot[v] = static_cast<int>(res.views.size());
      res.views.push_back(work[v].st);
    }
  for (int v = 0; v < s.size(); ++v)
    for (const auto& k : work[v].ext) {
      ViewStats& st = res.views[view_slot[v]];
      if (res.label[k.cell] == 0) {
        res.label[k.cell] = -1;
        res.reason[k.cell] = kSilfixExterior;
        res.constraints.push_back(k);
        ++st.exterior_added;
      } else if (res.label[k.cell] > 0) {
        ++st.conflicts;
      }
    }
  for (int v = 0; v < s.size(); ++v)
    for (const auto& k : work[v].intr) {
      ViewStats& st = res.views[view_slot[v]];
      if (res.label[k.cell] == 0) {
        res.label[k.cell] = 1;
        res.reason[k.cell] = kSilfixInterior;
        res.constraints.push_back(k);
        ++st.interior_added;
      } else if (res.label[k.cell] > 0) {
        ++st.already;
      } else {
        ++st.conflicts;
      }
    }
  double iou = 0;
  for (const auto& st : res.views) {
    res.exterior_added += st.exterior_added;
    res.interior_added += st.interior_added;
    res.conflicts += st.conflicts;
    res.already += st.already;
    iou += st.iou;
  }
  res.mean_iou = res.views.empty() ? 0.0 : iou / res.views.size();
  return res;
}

}  // namespace tetmvs::silfix
