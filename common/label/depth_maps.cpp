#include "common/label/depth_maps.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "common/label/geometry.h"

namespace tetmvs::label {

namespace {

// Radius in pixels of a window of one finest cell at the mean depth of Q in the view (at
// least 1 pixel).
int window_radius(const Camera& cam, const QPoints& q, double cell) {
  double zc = 0;
  for (std::int64_t p = 0; p < q.size(); ++p) zc += cam.depth(q.pos(p));
  zc = q.size() ? zc / q.size() : 1.0;
  return std::max(1, static_cast<int>(std::ceil(cell * cam.focal() / std::max(zc, 1e-12))));
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

// A disc splat: centre pixel (u, w), radius r (pixels) and value.
struct Splat {
  int u, w, r;
  float value;
};

// The splat of point X at depth z > 0: a disc of one finest cell at its depth (at least one
// pixel) around its nearest pixel; false when the disc misses the image.
bool splat_of(const Camera& cam, const Eigen::Vector3d& X, double z, double cell, float value, Splat& s) {
  const Eigen::Vector2d px = cam.project(X);
  // (a radius beyond a million pixels covers as much of any image as a larger one)
  s.r = static_cast<int>(std::clamp(std::ceil(cell * cam.focal() / z), 1.0, 1e6));
  if (!(std::abs(px.x()) < 1e9 && std::abs(px.y()) < 1e9)) return false;
  s.u = static_cast<int>(std::lround(px.x())), s.w = static_cast<int>(std::lround(px.y()));
  s.value = value;
  return s.u >= -s.r && s.u < cam.width + s.r && s.w >= -s.r && s.w < cam.height + s.r;
}

// Radii up to this have their discs' half-widths tabulated (disc_half_widths).
constexpr int kTableRadius = 32;

// The largest du with du^2 + dw^2 <= r^2, for r = 1..kTableRadius and dw = 0..r: entry
// r (r + 1) / 2 - 1 + dw.
const std::vector<std::int32_t>& disc_half_widths() {
  static const std::vector<std::int32_t> table = [] {
    std::vector<std::int32_t> t;
    for (std::int64_t r = 1; r <= kTableRadius; ++r)
      for (std::int64_t dw = 0; dw <= r; ++dw) {
        std::int64_t du = 0;
        while ((du + 1) * (du + 1) + dw * dw <= r * r) ++du;
        t.push_back(static_cast<std::int32_t>(du));
      }
    return t;
  }();
  return table;
}

// The pixels of splat s in a W x H image, those with du^2 + dw^2 <= r^2 from its centre:
// f(w, u0, u1) per image row w, for the columns u0..u1 (inclusive) of that row.
template <class F>
void for_splat_rows(const Splat& s, int W, int H, F&& f) {
  const std::int64_t r2 = std::int64_t{s.r} * s.r;
  const std::int32_t* half = s.r <= kTableRadius ? disc_half_widths().data() + (s.r * (s.r + 1) / 2 - 1) : nullptr;
  for (int w = std::max(s.w - s.r, 0); w <= std::min(s.w + s.r, H - 1); ++w) {
    std::int64_t du;
    if (half) {
      du = half[std::abs(w - s.w)];
    } else {
      const std::int64_t rest = r2 - std::int64_t{w - s.w} * (w - s.w);
      du = static_cast<std::int64_t>(std::sqrt(static_cast<double>(rest)));  // the largest du, du^2 <= rest
      while ((du + 1) * (du + 1) <= rest) ++du;
      while (du * du > rest) --du;
    }
    const auto a = static_cast<int>(std::max<std::int64_t>(s.u - du, 0));
    const auto b = static_cast<int>(std::min<std::int64_t>(s.u + du, W - 1));
    if (a <= b) f(w, a, b);
  }
}

// The largest value of the splats covering each pixel of a W x H image (-inf: none): per
// radius, the values placed at their centres (on the image grown by the radius) and dilated
// by that disc, which equals stamping every disc and is several times quicker. Discs wider
// than kDilateRadius (a point close to a camera) are stamped.
cv::Mat max_of_splats(const std::vector<Splat>& splats, int W, int H) {
  constexpr float kNone = -std::numeric_limits<float>::infinity();
  constexpr int kDilateRadius = 32;
  cv::Mat out(H, W, CV_32F, cv::Scalar(kNone));
  std::vector<int> radii;
  for (const Splat& s : splats) {
    if (s.r > kDilateRadius) {
      for_splat_rows(s, W, H, [&](int w, int a, int b) {
        float* row = out.ptr<float>(w);
        for (int u = a; u <= b; ++u) row[u] = std::max(row[u], s.value);
      });
    } else if (std::find(radii.begin(), radii.end(), s.r) == radii.end()) {
      radii.push_back(s.r);
    }
  }
  std::sort(radii.begin(), radii.end());
  for (const int r : radii) {
    cv::Mat centres(H + 2 * r, W + 2 * r, CV_32F, cv::Scalar(kNone));
    for (const Splat& s : splats)
      if (s.r == r) {
        float& c = centres.at<float>(s.w + r, s.u + r);
        c = std::max(c, s.value);
      }
    cv::Mat disc(2 * r + 1, 2 * r + 1, CV_8U, cv::Scalar(0));
    for (int dw = -r; dw <= r; ++dw)
      for (int du = -r; du <= r; ++du) disc.at<std::uint8_t>(dw + r, du + r) = du * du + dw * dw <= r * r;
    cv::Mat grown;
    cv::dilate(centres, grown, disc, cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(kNone));
    out = cv::max(out, grown(cv::Rect(r, r, W, H)));
  }
  return out;
}

}  // namespace

std::vector<std::vector<std::int64_t>> points_by_view(const QPoints& q, int views) {
  std::vector<std::vector<std::int64_t>> out(views);
  for (std::int64_t p = 0; p < q.size(); ++p)
    for (std::int64_t k = q.cam_offsets[p]; k < q.cam_offsets[p + 1]; ++k) {
      auto& list = out[q.cams[k]];
      if (list.empty() || list.back() != p) list.push_back(p);  // a camera listed twice counts once
    }
  return out;
}

namespace {
DepthMaps depth_maps_of(const Scene& s, const QPoints& q, double cell, bool far_side, bool with_exits,
                        double margin) {
  DepthMaps d;
  const int V = s.size();
  for (auto* maps : {&d.front, &d.back, &d.near, &d.far}) maps->resize(V);
  if (with_exits) {
    d.exit.resize(V);
    d.entry.resize(V);
  }
  const auto by_view = points_by_view(q, V);
#pragma omp parallel for schedule(dynamic, 1)
  for (int v = 0; v < V; ++v) {
    const Camera& cam = s.cams[v];
    const Eigen::Vector3d C = cam.centre();
    // front: the nearest splat (the largest of minus the depths); back: the farthest of the
    // points facing away (float(min z) and float(max z), as stamping in any order gives)
    std::vector<Splat> splats;
    Splat sp;
    for (const std::int64_t p : by_view[v]) {
      const Eigen::Vector3d X = q.pos(p);
      const double z = cam.depth(X);
      if (z > 0 && splat_of(cam, X, z, cell, -static_cast<float>(z), sp)) splats.push_back(sp);
    }
    cv::Mat front = -max_of_splats(splats, cam.width, cam.height);
    front.setTo(0, front == std::numeric_limits<float>::infinity());
    // every point's splat in this view, once, with its depth and which way it faces (n . (C - X))
    struct Seen {
      Splat s;
      double z, facing;
    };
    std::vector<Seen> all;
    if (far_side || with_exits)
      for (std::int64_t p = 0; p < q.size(); ++p) {
        const Eigen::Vector3d X = q.pos(p);
        const double facing = q.nrm(p).dot(C - X);
        const double z = cam.depth(X);
        if (z > 0 && splat_of(cam, X, z, cell, static_cast<float>(z), sp)) all.push_back({sp, z, facing});
      }
    splats.clear();
    if (far_side)
      for (const Seen& x : all)
        if (x.facing < 0) splats.push_back(x.s);  // facing away
    cv::Mat back = max_of_splats(splats, cam.width, cam.height);
    back.setTo(0, back == -std::numeric_limits<float>::infinity());
    if (with_exits) {
      cv::Mat exit = cv::Mat::zeros(cam.height, cam.width, CV_32F);
      cv::Mat entry = cv::Mat::zeros(cam.height, cam.width, CV_32F);
      for (const bool exits : {true, false})
        for (const Seen& x : all) {
          if (exits ? x.facing >= 0 : x.facing <= 0) continue;
          const double z = x.z;
          const float zf = x.s.value;
          const cv::Mat& before = exits ? front : exit;
          cv::Mat& target = exits ? exit : entry;
          for_splat_rows(x.s, cam.width, cam.height, [&](int w, int a, int b) {
            const float* bef = before.ptr<float>(w);
            float* row = target.ptr<float>(w);
            for (int u = a; u <= b; ++u)
              if (bef[u] != 0 && z >= bef[u] + margin && (row[u] == 0 || z < row[u])) row[u] = zf;
          });
        }
      d.exit[v] = exit;
      d.entry[v] = entry;
    }
    d.front[v] = front;
    d.back[v] = back;
    const int wr = window_radius(cam, q, cell);
    const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * wr + 1, 2 * wr + 1));
    if (far_side) cv::dilate(back, d.far[v], kernel, cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
    d.near[v] = nearest_in_window(front, wr);
  }
  return d;
}
}  // namespace

DepthMaps q_depth_maps(const Scene& s, const QPoints& q, double cell, bool with_exits, double margin) {
  return depth_maps_of(s, q, cell, true, with_exits, margin);
}

DepthMaps q_visible_side(const Scene& s, const QPoints& q, double cell) {
  return depth_maps_of(s, q, cell, false, false, 0);
}

DepthMaps visible_side_maps(const Scene& s, const QPoints& q, double cell, bool with_exits, double margin) {
  DepthMaps d = q_depth_maps(s, q, cell, with_exits, margin);
  if (s.num_silhouettes() == 0) {
    const auto med = quantile_depth_maps(s, q, cell, 0.5);
    for (int v = 0; v < s.size(); ++v) med[v].copyTo(d.front[v], med[v] != 0);
  }
  return d;
}

QPoints keep_points(const QPoints& q, const std::vector<std::uint8_t>& drop) {
  QPoints out;
  for (std::int64_t p = 0; p < q.size(); ++p) {
    if (drop[p]) continue;
    const std::vector<std::int32_t> cams(q.cams.begin() + q.cam_offsets[p], q.cams.begin() + q.cam_offsets[p + 1]);
    out.add(q.pos(p), q.nrm(p), q.score[p], cams, q.face[p]);
  }
  return out;
}

std::vector<cv::Mat> quantile_depth_maps(const Scene& s, const QPoints& q, double cell, double quantile) {
  std::vector<cv::Mat> out(s.size());
  const auto by_view = points_by_view(q, s.size());
#pragma omp parallel for schedule(dynamic, 1)
  for (int v = 0; v < s.size(); ++v) {
    const Camera& cam = s.cams[v];
    std::vector<std::pair<std::int32_t, float>> splat;  // (pixel, depth)
    for (const std::int64_t p : by_view[v]) {
      double z;
      int u0, w0;
      if (!nearest_pixel(cam, q.pos(p), z, u0, w0)) continue;
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

}  // namespace tetmvs::label
