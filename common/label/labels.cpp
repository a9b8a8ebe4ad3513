#include "common/label/labels.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <unordered_map>

#include "common/error.h"
#include "common/log.h"
#include "common/tetmesh/locate.h"

namespace tetmvs::label {

std::vector<std::int32_t> group_sizes(const tet::TetMesh& m, const std::vector<std::uint8_t>& in) {
  const std::int32_t C = m.num_cells();
  require(static_cast<std::int64_t>(in.size()) == C, "group_sizes: ", in.size(), " flags for ", C, " cells");
  std::vector<std::int32_t> parent(C);
  for (std::int32_t c = 0; c < C; ++c) parent[c] = c;
  const auto find = [&](std::int32_t c) {
    while (parent[c] != c) c = parent[c] = parent[parent[c]];
    return c;
  };
  for (std::int32_t f = 0; f < m.num_faces(); ++f) {  // union by the smaller root: deterministic
    const std::int32_t a = m.face_cell(f, 0), b = m.face_cell(f, 1);
    if (b < 0 || !in[a] || !in[b]) continue;
    const std::int32_t ra = find(a), rb = find(b);
    if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
  }
  std::vector<std::int32_t> size(C, 0);
  for (std::int32_t c = 0; c < C; ++c)
    if (in[c]) ++size[find(c)];
  std::vector<std::int32_t> out(C, 0);
  for (std::int32_t c = 0; c < C; ++c)
    if (in[c]) out[c] = size[find(c)];
  return out;
}

std::vector<std::uint8_t> small_groups(const tet::TetMesh& m, const std::vector<std::uint8_t>& in, double share) {
  const auto size = group_sizes(m, in);
  const std::int32_t largest = size.empty() ? 0 : *std::max_element(size.begin(), size.end());
  std::vector<std::uint8_t> small(size.size(), 0);
  for (std::size_t c = 0; c < size.size(); ++c) small[c] = in[c] && size[c] < share * largest;
  return small;
}

std::vector<std::uint8_t> outside_visual_hull(const tet::TetMesh& m, const Scene& s) {
  const std::int32_t C = m.num_cells();
  std::vector<std::uint8_t> out(C, 0);
  // distance (pixels) from each pixel to the nearest silhouette pixel
  std::vector<cv::Mat> dist(s.size());
  for (int v = 0; v < s.size(); ++v) {
    if (!s.has_silhouette(v)) continue;
    cv::Mat bg = s.sil[v] == 0;
    cv::distanceTransform(bg, dist[v], cv::DIST_L2, cv::DIST_MASK_PRECISE);
  }
#pragma omp parallel for schedule(dynamic, 1024)
  for (std::int32_t c = 0; c < C; ++c) {
    Eigen::Vector3d X[4];
    for (int k = 0; k < 4; ++k) X[k] = m.vertex(m.cell_v[c][k]);
    for (int v = 0; v < s.size() && !out[c]; ++v) {
      if (dist[v].empty()) continue;
      const Camera& cam = s.cams[v];
      Eigen::Vector2d p[4], centre = Eigen::Vector2d::Zero();
      bool front = true;
      for (int k = 0; k < 4; ++k) {
        front = front && cam.depth(X[k]) > 0;
        p[k] = cam.project(X[k]);
        centre += p[k] / 4.0;
      }
      if (!front) continue;
      double r = 0;
      for (int k = 0; k < 4; ++k) r = std::max(r, (p[k] - centre).norm());
      r += 1.5;  // pixel rounding of the silhouette and of the distance transform
      if (centre.x() - r < 0 || centre.y() - r < 0 || centre.x() + r > cam.width - 1 ||
          centre.y() + r > cam.height - 1)
        continue;  // partly outside the image: never carves
      const int u = static_cast<int>(std::lround(centre.x())), w = static_cast<int>(std::lround(centre.y()));
      if (dist[v].at<float>(w, u) > r + 0.75) out[c] = 1;
    }
  }
  return out;
}

std::vector<std::int32_t> visibility_votes(const tet::TetMesh& m, const Scene& s, const QPoints& q,
                                           double offset, std::int64_t* rays) {
  std::vector<std::int32_t> votes(m.num_cells(), 0);
  const std::int64_t P = q.size();
  std::int64_t nrays = 0;
  Progress prog("label: votes", P);
#pragma omp parallel reduction(+ : nrays)
  {
    std::vector<tet::WalkHit> hits;
#pragma omp for schedule(dynamic, 256)
    for (std::int64_t p = 0; p < P; ++p) {
      const Eigen::Vector3d X = q.pos(p);
      for (std::int64_t k = q.cam_offsets[p]; k < q.cam_offsets[p + 1]; ++k) {
        const Eigen::Vector3d dir = (s.cams[q.cams[k]].centre() - X).normalized();
        tet::walk_ray(m, X + offset * dir, dir, hits);
        for (const auto& h : hits) {
#pragma omp atomic
          ++votes[h.cell];
        }
        ++nrays;
      }
      prog.tick();
    }
  }
  prog.done();
  if (rays) *rays = nrays;
  return votes;
}

namespace {

// X's depth z in cam and the pixel (u, w) nearest to its projection; false when X is not in
// front of the camera or the pixel lies outside the image.
bool nearest_pixel(const Camera& cam, const Eigen::Vector3d& X, double& z, int& u, int& w) {
  z = cam.depth(X);
  if (z <= 0) return false;
  const Eigen::Vector2d p = cam.project(X);
  u = static_cast<int>(std::lround(p.x()));
  w = static_cast<int>(std::lround(p.y()));
  return u >= 0 && w >= 0 && u < cam.width && w < cam.height;
}

// Per-view depth maps of Q, splatted over a disc of about one finest cell: `front` holds
// the smallest depth of the points photo-consistent in that view (the visible surface),
// `back` the largest depth of the points facing away from the view (the far side of the
// object, seen by other cameras). 0 = no point there.
// `near` / `far` are `front` / `back` taken to their extreme over a window of about one
// finest cell: the free-space and beyond tests use them, so a gap between the splats of
// Q (a crossing face without a point) never lets a cell behind the surface pass for free
// space seen through the gap.
struct DepthMaps {
  std::vector<cv::Mat> front, back, near, far;
  // Only with_exits (the seen-free-space rule): `exit`, the nearest point of Q facing away
  // from the view at least 2 finest cells behind `front` (where the ray leaves the matter it
  // met), and `entry`, the nearest point facing the view at least 2 cells behind that exit
  // (where it meets matter again). 0 = none.
  std::vector<cv::Mat> exit, entry;
};

// Whether some point of a set lies within `radius` of X: a hash grid of bucket size radius.
class PointProximity {
 public:
  PointProximity(std::vector<Eigen::Vector3d> pts, double radius) : pts_(std::move(pts)), r_(radius) {
    for (std::size_t p = 0; p < pts_.size(); ++p) buckets_[key(pts_[p])].push_back(p);
  }
  bool any_within(const Eigen::Vector3d& X) const {
    const Eigen::Vector3d b = (X / r_).array().floor();
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = buckets_.find(pack(b + Eigen::Vector3d(dx, dy, dz)));
          if (it == buckets_.end()) continue;
          for (std::size_t p : it->second)
            if ((pts_[p] - X).squaredNorm() <= r_ * r_) return true;
        }
    return false;
  }

 private:
  static std::int64_t pack(const Eigen::Vector3d& b) {
    const auto f = [](double v) { return static_cast<std::int64_t>(v) & 0x1FFFFF; };
    return f(b.x()) | (f(b.y()) << 21) | (f(b.z()) << 42);
  }
  std::int64_t key(const Eigen::Vector3d& X) const { return pack((X / r_).array().floor()); }
  std::vector<Eigen::Vector3d> pts_;
  double r_;
  std::unordered_map<std::int64_t, std::vector<std::size_t>> buckets_;
};

std::vector<Eigen::Vector3d> positions(const QPoints& q) {
  std::vector<Eigen::Vector3d> out(q.size());
  for (std::int64_t p = 0; p < q.size(); ++p) out[p] = q.pos(p);
  return out;
}

// Radius in pixels of a window of `cells` finest cells at the mean depth of Q in the view
// (at least 1 pixel).
int window_radius(const Camera& cam, const QPoints& q, double cell, double cells) {
  double zc = 0;
  for (std::int64_t p = 0; p < q.size(); ++p) zc += cam.depth(q.pos(p));
  zc = q.size() ? zc / q.size() : 1.0;
  return std::max(1, static_cast<int>(std::ceil(cells * cell * cam.focal() / std::max(zc, 1e-12))));
}

// The nearest depth of `front` within a disc of radius wr around each pixel (0: none).
cv::Mat nearest_in_window(const cv::Mat& front, int wr) {
  const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * wr + 1, 2 * wr + 1));
  cv::Mat f_inf = front.clone();
  f_inf.setTo(std::numeric_limits<float>::max(), front == 0);
  cv::Mat nearm;
  cv::erode(f_inf, nearm, kernel, cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(std::numeric_limits<float>::max()));
  nearm.setTo(0, nearm == std::numeric_limits<float>::max());
  return nearm;
}

// Calls f(u, w) for every pixel of the disc (one finest cell at the point's depth, at least
// one pixel) that point X at depth z > 0 covers in the image.
template <class F>
void for_splat(const Camera& cam, const Eigen::Vector3d& X, double z, double cell, F&& f) {
  const Eigen::Vector2d px = cam.project(X);
  const int r = std::max(1, static_cast<int>(std::ceil(cell * cam.focal() / z)));
  const int u0 = static_cast<int>(std::lround(px.x())), w0 = static_cast<int>(std::lround(px.y()));
  for (int w = w0 - r; w <= w0 + r; ++w)
    for (int u = u0 - r; u <= u0 + r; ++u)
      if (u >= 0 && w >= 0 && u < cam.width && w < cam.height && (u - u0) * (u - u0) + (w - w0) * (w - w0) <= r * r)
        f(u, w);
}

DepthMaps q_depth_maps(const Scene& s, const QPoints& q, double cell, bool with_exits = false) {
  DepthMaps d;
  d.front.resize(s.size());
  d.back.resize(s.size());
  d.near.resize(s.size());
  d.far.resize(s.size());
  if (with_exits) {
    d.exit.resize(s.size());
    d.entry.resize(s.size());
  }
  const auto keep_nearest = [](cv::Mat& m, int u, int w, double z) {
    float& cur = m.at<float>(w, u);
    if (cur == 0 || z < cur) cur = static_cast<float>(z);
  };
#pragma omp parallel for schedule(dynamic, 1)
  for (int v = 0; v < s.size(); ++v) {
    const Camera& cam = s.cams[v];
    cv::Mat front = cv::Mat::zeros(cam.height, cam.width, CV_32F);
    cv::Mat back = cv::Mat::zeros(cam.height, cam.width, CV_32F);
    const Eigen::Vector3d C = cam.centre();
    for (std::int64_t p = 0; p < q.size(); ++p) {
      const Eigen::Vector3d X = q.pos(p);
      bool consistent = false;
      for (std::int64_t k = q.cam_offsets[p]; k < q.cam_offsets[p + 1] && !consistent; ++k)
        consistent = q.cams[k] == v;
      const bool facing_away = q.nrm(p).dot(C - X) < 0;
      if (!consistent && !facing_away) continue;
      const double z = cam.depth(X);
      if (z <= 0) continue;
      for_splat(cam, X, z, cell, [&](int u, int w) {
        if (consistent) keep_nearest(front, u, w, z);
        if (facing_away) {
          float& cur = back.at<float>(w, u);
          if (z > cur) cur = static_cast<float>(z);
        }
      });
    }
    if (with_exits) {
      // exit: the nearest point facing away from the view at least 2 cells behind the visible
      // side; entry: the nearest point facing the view at least 2 cells behind that exit
      cv::Mat exit = cv::Mat::zeros(cam.height, cam.width, CV_32F);
      cv::Mat entry = cv::Mat::zeros(cam.height, cam.width, CV_32F);
      for (const bool exits : {true, false})
        for (std::int64_t p = 0; p < q.size(); ++p) {
          const Eigen::Vector3d X = q.pos(p);
          const double facing = q.nrm(p).dot(C - X);
          if (exits ? facing >= 0 : facing <= 0) continue;
          const double z = cam.depth(X);
          if (z <= 0) continue;
          const cv::Mat& before = exits ? front : exit;
          for_splat(cam, X, z, cell, [&](int u, int w) {
            const float b = before.at<float>(w, u);
            if (b != 0 && z >= b + 2 * cell) keep_nearest(exits ? exit : entry, u, w, z);
          });
        }
      d.exit[v] = exit;
      d.entry[v] = entry;
    }
    d.front[v] = front;
    d.back[v] = back;
    // window: one finest cell at the depth of the scene's centre (at least 3x3 pixels)
    const int wr = window_radius(cam, q, cell, 1.0);
    const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * wr + 1, 2 * wr + 1));
    cv::Mat farm;
    cv::dilate(back, farm, kernel, cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
    d.near[v] = nearest_in_window(front, wr);
    d.far[v] = farm;
  }
  return d;
}

// The points of q whose drop flag is 0, in order.
QPoints keep_points(const QPoints& q, const std::vector<std::uint8_t>& drop) {
  QPoints out;
  for (std::int64_t p = 0; p < q.size(); ++p) {
    if (drop[p]) continue;
    const std::vector<std::int32_t> cams(q.cams.begin() + q.cam_offsets[p], q.cams.begin() + q.cam_offsets[p + 1]);
    out.add(q.pos(p), q.nrm(p), q.score[p], cams, q.face[p]);
  }
  return out;
}

// Points of q that lie in free space seen by other points: in at least `views_needed` views
// the point is in front of q's visible side (the `near` map, by `margin`). A point on the
// surface is never in front of what a camera sees there; a false match floating in the air
// (in a cup's cavity, "consistent" in views that really see the outer wall) is, in the views
// that see past it. The point's own splat is only in the views it is consistent in, where it
// can never be in front of itself.
QPoints drop_points_in_free_space(const Scene& s, const QPoints& q, const DepthMaps& d, double margin, int views_needed,
                                  std::int64_t* dropped) {
  const std::int64_t P = q.size();
  std::vector<std::uint8_t> drop(P, 0);
#pragma omp parallel for schedule(dynamic, 1024)
  for (std::int64_t p = 0; p < P; ++p) {
    const Eigen::Vector3d X = q.pos(p);
    int free_space = 0;
    for (int v = 0; v < s.size() && free_space < views_needed; ++v) {
      double z;
      int u, w;
      if (!nearest_pixel(s.cams[v], X, z, u, w)) continue;
      const float dn = d.near[v].at<float>(w, u);
      free_space += dn != 0 && z < dn - margin;
    }
    drop[p] = free_space >= views_needed;
  }
  if (dropped) *dropped = std::count(drop.begin(), drop.end(), std::uint8_t{1});
  return keep_points(q, drop);
}

// Per view, the per-pixel `quantile` (0 the nearest, 0.5 the median, 1 the farthest) of the
// depths of the splats (radius about `cell`) of the points of q photo-consistent in it; 0
// where fewer than 3 splats cover the pixel.
std::vector<cv::Mat> quantile_depth_maps(const Scene& s, const QPoints& q, double cell, double quantile) {
  const std::int64_t P = q.size();
  std::vector<cv::Mat> out(s.size());
#pragma omp parallel for schedule(dynamic, 1)
  for (int v = 0; v < s.size(); ++v) {
    const Camera& cam = s.cams[v];
    std::vector<std::pair<std::int32_t, float>> splat;  // (pixel, depth)
    for (std::int64_t p = 0; p < P; ++p) {
      bool consistent = false;
      for (std::int64_t k = q.cam_offsets[p]; k < q.cam_offsets[p + 1] && !consistent; ++k) consistent = q.cams[k] == v;
      double z;
      int u0, w0;
      if (!consistent || !nearest_pixel(cam, q.pos(p), z, u0, w0)) continue;
      const int r = std::max(1, static_cast<int>(std::lround(cell * cam.focal() / z)));
      for (int w = std::max(0, w0 - r); w <= std::min(cam.height - 1, w0 + r); ++w)
        for (int u = std::max(0, u0 - r); u <= std::min(cam.width - 1, u0 + r); ++u)
          if ((u - u0) * (u - u0) + (w - w0) * (w - w0) <= r * r) splat.emplace_back(w * cam.width + u, static_cast<float>(z));
    }
    std::sort(splat.begin(), splat.end());
    cv::Mat out_v = cv::Mat::zeros(cam.height, cam.width, CV_32F);
    for (std::size_t i = 0; i < splat.size();) {
      std::size_t j = i;
      while (j < splat.size() && splat[j].first == splat[i].first) ++j;
      if (j - i >= 3) {
        const auto k = static_cast<std::size_t>(std::floor(quantile * static_cast<double>(j - i - 1)));
        out_v.at<float>(splat[i].first / cam.width, splat[i].first % cam.width) = splat[i + k].second;
      }
      i = j;
    }
    out[v] = out_v;
  }
  return out;
}

std::vector<cv::Mat> median_depth_maps(const Scene& s, const QPoints& q, double cell) {
  return quantile_depth_maps(s, q, cell, 0.5);
}

}  // namespace

// Points of q in front of Q's per-pixel depth `quantile` (quantile_depth_maps) by `margin`
// in at least `views_needed` views and in at least `share` of the views where that depth
// exists at the point's pixel; no test where a view has none.
// Median, no share (Options::median_free_views, scenes without silhouettes): where false
// matches crowd in front of the surface (near occluding contours), the window minimum of
// drop_points_in_free_space is one of them; the median is still the surface as long as most
// points there lie on it.
// Lower quartile and a share (Options::quantile_free_views, scenes with silhouettes): the
// photo-consistency band in front of a surface that the hull does not bound (a cup's far
// inner wall) reaches several cells into the air; those points are in front of Q's depth in
// most of the views that see the surface. A true point is in front of it only where points
// hidden behind the surface (scored with views that do not see them: camera selection has
// no occlusion test) push the depth back, near occluding contours, in a few views.
std::vector<std::uint8_t> in_front_of_quantile(const Scene& s, const QPoints& q, double cell, double margin,
                                               double quantile, int views_needed, double share) {
  const std::int64_t P = q.size();
  const auto depth = quantile_depth_maps(s, q, cell, quantile);
  std::vector<std::uint8_t> drop(P, 0);
#pragma omp parallel for schedule(dynamic, 1024)
  for (std::int64_t p = 0; p < P; ++p) {
    int in_front = 0, with_depth = 0;
    for (int v = 0; v < s.size() && (share > 0 || in_front < views_needed); ++v) {
      double z;
      int u, w;
      if (!nearest_pixel(s.cams[v], q.pos(p), z, u, w)) continue;
      const float d = depth[v].at<float>(w, u);
      in_front += d != 0 && z < d - margin;
      with_depth += d != 0;
    }
    drop[p] = in_front >= views_needed && in_front >= share * with_depth;
  }
  return drop;
}

namespace {

double percentile(std::vector<std::int32_t> v, double pct) {
  if (v.empty()) return 0;
  const std::size_t k = std::min(v.size() - 1, static_cast<std::size_t>(std::floor(pct / 100.0 * (v.size() - 1) + 0.5)));
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[k];
}

}  // namespace

namespace {
// Pixels to the nearest silhouette boundary, per view with a silhouette (empty otherwise).
std::vector<cv::Mat> silhouette_distances(const Scene& s) {
  std::vector<cv::Mat> dist(s.size());
  for (int v = 0; v < s.size(); ++v)
    if (s.has_silhouette(v)) cv::distanceTransform(s.sil[v], dist[v], cv::DIST_L2, cv::DIST_MASK_PRECISE);
  return dist;
}

// True when X lies at least `depth` (world units) inside the visual hull: in every view with a
// silhouette that it projects into, the pixel distance to the silhouette's edge, scaled to X's
// depth (z / focal), is at least that.
bool deep_in_hull(const Scene& s, const std::vector<cv::Mat>& dist, const Eigen::Vector3d& X, double depth) {
  for (int v = 0; v < s.size(); ++v) {
    double z;
    int u, w;
    if (dist[v].empty() || !nearest_pixel(s.cams[v], X, z, u, w)) continue;
    if (dist[v].at<float>(w, u) * z / s.cams[v].focal() < depth) return false;
  }
  return true;
}

// True when X projects at least `margin` pixels inside the silhouette of every view with a
// silhouette whose image it falls in, and there is at least one such view.
bool in_hull_core(const Scene& s, const std::vector<cv::Mat>& dist, const Eigen::Vector3d& X, double margin) {
  int views = 0;
  for (int v = 0; v < s.size(); ++v) {
    double z;
    int u, w;
    if (dist[v].empty() || !nearest_pixel(s.cams[v], X, z, u, w)) continue;
    if (dist[v].at<float>(w, u) < margin) return false;
    ++views;
  }
  return views > 0;
}
}  // namespace

std::vector<cv::Mat> q_silhouettes(const Scene& s, const QPoints& q, double cell, double close_px, double margin_px,
                                   int min_points) {
  require(cell > 0 && close_px >= 0 && margin_px >= 0, "label: q_silhouettes needs cell > 0, close_px >= 0, margin_px >= 0");
  std::vector<cv::Mat> out(s.size());
#pragma omp parallel for schedule(dynamic, 1)
  for (int v = 0; v < s.size(); ++v) {
    if (s.has_silhouette(v)) continue;
    const Camera& cam = s.cams[v];
    cv::Mat m = cv::Mat::zeros(cam.height, cam.width, CV_8U);
    int n = 0;
    for (std::int64_t p = 0; p < q.size(); ++p) {
      bool consistent = false;
      for (std::int64_t k = q.cam_offsets[p]; k < q.cam_offsets[p + 1] && !consistent; ++k) consistent = q.cams[k] == v;
      double z;
      int u, w;
      if (!consistent || !nearest_pixel(cam, q.pos(p), z, u, w)) continue;
      const int r = std::max(1, static_cast<int>(std::lround(cell * cam.focal() / z)));
      cv::circle(m, cv::Point(u, w), r, cv::Scalar(255), cv::FILLED);
      ++n;
    }
    if (n < min_points) continue;  // too few points to outline the object: no estimate
    const int c = static_cast<int>(std::lround(close_px));
    if (c > 0)
      cv::morphologyEx(m, m, cv::MORPH_CLOSE, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * c + 1, 2 * c + 1)),
                       cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
    // fill holes: background is what the image border reaches through unmarked pixels
    cv::Mat pad;
    cv::copyMakeBorder(m, pad, 1, 1, 1, 1, cv::BORDER_CONSTANT, cv::Scalar(0));
    cv::floodFill(pad, cv::Point(0, 0), cv::Scalar(128));
    m = pad(cv::Rect(1, 1, cam.width, cam.height)) != 128;
    const int g = static_cast<int>(std::lround(margin_px));
    if (g > 0) cv::dilate(m, m, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * g + 1, 2 * g + 1)));
    out[v] = m;
  }
  return out;
}

std::vector<std::uint8_t> hull_core_cells(const tet::TetMesh& m, const Scene& s, const std::vector<cv::Mat>& dist,
                                          const std::vector<std::int8_t>& label, double core_px, int min_views) {
  const std::int32_t C = m.num_cells();
  std::vector<std::uint8_t> core(C, 0);
#pragma omp parallel for schedule(dynamic, 256)
  for (std::int32_t c = 0; c < C; ++c) {
    if (label[c] != 0) continue;  // box boundary or outside the hull
    const Eigen::Vector3d X = m.cell_centroid(c);
    int deep = 0;
    bool ok = true;
    for (int v = 0; v < s.size() && ok; ++v) {
      if (dist[v].empty()) continue;
      const Camera& cam = s.cams[v];
      if (cam.depth(X) <= 0) continue;
      const Eigen::Vector2d p = cam.project(X);
      const int u = static_cast<int>(std::lround(p.x())), w = static_cast<int>(std::lround(p.y()));
      if (u < 0 || w < 0 || u >= cam.width || w >= cam.height) continue;
      // projected radius of the cell around its centre, in pixels
      double rad = 0;
      for (int k = 0; k < 4; ++k) {
        const Eigen::Vector3d V = m.vertex(m.cell_v[c][k]);
        rad = cam.depth(V) > 0 ? std::max(rad, (cam.project(V) - p).norm()) : 1e30;
      }
      ok = dist[v].at<float>(w, u) >= rad + 1.0 + core_px;  // +1: pixel rounding
      ++deep;
    }
    core[c] = ok && deep >= min_views;
  }
  return core;
}

// Options::conflict_cells: where a cell of the hidden rule (interior) and one of the votes or of
// seen free space (exterior) lie within conflict_cells finest cells of each other (centroids),
// the interior cell is left free, and the exterior one too unless the views hiding it put it
// deeper than the shell and that distance (hidden_depth >= interior_depth + conflict_cells).
// Both sets are taken before either yields, so the order of the cells does not matter.
void resolve_conflicts(const tet::TetMesh& m, const Options& o, double cell, Result& r) {
  const std::int32_t C = m.num_cells();
  const auto from_q_outside = [&](std::int32_t c) { return r.reason[c] == kVotedOut || r.reason[c] == kSeenFree; };
  std::vector<Eigen::Vector3d> inside, outside;
  for (std::int32_t c = 0; c < C; ++c) {
    if (r.reason[c] == kHidden) inside.push_back(m.cell_centroid(c));
    if (from_q_outside(c)) outside.push_back(m.cell_centroid(c));
  }
  if (inside.empty() || outside.empty()) return;
  const double reach = o.conflict_cells * cell;
  const PointProximity near_inside(std::move(inside), reach), near_outside(std::move(outside), reach);
  // deep enough to be beyond the reach of the shell of interior cells, in finest cells
  const double beyond_shell = std::max(0.0, o.interior_depth) + o.conflict_cells;
  std::vector<std::uint8_t> yield(C, 0);
#pragma omp parallel for schedule(dynamic, 1024)
  for (std::int32_t c = 0; c < C; ++c) {
    if (r.reason[c] == kHidden)
      yield[c] = near_outside.any_within(m.cell_centroid(c));
    else if (from_q_outside(c) && r.hidden_depth[c] >= 0 && r.hidden_depth[c] < beyond_shell)
      yield[c] = near_inside.any_within(m.cell_centroid(c));
  }
  for (std::int32_t c = 0; c < C; ++c) {
    if (!yield[c]) continue;
    (r.label[c] == 1 ? r.conflict_interior : r.conflict_exterior) += 1;
    r.label[c] = 0;
    r.reason[c] = kNone;
  }
}

Result label_cells(const tet::TetMesh& m, const Scene& s, const QPoints& q_in, const Options& o) {
  const std::int32_t C = m.num_cells();
  Result r;
  // With the hull-core prior the core is matter, so points of Q inside it are false
  // matches: they are dropped before they cast votes or make depth maps (their rays would
  // carve tunnels through the core).
  std::vector<cv::Mat> dist;
  QPoints q_core;
  if (o.hull_core_px > 0) {
    dist = silhouette_distances(s);
    std::vector<std::uint8_t> drop(q_in.size());
    for (std::int64_t p = 0; p < q_in.size(); ++p) r.q_dropped += drop[p] = in_hull_core(s, dist, q_in.pos(p), o.hull_core_px);
    q_core = keep_points(q_in, drop);
  }
  const QPoints& q_hull_in = o.hull_core_px > 0 ? q_core : q_in;
  r.label.assign(C, 0);
  r.reason.assign(C, kNone);
  const int finest = m.max_cell_level();
  const double cell = tet::red_edge_length(m.lat, finest);
  // In a scene without any silhouette every view gets one estimated from Q
  // (Options::q_silhouettes; scenes with some silhouettes, such as dinoRing's 43 of 48, are
  // left as they were): s_est holds the estimates, s_all the given and the estimated ones. Points of Q outside an estimated
  // silhouette are dropped: another view sees background (or nothing consistent) there.
  Scene s_est = s, s_all = s;
  for (auto& mask : s_est.sil) mask = cv::Mat();
  QPoints q_hull;
  if (o.q_silhouettes && s.num_silhouettes() == 0) {
    const auto est = q_silhouettes(s, q_hull_in, cell, o.q_sil_close_px, o.q_sil_margin_px, o.q_sil_min_points);
    for (int v = 0; v < s.size(); ++v)
      if (!est[v].empty()) s_est.sil[v] = s_all.sil[v] = est[v], ++r.q_sil_views;
  }
  if (r.q_sil_views > 0) {
    std::vector<std::uint8_t> drop(q_hull_in.size());
    for (std::int64_t p = 0; p < q_hull_in.size(); ++p) {
      bool inside = true;
      for (int v = 0; v < s.size() && inside; ++v) {
        double z;
        int u, w;
        if (s_est.has_silhouette(v) && nearest_pixel(s.cams[v], q_hull_in.pos(p), z, u, w))
          inside = s_est.sil[v].at<std::uint8_t>(w, u) != 0;
      }
      r.q_outside_hull += drop[p] = !inside;
    }
    q_hull = keep_points(q_hull_in, drop);
  }
  const QPoints& q_hull_out = r.q_sil_views > 0 ? q_hull : q_hull_in;
  // Points in front of the median depth of Q in median_free_views views (only in scenes
  // without any silhouette, where false matches crowd in front of the surface).
  QPoints q_med;
  const bool use_median = o.median_free_views > 0 && s.num_silhouettes() == 0;
  if (use_median) {
    q_med = q_hull_out;
    for (int pass = 0; pass < o.median_passes; ++pass) {
      const auto drop = in_front_of_quantile(s, q_med, cell, o.depth_margin * cell, 0.5, o.median_free_views, 0.0);
      std::int64_t n = 0;
      for (auto d : drop) n += d;
      r.q_in_front_of_median += n;
      if (n == 0) break;
      q_med = keep_points(q_med, drop);
    }
  }
  // Points in front of Q's free_quantile depth (the lower quartile by default) in
  // quantile_free_views views (off by default; scenes with silhouettes, so never after the
  // median test: the band of photo-consistency in front of surfaces the hull does not bound).
  QPoints q_quant;
  const bool use_quantile = o.quantile_free_views > 0 && s.num_silhouettes() > 0;
  if (use_quantile) {
    const auto drop = in_front_of_quantile(s, q_hull_out, cell, o.depth_margin * cell, o.free_quantile,
                                           o.quantile_free_views, o.quantile_free_share);
    for (auto d : drop) r.q_in_front_of_quantile += d;
    q_quant = keep_points(q_hull_out, drop);
  }
  const QPoints& q_prior = use_quantile ? q_quant : use_median ? q_med : q_hull_out;
  // Free space outranks occlusion for Q itself: points lying in the free space that other
  // points prove (in front of what label.free_views views see) are false matches.
  QPoints q_free;
  if (o.drop_free_points)
    q_free = drop_points_in_free_space(s, q_prior, q_depth_maps(s, q_prior, cell), o.depth_margin * cell, o.free_views,
                                       &r.q_in_free_space);
  const QPoints& q = o.drop_free_points ? q_free : q_prior;
  // 1. the box boundary
  for (std::int32_t f = 0; f < m.num_faces(); ++f)
    if (m.face_on_boundary(f)) {
      const std::int32_t c = m.face_cell(f, 0);
      r.label[c] = -1;
      r.reason[c] = kBoundary;
    }
  // 2. the visual hull
  const auto hull_out = outside_visual_hull(m, s);
  for (std::int32_t c = 0; c < C; ++c)
    if (hull_out[c] && r.label[c] == 0) {
      r.label[c] = -1;
      r.reason[c] = kOutsideHull;
    }
  if (r.q_sil_views > 0) {
    const auto outside_q_hull = outside_visual_hull(m, s_est);
    for (std::int32_t c = 0; c < C; ++c)
      if (outside_q_hull[c] && r.label[c] == 0) {
        r.label[c] = -1;
        r.reason[c] = kOutsideQHull;
      }
  }
  // 3. votes
  r.votes = visibility_votes(m, s, q, o.vote_offset * cell, &r.rays);
  std::vector<std::int32_t> pool;
  std::vector<std::int32_t> candidates;
  for (std::int32_t c = 0; c < C; ++c) {
    if (r.label[c] != 0) continue;
    if (m.node_level[m.cell_node[c]] >= finest) continue;  // active band: left to the cut
    candidates.push_back(c);
    pool.push_back(r.votes[c]);
  }
  r.low_votes = percentile(pool, o.low_percentile);
  // The high percentile is taken over the cells some ray crosses: cells no ray reaches say
  // nothing about free space, and where they are most of the pool (a thin active band
  // around an object whose unseen inside is all inactive) the percentile of all cells is 0
  // and any few stray rays would make a cell exterior.
  std::vector<std::int32_t> crossed;
  for (const auto v : pool)
    if (v > 0) crossed.push_back(v);
  r.high_votes = percentile(crossed, o.high_percentile);
  auto depth = q_depth_maps(s, q, cell, o.seen_free_views > 0);
  // Without silhouettes the visible side for the hidden (interior) test is the median depth
  // of Q where at least 3 splats give one: false matches in front of the surface must not
  // hide the air behind them.
  if (use_median) {
    const auto med = median_depth_maps(s, q, cell);
    for (int v = 0; v < s.size(); ++v) {
      cv::Mat f = depth.front[v].clone();
      med[v].copyTo(f, med[v] != 0);
      depth.front[v] = f;
    }
  }
  const double margin = o.depth_margin * cell;
  // Seen free space (Options::seen_free_views): with a window wider than the free test's own
  // (one cell), the nearest Q within seen_free_window cells, so that a gap in Q's splats where
  // a surface faces the view is less likely to pass for free space. Empty: the free test's.
  std::vector<cv::Mat> wide_near;
  if (o.seen_free_views > 0 && o.seen_free_window != 1.0) {
    wide_near.resize(s.size());
#pragma omp parallel for schedule(dynamic, 1)
    for (int v = 0; v < s.size(); ++v)
      wide_near[v] = nearest_in_window(depth.front[v], window_radius(s.cams[v], q, cell, o.seen_free_window));
  }
  const double shell = o.interior_depth > 0 ? o.interior_depth * cell : std::numeric_limits<double>::infinity();
  std::vector<std::uint8_t> seen_free(C, 0);
  std::vector<std::int8_t> decided(C, 0);
  std::vector<std::uint8_t> is_candidate(C, 0);
  for (std::int32_t c : candidates) is_candidate[c] = 1;
  r.inside_evidence.assign(C, 0.0f);
  r.outside_evidence.assign(C, 0.0f);
  r.free_views.assign(C, 0);
  r.beyond_views.assign(C, 0);
  r.hidden_views.assign(C, 0);
  r.seen_views.assign(C, 0);
  r.hidden_depth.assign(C, -1.0f);
  const auto u8 = [](int n) { return static_cast<std::uint8_t>(std::min(n, 255)); };
  // Every free cell gets soft evidence (for the cut's optional visibility term); the
  // inactive candidates also get hard labels.
#pragma omp parallel for schedule(dynamic, 256)
  for (std::int32_t c = 0; c < C; ++c) {
    if (r.label[c] != 0) continue;
    const Eigen::Vector3d X = m.cell_centroid(c);
    int sandwiched = 0, free_space = 0, beyond = 0, seen = 0, outside_views = 0, wide_free = 0, shell_hidden = 0, exited = 0;
    double shallowest = -1;
    std::vector<double> gaps;  // depth behind Q's visible side, per hiding view
    for (int v = 0; v < s.size(); ++v) {
      double z;
      int u, w;
      if (!nearest_pixel(s.cams[v], X, z, u, w)) continue;
      const float df = depth.front[v].at<float>(w, u), db = depth.back[v].at<float>(w, u);
      const float dn = depth.near[v].at<float>(w, u), dx = depth.far[v].at<float>(w, u);
      const bool is_free = dn != 0 && z < dn - margin, is_beyond = dx != 0 && z > dx + margin;
      free_space += is_free;
      beyond += is_beyond;
      outside_views += is_free || is_beyond;
      if (df != 0 && db != 0 && z > df + margin && z < db - margin) {
        ++sandwiched;
        gaps.push_back(z - df);
        shell_hidden += z - df <= shell;
        if (!depth.exit.empty()) {
          const float ex = depth.exit[v].at<float>(w, u), en = depth.entry[v].at<float>(w, u);
          exited += ex != 0 && ex < z - margin && (en == 0 || en > z - margin);
        }
      }
      if (wide_near.empty()) {
        wide_free += is_free;
      } else {
        const float dw = wide_near[v].at<float>(w, u);
        wide_free += dw != 0 && z < dw - margin;
      }
      ++seen;
    }
    r.free_views[c] = u8(free_space);
    r.beyond_views[c] = u8(beyond);
    r.hidden_views[c] = u8(sandwiched);
    r.seen_views[c] = u8(seen);
    // the depth reached in min_occluding_views of the hiding views (robust to a stray point of Q)
    if (static_cast<int>(gaps.size()) >= o.min_occluding_views) {
      std::nth_element(gaps.begin(), gaps.begin() + (o.min_occluding_views - 1), gaps.end());
      shallowest = gaps[o.min_occluding_views - 1];
    } else {
      shallowest = -1;
    }
    r.hidden_depth[c] = shallowest < 0 ? -1.0f : static_cast<float>(shallowest / cell);
    if (seen > 0) {
      const double out = std::min(1.0, o.free_weight * outside_views / seen);
      r.outside_evidence[c] = static_cast<float>(out);
      r.inside_evidence[c] = static_cast<float>((1.0 - out) * sandwiched / seen);
    }
    // Seen free space: free in seen_free_views views and, in every view hiding it, deeper
    // behind Q's visible side than matter under a seen surface lies (the shell of
    // interior_depth), and in seen_free_exit_share of them behind a wall: the ray left the
    // matter it met (a point facing away from the view) and met none again before the cell.
    // A cavity's air seen over its rim; active cells too (Q's band there).
    if (o.seen_free_views > 0 && wide_free >= o.seen_free_views && shell_hidden == 0 &&
        exited >= o.seen_free_exit_share * sandwiched)
      seen_free[c] = 1;  // a candidate still gets its own label below, should the tests after this loop fail
    if (!is_candidate[c]) continue;
    // interior cells must lie wholly inside every silhouette (corners; outside an image is fine)
    bool in_hull = true;
    for (int k = 0; k < 4 && in_hull; ++k) {
      const Eigen::Vector3d V = m.vertex(m.cell_v[c][k]);
      for (int v = 0; v < s.size() && in_hull; ++v) {
        if (!s_all.has_silhouette(v) || s.cams[v].depth(V) <= 0) continue;
        const Eigen::Vector2d p = s.cams[v].project(V);
        in_hull = s_all.in_silhouette(v, p.x(), p.y(), true);
      }
    }
    const int votes = r.votes[c];
    // With the hull-core prior, the core supplies the interior; "hidden behind Q" in the band
    // under the hull's surface rests on the very points the prior distrusts (measured on
    // dinoRing: single-cell specks outside the body).
    if (o.hull_core_px <= 0 && in_hull && votes <= r.low_votes && free_space == 0 && beyond == 0 &&
        sandwiched >= o.min_occluding_views) {
      if (o.interior_depth <= 0 || shallowest <= o.interior_depth * cell)
        decided[c] = 1;
      else
        decided[c] = 3;  // hidden everywhere, but too deep behind the seen surface: left free
    } else if (votes > r.high_votes && votes >= o.min_exterior_votes && free_space >= o.free_views)
      decided[c] = -1;
  }
  // 4. the optional hull-core prior (Options::hull_core_px)
  if (o.hull_core_px > 0) {
    const auto core = hull_core_cells(m, s, dist, r.label, o.hull_core_px, o.min_occluding_views);
    for (std::int32_t c = 0; c < C; ++c)
      if (core[c]) decided[c] = 2;
  }
  for (std::int32_t c = 0; c < C; ++c)
    if (decided[c] == 2) {
      r.label[c] = 1;
      r.reason[c] = kHullCore;
    }
  // Exterior by votes also needs the cell deep inside the visual hull (voted_out_hull_depth):
  // under a surface that a silhouette bounds, Q's band lies cells inside the surface and the
  // rays of its points cross the matter above it (the same cause as for the seen-free rule).
  std::vector<cv::Mat> sil_dist;  // of s_all, computed once for the hull tests
  const bool hull_tests = s_all.num_silhouettes() > 0 &&
                          (o.voted_out_hull_depth > 0 || (o.seen_free_views > 0 && o.seen_free_hull_depth > 0));
  if (hull_tests) sil_dist = !dist.empty() && s.num_silhouettes() > 0 ? dist : silhouette_distances(s_all);
  if (o.voted_out_hull_depth > 0 && !sil_dist.empty()) {
    std::vector<std::uint8_t> shallow(C, 0);
#pragma omp parallel for schedule(dynamic, 1024)
    for (std::int32_t c = 0; c < C; ++c)
      if (decided[c] == -1 && !deep_in_hull(s, sil_dist, m.cell_centroid(c), o.voted_out_hull_depth * cell))
        shallow[c] = 1;
    for (std::int32_t c = 0; c < C; ++c)
      if (shallow[c]) {
        decided[c] = 0;
        ++r.voted_out_near_hull;
      }
  }
  // Interior islands (interior_min_share): hidden cells in face-connected groups smaller than
  // that share of the largest group are left free.
  if (o.interior_min_share > 0) {
    std::vector<std::uint8_t> hidden(C, 0);
    for (std::int32_t c : candidates) hidden[c] = decided[c] == 1;
    const auto islands = small_groups(m, hidden, o.interior_min_share);
    for (std::int32_t c : candidates)
      if (islands[c]) {
        decided[c] = 0;
        ++r.interior_islands;
      }
  }
  for (std::int32_t c : candidates) {
    if (decided[c] == 1) {
      r.label[c] = 1;
      r.reason[c] = kHidden;
    } else if (decided[c] == -1) {
      r.label[c] = -1;
      r.reason[c] = kVotedOut;
    }
  }
  // ... and clear of Q: a cell just under a surface can look free in a view where the
  // nearest point of Q in its window lies a little deeper, but the surface's points are close.
  if (o.seen_free_views > 0 && o.seen_free_clearance > 0 && q.size() > 0) {
    const PointProximity near_q(positions(q), o.seen_free_clearance * cell);
#pragma omp parallel for schedule(dynamic, 1024)
    for (std::int32_t c = 0; c < C; ++c)
      if (seen_free[c] && near_q.any_within(m.cell_centroid(c))) seen_free[c] = 0;
  }
  // ... and deep inside the visual hull (seen_free_hull_depth): where a silhouette bounds the surface,
  // Q's band of photo-consistency is clipped in front of it and reaches only inward, so Q's
  // visible side can lie cells under the true surface and the matter between looks free
  // (docs/architecture.md, "Seen free space").
  if (o.seen_free_views > 0 && o.seen_free_hull_depth > 0 && !sil_dist.empty()) {
#pragma omp parallel for schedule(dynamic, 1024)
    for (std::int32_t c = 0; c < C; ++c)
      if (seen_free[c] && !deep_in_hull(s, sil_dist, m.cell_centroid(c), o.seen_free_hull_depth * cell))
        seen_free[c] = 0;
  }
  // ... and in a face-connected group of at least seen_free_min_cells such cells
  if (o.seen_free_min_cells > 1) {
    const auto sizes = group_sizes(m, seen_free);
    for (std::int32_t c = 0; c < C; ++c)
      if (seen_free[c] && sizes[c] < o.seen_free_min_cells) {
        seen_free[c] = 0;
        ++r.seen_free_islands;
      }
  }
  for (std::int32_t c = 0; c < C; ++c)
    if (seen_free[c] && r.reason[c] != kHullCore) {  // the hull-core prior overrules Q
      r.label[c] = -1;
      r.reason[c] = kSeenFree;
    }
  if (o.conflict_cells > 0) resolve_conflicts(m, o, cell, r);
  for (std::int32_t c = 0; c < C; ++c) {
    r.too_deep += decided[c] == 3;
    r.interior += r.label[c] == 1;
    r.exterior += r.label[c] == -1;
    r.boundary += r.reason[c] == kBoundary;
    r.hull_exterior += r.reason[c] == kOutsideHull;
    r.voted_out += r.reason[c] == kVotedOut;
    r.seen_free += r.reason[c] == kSeenFree;
    r.hull_core += r.reason[c] == kHullCore;
    r.q_hull_exterior += r.reason[c] == kOutsideQHull;
  }
  // Seeds without Q: a textureless object has almost no Q, so nothing is hidden behind it.
  // With silhouettes, the hull core is matter whatever the texture (Options::seed_core_px).
  // Not when Q hides cells that are only too deep (a cup's unseen cavity: the hull core
  // would fill it), and never a cell that some view sees as free space or beyond Q.
  if (r.interior == 0 && r.too_deep == 0 && o.seed_core_px > 0 && s.num_silhouettes() > 0) {
    if (dist.empty()) dist = silhouette_distances(s);
    const auto core = hull_core_cells(m, s, dist, r.label, o.seed_core_px, o.min_occluding_views);
    for (std::int32_t c = 0; c < C; ++c)
      if (core[c] && r.free_views[c] == 0 && r.beyond_views[c] == 0) {
        r.label[c] = 1;
        r.reason[c] = kSeedCore;
        ++r.seed_core;
        ++r.interior;
      }
  }
  return r;
}

}  // namespace tetmvs::label
