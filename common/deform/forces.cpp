#include "common/deform/forces.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "common/error.h"
#include "common/image.h"
#include "common/silhouette/border.h"
#include "common/trimesh/raster.h"

namespace tetmvs::deform {

cv::Mat signed_distance(const cv::Mat& mask) {
  cv::Mat obj = mask > 127, bg = mask <= 127;
  // distances to the outline, which the image border is not (common/silhouette/border.h)
  const cv::Mat d_in = silhouette::distance_inside(obj), d_out = silhouette::distance_outside(obj);
  cv::Mat sd(mask.size(), CV_32F);
  const bool any_obj = cv::countNonZero(obj) > 0, any_bg = cv::countNonZero(bg) > 0;
  const float big = static_cast<float>(mask.cols + mask.rows);
  for (int y = 0; y < mask.rows; ++y)
    for (int x = 0; x < mask.cols; ++x) {
      float v;
      if (obj.at<std::uint8_t>(y, x)) v = any_bg ? -(d_in.at<float>(y, x) - 0.5f) : -big;
      else v = any_obj ? d_out.at<float>(y, x) - 0.5f : big;
      sd.at<float>(y, x) = v;
    }
  return sd;
}

cv::Mat signed_distance_near(const cv::Mat& obj, int reach) {
  require(obj.type() == CV_8U && reach >= 1, "signed_distance_near: a CV_8U mask and a reach >= 1");
  // stamping costs the outline's length times the disc: beyond a reach of 16 px the
  // whole-image transform is cheaper (distances beyond the reach set as stamping leaves them)
  const float far = static_cast<float>(reach) + 0.5f, last = static_cast<float>(reach) - 0.5f;
  if (reach > 16) {
    cv::Mat sd = signed_distance(obj != 0);
    sd.setTo(far, sd > last);
    sd.setTo(-far, sd < -last);
    return sd;
  }
  const int W = obj.cols, H = obj.rows;
  // squared distance of each pixel to the nearest pixel of the other side, stamped from the
  // pixels with a 4-neighbour of the other side (the nearest pixel of the other side always
  // has one: a step towards the pixel along its longer axis is closer)
  struct Offset {
    int dx, dy, dd;  // dd: squared length
  };
  std::vector<Offset> disc;
  for (int dy = -reach; dy <= reach; ++dy)
    for (int dx = -reach; dx <= reach; ++dx)
      if (dx * dx + dy * dy <= reach * reach && (dx || dy)) disc.push_back({dx, dy, dx * dx + dy * dy});
  std::vector<int> d2(static_cast<size_t>(W) * H, std::numeric_limits<int>::max());
  for (int y = 0; y < H; ++y) {
    const std::uint8_t* r = obj.ptr<std::uint8_t>(y);
    const std::uint8_t* up = y > 0 ? obj.ptr<std::uint8_t>(y - 1) : nullptr;
    const std::uint8_t* dn = y + 1 < H ? obj.ptr<std::uint8_t>(y + 1) : nullptr;
    for (int x = 0; x < W; ++x) {
      const bool in = r[x] != 0;
      if (!((x > 0 && (r[x - 1] != 0) != in) || (x + 1 < W && (r[x + 1] != 0) != in) || (up && (up[x] != 0) != in) ||
            (dn && (dn[x] != 0) != in)))
        continue;
      const bool whole = x >= reach && x + reach < W && y >= reach && y + reach < H;
      const int p = y * W + x;
      for (const Offset& o : disc) {
        if (!whole && (x + o.dx < 0 || x + o.dx >= W || y + o.dy < 0 || y + o.dy >= H)) continue;
        const int q = p + o.dy * W + o.dx;
        if ((obj.data[q] != 0) != in && o.dd < d2[q]) d2[q] = o.dd;
      }
    }
  }
  cv::Mat sd(H, W, CV_32F);
  for (int y = 0; y < H; ++y) {
    const std::uint8_t* r = obj.ptr<std::uint8_t>(y);
    float* o = sd.ptr<float>(y);
    for (int x = 0; x < W; ++x) {
      const int dd = d2[static_cast<size_t>(y) * W + x];
      const float d = dd == std::numeric_limits<int>::max() ? far : std::sqrt(static_cast<float>(dd)) - 0.5f;
      o[x] = r[x] ? -d : d;
    }
  }
  return sd;
}

ViewRaster rasterize_view(const TriMesh& mesh, const Camera& cam, const cv::Mat& sil, int sd_reach) {
  ViewRaster r;
  RasterOptions ro;
  ro.cull_back = true;  // closed outward mesh: back faces are always hidden behind front ones
  r.raster = rasterize(mesh, cam, ro);
  r.depth = r.raster.depth;
  // Beyond sd_reach of the covered pixels everything is empty and sd is the far value: the
  // distances and counts are computed in the covered box grown by more than the reach.
  const int grow = sd_reach + 2;
  const cv::Rect& box = r.raster.covered_box;
  const cv::Rect roi = box.empty() ? cv::Rect()
                                   : cv::Rect(box.x - grow, box.y - grow, box.width + 2 * grow, box.height + 2 * grow) &
                                         cv::Rect(0, 0, cam.width, cam.height);
  r.sd.create(cam.height, cam.width, CV_32F);
  std::fill_n(r.sd.ptr<float>(), static_cast<std::size_t>(cam.width) * cam.height, static_cast<float>(sd_reach) + 0.5f);
  cv::Mat covered;
  if (!roi.empty()) {
    covered = r.raster.tri(roi) >= 0;
    signed_distance_near(covered, sd_reach).copyTo(r.sd(roi));
    r.covered = cv::countNonZero(covered);
  }
  if (!sil.empty()) {
    r.agree = roi.empty() ? 0 : cv::countNonZero(covered & (sil(roi) > 127));
    r.either = r.covered + cv::countNonZero(sil > 127) - r.agree;
  }
  return r;
}

std::vector<Eigen::Vector3d> vertex_normals(const std::vector<Eigen::Vector3d>& V,
                                            const std::vector<Eigen::Vector3i>& F) {
  std::vector<Eigen::Vector3d> N(V.size(), Eigen::Vector3d::Zero());
  for (const auto& t : F) {
    const Eigen::Vector3d c = (V[t[1]] - V[t[0]]).cross(V[t[2]] - V[t[0]]);
    for (int k = 0; k < 3; ++k) N[t[k]] += c;
  }
  for (auto& n : N) {
    const double l = n.norm();
    n = l > 0 ? Eigen::Vector3d(n / l) : Eigen::Vector3d::Zero();
  }
  return N;
}

std::vector<double> vertex_footprints(const std::vector<Eigen::Vector3d>& V, const std::vector<Camera>& cams,
                                      double fallback) {
  const int nv = static_cast<int>(V.size());
  std::vector<double> fp(nv, fallback);
#pragma omp parallel for schedule(static)
  for (int v = 0; v < nv; ++v) {
    double best = std::numeric_limits<double>::infinity();
    for (const auto& c : cams) {
      // c.sees(X) without computing the depth twice
      const double d = c.depth(V[v]);
      if (d <= 0) continue;
      const Eigen::Vector2d p = c.project(V[v]);
      if (p.x() >= 0.0 && p.y() >= 0.0 && p.x() <= c.width - 1 - 0.0 && p.y() <= c.height - 1 - 0.0)
        best = std::min(best, d / c.focal());
    }
    if (std::isfinite(best)) fp[v] = best;
  }
  return fp;
}

namespace {
// X's pixel p in view c (false when behind the camera or outside the image), and its depth d.
inline bool pixel_of(const Eigen::Vector3d& X, const Camera& c, Eigen::Vector2d& p, double& d) {
  d = c.depth(X);
  if (!(d > 0)) return false;
  p = c.project(X);  // c.sees(X), projecting once
  return p.x() >= 0.0 && p.y() >= 0.0 && p.x() <= c.width - 1 - 0.0 && p.y() <= c.height - 1 - 0.0;
}
// Whether a point of depth d at pixel p is at most tol_px pixel footprints behind the z-buffer.
inline bool unoccluded(const Camera& c, const ViewRaster& r, double tol_px, const Eigen::Vector2d& p, double d) {
  const int x = static_cast<int>(round_nearest(p.x())), y = static_cast<int>(round_nearest(p.y()));
  return !(d > r.depth.at<float>(y, x) + tol_px * d / c.focal());
}
// Vertex X in front of view c, inside its image and not behind the view's z-buffer by more
// than tol_px pixel footprints; p receives its projection.
inline bool visible_in(const Eigen::Vector3d& X, const Camera& c, const ViewRaster& r, double tol_px,
                       Eigen::Vector2d& p) {
  double d;
  return pixel_of(X, c, p, d) && unoccluded(c, r, tol_px, p, d);
}
}  // namespace

std::vector<std::uint8_t> vertex_visibility(const std::vector<Eigen::Vector3d>& V, const std::vector<Camera>& cams,
                                            const std::vector<ViewRaster>& rasters, double tol_px) {
  const int nv = static_cast<int>(V.size()), nc = static_cast<int>(cams.size());
  std::vector<std::uint8_t> vis(static_cast<size_t>(nv) * nc, 0);
#pragma omp parallel for schedule(static)
  for (int v = 0; v < nv; ++v)
    for (int i = 0; i < nc; ++i) {
      Eigen::Vector2d p;
      vis[static_cast<size_t>(v) * nc + i] = visible_in(V[v], cams[i], rasters[i], tol_px, p);
    }
  return vis;
}

std::vector<Eigen::Vector3d> smooth_force(const std::vector<Eigen::Vector3d>& V, const Topology& topo,
                                          const std::vector<Eigen::Vector3d>& N, const Options& opt, bool fairing) {
  const int nv = static_cast<int>(V.size());
  std::vector<Eigen::Vector3d> L(nv, Eigen::Vector3d::Zero()), out(nv, Eigen::Vector3d::Zero());
  const auto umbrella = [&](const std::vector<Eigen::Vector3d>& X, int v) {
    const int s = topo.nbr_start[v], e = topo.nbr_start[v + 1];
    if (e == s) return Eigen::Vector3d(Eigen::Vector3d::Zero());
    Eigen::Vector3d m = Eigen::Vector3d::Zero();
    for (int q = s; q < e; ++q) m += X[topo.nbr[q]];
    return Eigen::Vector3d(m / (e - s) - X[v]);
  };
#pragma omp parallel for schedule(static)
  for (int v = 0; v < nv; ++v) L[v] = umbrella(V, v);
  if (fairing && opt.smooth_fairing > 0) {
    std::vector<double> ln(nv), mean(nv);
    for (int v = 0; v < nv; ++v) ln[v] = mean[v] = L[v].dot(N[v]);
    ring_average(mean, topo, kFairingRounds);
#pragma omp parallel for schedule(static)
    for (int v = 0; v < nv; ++v) {
      const Eigen::Vector3d& n = N[v];
      out[v] = opt.smooth_tangent * (L[v] - ln[v] * n) + opt.smooth_normal * ln[v] * n +
               opt.smooth_fairing * (ln[v] - mean[v]) * n;
    }
    return out;
  }
#pragma omp parallel for schedule(static)
  for (int v = 0; v < nv; ++v) {
    const Eigen::Vector3d& n = N[v];
    const double ln = L[v].dot(n);
    const Eigen::Vector3d L2 = umbrella(L, v);
    out[v] = opt.smooth_tangent * (L[v] - ln * n) + opt.smooth_normal * ln * n -
             opt.smooth_bilaplacian * L2.dot(n) * n;
  }
  return out;
}

std::vector<Eigen::Vector3d> silhouette_force(const std::vector<Eigen::Vector3d>& V,
                                              const std::vector<Eigen::Vector3d>& N, const std::vector<double>& fp,
                                              const std::vector<Camera>& cams, const std::vector<cv::Mat>& sd,
                                              const std::vector<ViewRaster>& rasters, const Options& opt,
                                              std::vector<int>& rim_views) {
  const int nv = static_cast<int>(V.size()), nc = static_cast<int>(cams.size());
  std::vector<Eigen::Vector3d> out(nv, Eigen::Vector3d::Zero());
  rim_views.assign(nv, 0);
#pragma omp parallel for schedule(dynamic, 512)
  for (int v = 0; v < nv; ++v) {
    const Eigen::Vector3d& X = V[v];
    const Eigen::Vector3d& n = N[v];
    if (n.squaredNorm() == 0) continue;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int count = 0;
    for (int i = 0; i < nc; ++i) {
      if (sd[i].empty()) continue;
      const Camera& c = cams[i];
      const Eigen::Vector3d r = (X - c.centre()).normalized();
      const double cr = n.dot(r);
      if (std::abs(cr) >= opt.rim_cos) continue;
      Eigen::Vector2d p;  // visibility only where the rest is needed: most views are not rims
      double depth;
      if (!pixel_of(X, c, p, depth)) continue;
      const int x = static_cast<int>(round_nearest(p.x())), y = static_cast<int>(round_nearest(p.y()));
      const float sd_mesh = rasters[i].sd.at<float>(y, x);
      if (sd_mesh < -opt.sil_band_px) continue;  // not near the mesh's own silhouette boundary
      if (!unoccluded(c, rasters[i], opt.visibility_tol_px, p, depth)) continue;
      const Eigen::Vector3d np = (n - cr * r).normalized();
      const double step = fp[v];
      const Eigen::Vector2d u = (c.project(X + step * np) - p) / step;  // pixels per world unit along np
      const double lu = u.norm();
      if (!(lu > 0)) continue;
      float s0, sx0, sx1, sy0, sy1;
      const cv::Mat& m = sd[i];
      if (!sample_bilinear(m, p.x(), p.y(), s0) || !sample_bilinear(m, p.x() - 1, p.y(), sx0) ||
          !sample_bilinear(m, p.x() + 1, p.y(), sx1) || !sample_bilinear(m, p.x(), p.y() - 1, sy0) ||
          !sample_bilinear(m, p.x(), p.y() + 1, sy1))
        continue;
      const Eigen::Vector2d g(0.5 * (sx1 - sx0), 0.5 * (sy1 - sy0));
      const double slope = g.dot(u);  // d(signed distance) / d(move along np)
      if (!(slope > 0.3 * lu)) continue;
      // The mesh's contour at this pixel should move onto the true one: the discrepancy
      // between the two signed distances (not the true one alone: vertices of the rim band
      // project inside the contour by construction).
      // (binary masks place their contours only to about half a pixel: smaller
      // disagreements are left to the photometric force)
      double diff = s0 - sd_mesh;
      diff = diff > 0 ? std::max(0.0, diff - opt.sil_tolerance_px) : std::min(0.0, diff + opt.sil_tolerance_px);
      double delta = -diff / slope;
      const double lim = opt.sil_max_px / lu;
      delta = std::clamp(delta, -lim, lim);
      sum += delta * np;
      ++count;
    }
    if (count > 0) out[v] = sum / count;
    rim_views[v] = count;
  }
  return out;
}

std::vector<double> silhouette_spread(const std::vector<Eigen::Vector3d>& V, const std::vector<Eigen::Vector3d>& N,
                                      const std::vector<double>& fp, const Topology& topo,
                                      const std::vector<Eigen::Vector3d>& fsil, const SpreadOptions& o) {
  const int nv = static_cast<int>(V.size());
  std::vector<double> out(nv, 0.0);
  if (!(o.reach_px > 0)) return out;
  // ring by ring outwards from the spreading corrections: each reached vertex carries the
  // mean correction of the neighbours it was reached from and its shortest distance (pixels
  // of the level); every corrected vertex is reached from the start (it moves by its own)
  std::vector<double> carried(nv, 0.0), dist(nv, 0.0);
  std::vector<char> reached(nv, 0);
  std::vector<int> ring;
  for (int v = 0; v < nv; ++v) {
    if (fsil[v].squaredNorm() == 0) continue;
    reached[v] = 1;
    carried[v] = fsil[v].dot(N[v]);
    if (carried[v] > 0 && fsil[v].norm() < o.max_source_px * fp[v]) ring.push_back(v);
  }
  std::vector<int> next;
  std::vector<double> sum(nv, 0.0), best(nv, 0.0);
  std::vector<int> count(nv, 0);
  while (!ring.empty()) {  // serial, in vertex order: the result does not depend on threads
    next.clear();
    for (const int q : ring)
      for (int k = topo.nbr_start[q]; k < topo.nbr_start[q + 1]; ++k) {
        const int v = topo.nbr[k];
        if (reached[v] || !(fp[v] > 0)) continue;
        const double d = dist[q] + (V[v] - V[q]).norm() / (fp[v] * o.level_scale);
        if (d >= o.reach_px) continue;
        if (count[v] == 0) next.push_back(v), best[v] = d;
        sum[v] += carried[q], ++count[v], best[v] = std::min(best[v], d);
      }
    std::sort(next.begin(), next.end());
    for (const int v : next) {
      carried[v] = sum[v] / count[v], dist[v] = best[v], reached[v] = 1;
      out[v] = carried[v] * (1.0 - dist[v] / o.reach_px);
    }
    ring.swap(next);
  }
  return out;
}

}  // namespace tetmvs::deform
