#include "common/trimesh/raster.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include "common/error.h"

namespace tetmvs {

namespace {
constexpr std::int64_t kSub = 256;  // fixed-point steps per sample

inline std::int64_t edge(std::int64_t ax, std::int64_t ay, std::int64_t bx, std::int64_t by, std::int64_t px,
                         std::int64_t py) {
  return (bx - ax) * (py - ay) - (by - ay) * (px - ax);
}
inline std::int64_t floor_div(std::int64_t a, std::int64_t b) {
  const std::int64_t q = a / b;
  return (a % b != 0 && (a < 0) != (b < 0)) ? q - 1 : q;
}
// Top-left ownership of edge a->b for a triangle with positive edge() area (y down).
inline bool owns(std::int64_t ax, std::int64_t ay, std::int64_t bx, std::int64_t by) {
  const std::int64_t dx = bx - ax, dy = by - ay;
  return dy < 0 || (dy == 0 && dx > 0);
}
}  // namespace

Raster rasterize(const TriMesh& m, const Camera& cam, const RasterOptions& opt) {
  require(cam.width > 0 && cam.height > 0, "rasterize: camera '", cam.name, "' has no image size");
  require(opt.supersample >= 1 && opt.supersample <= 16, "rasterize: supersample must be 1..16, got ", opt.supersample);
  Raster r;
  r.width = cam.width;
  r.height = cam.height;
  r.ss = opt.supersample;
  const int W = cam.width * r.ss, H = cam.height * r.ss;
  r.depth.create(H, W, CV_32F);
  r.tri.create(H, W, CV_32S);
  std::fill_n(r.depth.ptr<float>(), static_cast<std::size_t>(W) * H, std::numeric_limits<float>::infinity());
  std::fill_n(r.tri.ptr<int>(), static_cast<std::size_t>(W) * H, -1);
  const std::size_t nv = m.V.size();
  // Per vertex, packed (one cache line per triangle corner): depth, its inverse, the
  // unsnapped sample-grid coordinates (for depth) and the snapped ones.
  struct Proj {
    double z, iz, pu, pv;
    std::int64_t fx, fy;
  };
  std::vector<Proj> pr(nv);
  const Eigen::Matrix3d KR = cam.K * cam.R;
  const Eigen::Vector3d Kt = cam.K * cam.t;
  const double s = r.ss;
  // Keep snapped coordinates within a range where products fit in 64 bits.
  const double lim = 1e7;
  for (std::size_t i = 0; i < nv; ++i) {
    const Eigen::Vector3d x = KR * m.V[i] + Kt;
    Proj& p = pr[i];
    p.z = x.z();
    if (!(x.z() > opt.znear)) continue;
    p.iz = 1.0 / x.z();
    double u = (x.x() / x.z() + 0.5) * s - 0.5, v = (x.y() / x.z() + 0.5) * s - 0.5;
    u = std::clamp(u, -lim, lim);
    v = std::clamp(v, -lim, lim);
    p.pu = u;
    p.pv = v;
    p.fx = round_nearest(u * kSub);
    p.fy = round_nearest(v * kSub);
  }
  float* D = r.depth.ptr<float>();
  int* T = r.tri.ptr<int>();
  struct {
    std::int64_t x0, x1, y0, y1;
  } cover{W, -1, H, -1};  // the samples the triangles cover
  for (std::size_t f = 0; f < m.F.size(); ++f) {
    int i0 = m.F[f][0], i1 = m.F[f][1], i2 = m.F[f][2];
    if (!(pr[i0].z > opt.znear && pr[i1].z > opt.znear && pr[i2].z > opt.znear)) {
      ++r.skipped_near;
      continue;
    }
    std::int64_t area = edge(pr[i0].fx, pr[i0].fy, pr[i1].fx, pr[i1].fy, pr[i2].fx, pr[i2].fy);
    if (area == 0) continue;
    // With y down, a triangle counter-clockwise seen from its front has negative area here.
    if (opt.cull_back && area > 0) continue;
    if (area < 0) {
      std::swap(i1, i2);
      area = -area;
    }
    const Proj &p0 = pr[i0], &p1 = pr[i1], &p2 = pr[i2];
    const std::int64_t x0 = p0.fx, y0 = p0.fy, x1 = p1.fx, y1 = p1.fy, x2 = p2.fx, y2 = p2.fy;
    const std::int64_t minx = std::min({x0, x1, x2}), maxx = std::max({x0, x1, x2});
    const std::int64_t miny = std::min({y0, y1, y2}), maxy = std::max({y0, y1, y2});
    // Sample i sits at i * kSub.
    const std::int64_t ia = std::max<std::int64_t>(0, -floor_div(-minx, kSub));
    const std::int64_t ib = std::min<std::int64_t>(W - 1, floor_div(maxx, kSub));
    const std::int64_t ja = std::max<std::int64_t>(0, -floor_div(-miny, kSub));
    const std::int64_t jb = std::min<std::int64_t>(H - 1, floor_div(maxy, kSub));
    if (ia > ib || ja > jb) continue;
    const std::int64_t b0 = owns(x1, y1, x2, y2) ? 0 : 1;  // edge opposite vertex 0
    const std::int64_t b1 = owns(x2, y2, x0, y0) ? 0 : 1;
    const std::int64_t b2 = owns(x0, y0, x1, y1) ? 0 : 1;
    // 1/z is affine in image coordinates: 1/z = A u + B v + C0, from the unsnapped vertices;
    // set up at the first covered sample (most small triangles cover none).
    bool plane = false;
    double A = 0, B = 0, C0 = 0;
    const auto setup_plane = [&] {
      const double iz0 = p0.iz, iz1 = p1.iz, iz2 = p2.iz;
      const double e1u = p1.pu - p0.pu, e1v = p1.pv - p0.pv, e2u = p2.pu - p0.pu, e2v = p2.pv - p0.pv;
      const double det = e1u * e2v - e1v * e2u;
      if (det != 0) {
        A = ((iz1 - iz0) * e2v - (iz2 - iz0) * e1v) / det;
        B = ((iz2 - iz0) * e1u - (iz1 - iz0) * e2u) / det;
      }
      C0 = iz0 - A * p0.pu - B * p0.pv;
      plane = true;
    };
    // Each edge function is affine along a row: w(i) = w(ia) + (i - ia) d with d = -(y_b - y_a) kSub.
    // The covered samples of a row are the span where all three are >= their ownership bias,
    // solved exactly in integers (the same samples as testing each one).
    const std::int64_t d0 = -(y2 - y1) * kSub, d1 = -(y0 - y2) * kSub, d2 = -(y1 - y0) * kSub;
    for (std::int64_t j = ja; j <= jb; ++j) {
      const std::int64_t py = j * kSub, px = ia * kSub;
      std::int64_t lo = ia, hi = ib;
      const auto clip = [&](std::int64_t w, std::int64_t d) {  // keep the i with w + (i - ia) d >= 0
        if (d > 0) {
          if (w < 0) lo = std::max(lo, ia - floor_div(w, d));  // ia + ceil(-w / d)
        } else if (d < 0) {
          hi = w < 0 ? ia - 1 : std::min(hi, ia + floor_div(w, -d));
        } else if (w < 0) {
          hi = ia - 1;
        }
      };
      clip(edge(x1, y1, x2, y2, px, py) - b0, d0);
      clip(edge(x2, y2, x0, y0, px, py) - b1, d1);
      clip(edge(x0, y0, x1, y1, px, py) - b2, d2);
      if (lo > hi) continue;
      if (!plane) setup_plane();
      cover.x0 = std::min(cover.x0, lo), cover.x1 = std::max(cover.x1, hi);
      cover.y0 = std::min(cover.y0, j), cover.y1 = std::max(cover.y1, j);
      for (std::int64_t i = lo; i <= hi; ++i) {
        const double iz = A * static_cast<double>(i) + B * static_cast<double>(j) + C0;
        const float d = static_cast<float>(1.0 / iz);
        const std::size_t k = static_cast<std::size_t>(j) * W + i;
        if (d < D[k] || (d == D[k] && static_cast<int>(f) < T[k])) {
          D[k] = d;
          T[k] = static_cast<int>(f);
        }
      }
    }
  }
  if (cover.x1 >= 0)
    r.covered_box = cv::Rect(static_cast<int>(cover.x0), static_cast<int>(cover.y0), static_cast<int>(cover.x1 - cover.x0 + 1),
                             static_cast<int>(cover.y1 - cover.y0 + 1));
  return r;
}

cv::Mat Raster::coverage() const {
  cv::Mat c(height, width, CV_32F, cv::Scalar(0));
  const float w = 1.0f / (ss * ss);
  for (int j = 0; j < height * ss; ++j) {
    const int* t = tri.ptr<int>(j);
    float* out = c.ptr<float>(j / ss);
    for (int i = 0; i < width * ss; ++i)
      if (t[i] >= 0) out[i / ss] += w;
  }
  return c;
}

cv::Mat Raster::centre_mask() const {
  require(ss % 2 == 1, "Raster::centre_mask needs an odd supersampling factor (got ", ss, ")");
  cv::Mat mask(height, width, CV_8U, cv::Scalar(0));
  const int o = ss / 2;  // the middle sample of each pixel is its centre
  for (int v = 0; v < height; ++v) {
    const int* t = tri.ptr<int>(v * ss + o);
    std::uint8_t* out = mask.ptr<std::uint8_t>(v);
    for (int u = 0; u < width; ++u) out[u] = t[u * ss + o] >= 0 ? 255 : 0;
  }
  return mask;
}

Raster subsample(const Raster& r, int level) {
  require(r.ss == 1, "subsample: the raster is supersampled (", r.ss, ")");
  require(level >= 0 && level <= 12, "subsample: pyramid level ", level, " must lie in [0, 12]");
  Raster out;
  out.width = r.width;
  out.height = r.height;
  for (int l = 0; l < level; ++l) {
    out.width = (out.width + 1) / 2;
    out.height = (out.height + 1) / 2;
  }
  out.skipped_near = r.skipped_near;
  out.depth.create(out.height, out.width, CV_32F);
  out.tri.create(out.height, out.width, CV_32S);
  int x0 = out.width, x1 = -1, y0 = out.height, y1 = -1;  // the covered samples' box
  for (int y = 0; y < out.height; ++y) {
    const float* d = r.depth.ptr<float>(y << level);
    const int* t = r.tri.ptr<int>(y << level);
    float* od = out.depth.ptr<float>(y);
    int* ot = out.tri.ptr<int>(y);
    for (int x = 0; x < out.width; ++x) {
      od[x] = d[x << level];
      ot[x] = t[x << level];
      if (ot[x] >= 0) x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    }
  }
  if (x1 >= 0) out.covered_box = cv::Rect(x0, y0, x1 - x0 + 1, y1 - y0 + 1);
  return out;
}

bool pixel_point_on_triangle(const TriMesh& m, int f, const Camera& cam, double u, double v, Eigen::Vector3d& X) {
  const Eigen::Vector3d C = cam.centre();
  const Eigen::Vector3d d = cam.R.transpose() * (cam.K.inverse() * Eigen::Vector3d(u, v, 1.0));
  const Eigen::Vector3d& a = m.V[m.F[f][0]];
  const Eigen::Vector3d n = (m.V[m.F[f][1]] - a).cross(m.V[m.F[f][2]] - a);
  const double den = n.dot(d);
  if (den == 0 || !std::isfinite(den)) return false;
  X = C + d * (n.dot(a - C) / den);
  return true;
}

}  // namespace tetmvs
