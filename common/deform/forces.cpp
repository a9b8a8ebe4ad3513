#include "common/deform/forces.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "common/image.h"
#include "common/photo/camera_select.h"
#include "common/photo/orientations.h"
#include "common/photo/patch.h"
#include "common/photo/scratch.h"
#include "common/trimesh/raster.h"

namespace tetmvs::deform {

cv::Mat signed_distance(const cv::Mat& mask) {
  cv::Mat obj = mask > 127, bg = mask <= 127;
  cv::Mat d_in, d_out;
  // distanceTransform: distance of each non-zero pixel to the nearest zero pixel
  cv::distanceTransform(obj, d_in, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  cv::distanceTransform(bg, d_out, cv::DIST_L2, cv::DIST_MASK_PRECISE);
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

ViewRaster rasterize_view(const TriMesh& mesh, const Camera& cam, const cv::Mat& sil) {
  ViewRaster r;
  const Raster ras = rasterize(mesh, cam, {});
  r.depth = ras.depth;
  const cv::Mat covered = ras.tri >= 0;
  r.sd = signed_distance(covered);
  r.covered = cv::countNonZero(covered);
  if (!sil.empty()) {
    const cv::Mat truth = sil > 127;
    r.agree = cv::countNonZero(covered & truth);
    r.either = cv::countNonZero(covered | truth);
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
    for (const auto& c : cams)
      if (c.sees(V[v])) best = std::min(best, c.depth(V[v]) / c.focal());
    if (std::isfinite(best)) fp[v] = best;
  }
  return fp;
}

std::vector<std::uint8_t> vertex_visibility(const std::vector<Eigen::Vector3d>& V, const std::vector<Camera>& cams,
                                            const std::vector<ViewRaster>& rasters, double tol_px) {
  const int nv = static_cast<int>(V.size()), nc = static_cast<int>(cams.size());
  std::vector<std::uint8_t> vis(static_cast<size_t>(nv) * nc, 0);
#pragma omp parallel for schedule(static)
  for (int v = 0; v < nv; ++v)
    for (int i = 0; i < nc; ++i) {
      const Camera& c = cams[i];
      const double d = c.depth(V[v]);
      if (!(d > 0) || !c.sees(V[v])) continue;
      const Eigen::Vector2d p = c.project(V[v]);
      const int x = static_cast<int>(std::lround(p.x())), y = static_cast<int>(std::lround(p.y()));
      const float z = rasters[i].depth.at<float>(y, x);
      vis[static_cast<size_t>(v) * nc + i] = !(d > z + tol_px * d / c.focal());
    }
  return vis;
}

std::vector<Eigen::Vector3d> smooth_force(const std::vector<Eigen::Vector3d>& V, const Topology& topo,
                                          const std::vector<Eigen::Vector3d>& N, const Options& opt) {
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
                                              const std::vector<ViewRaster>& rasters,
                                              const std::vector<std::uint8_t>& vis, const Options& opt,
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
      if (sd[i].empty() || !vis[static_cast<size_t>(v) * nc + i]) continue;
      const Camera& c = cams[i];
      const Eigen::Vector3d r = (X - c.centre()).normalized();
      const double cr = n.dot(r);
      if (std::abs(cr) >= opt.rim_cos) continue;
      const Eigen::Vector2d p = c.project(X);
      const int x = static_cast<int>(std::lround(p.x())), y = static_cast<int>(std::lround(p.y()));
      const float sd_mesh = rasters[i].sd.at<float>(y, x);
      if (sd_mesh < -opt.sil_band_px) continue;  // not near the mesh's own silhouette boundary
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
      double delta = -(s0 - sd_mesh) / slope;
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

std::vector<Eigen::Vector3d> texture_force(const std::vector<Eigen::Vector3d>& V,
                                           const std::vector<Eigen::Vector3d>& N, const std::vector<double>& fp,
                                           const photo::Views& views, const std::vector<std::uint8_t>& vis,
                                           const Options& opt, const photo::Options& photo_opt,
                                           std::vector<TextureProbe>& probes) {
  photo::Options popt = photo_opt;
  popt.cone_deg = opt.texture_cone_deg;
  const int nv = static_cast<int>(V.size()), nc = views.size();
  std::vector<Eigen::Vector3d> out(nv, Eigen::Vector3d::Zero());
  probes.assign(nv, TextureProbe{});
  const int J = static_cast<int>(std::lround(opt.texture_range_px / opt.texture_step_px));
  const int ns = 2 * J + 1;
#pragma omp parallel
  {
    photo::Scratch scratch;
    std::vector<float> sc(ns);
#pragma omp for schedule(dynamic, 64)
    for (int v = 0; v < nv; ++v) {
      const Eigen::Vector3d& n = N[v];
      if (n.squaredNorm() == 0) continue;
      const Eigen::Vector3d a1 = photo::stable_perpendicular(n);
      const Eigen::Vector3d a2 = n.cross(a1);
      const auto score_at = [&](double t) {
        photo::detail::prepare_centre(views, V[v] + t * n, popt, scratch);
        if (opt.occlusion && !vis.empty())
          for (int i = 0; i < nc; ++i)
            if (!vis[static_cast<size_t>(v) * nc + i]) scratch.cache[i].usable = false;
        photo::PatchResult r;
        photo::detail::score_prepared(views, n, a1, &a2, popt, scratch, r);
        return r;
      };
      // Offsets in "parallax pixels": a move t along n shifts what the views see on the
      // patch plane relative to each other by t * |w_a - w_b|, w = in-plane part of the
      // direction to the camera over its normal part. With close cameras (dense rings)
      // the same depth resolution needs longer steps.
      const photo::PatchResult r0 = score_at(0.0);
      if (!r0.valid()) continue;
      double par = 0;
      int pairs = 0;
      for (int a = 0; a < r0.num_views; ++a)
        for (int b = a + 1; b < r0.num_views; ++b) {
          const auto w = [&](int view) {
            const Eigen::Vector3d r = (views[view].centre - V[v]).normalized();
            const double c = std::max(r.dot(n), 0.05);
            return Eigen::Vector3d((r - r.dot(n) * n) / c);
          };
          par += (w(r0.views[a]) - w(r0.views[b])).norm();
          ++pairs;
        }
      par = std::clamp(pairs ? par / pairs : 1.0, opt.texture_min_parallax, 1.0);
      const double unit = fp[v] / par;  // world length of one parallax pixel along n
      int best = -1;
      for (int j = 0; j < ns; ++j) {
        const photo::PatchResult r = j == J ? r0 : score_at((j - J) * opt.texture_step_px * unit);
        sc[j] = r.valid() ? r.score : photo::kNoScore;
        if (r.valid() && (best < 0 || sc[j] > sc[best])) best = j;
      }
      if (best < 0) continue;
      TextureProbe& pr = probes[v];
      pr.best_score = sc[best];
      double off = best - J;
      if (best > 0 && best < ns - 1 && sc[best - 1] != photo::kNoScore && sc[best + 1] != photo::kNoScore) {
        const double sm = sc[best - 1], s0 = sc[best], sp = sc[best + 1];
        const double den = sm - 2 * s0 + sp;
        if (den < 0) off += std::clamp(0.5 * (sm - sp) / den, -0.5, 0.5);
      }
      off *= opt.texture_step_px;
      pr.offset_px = static_cast<float>(off * unit / fp[v]);
      // A clear peak: the profile drops by the contrast on both sides of it.
      float lo_left = 2.f, lo_right = 2.f;
      for (int j = 0; j < best; ++j)
        if (sc[j] != photo::kNoScore) lo_left = std::min(lo_left, sc[j]);
      for (int j = best + 1; j < ns; ++j)
        if (sc[j] != photo::kNoScore) lo_right = std::min(lo_right, sc[j]);
      const float contrast = sc[best] - std::max(lo_left, lo_right);
      if (sc[best] >= opt.texture_min_score && contrast >= opt.texture_min_contrast) {
        pr.applied = true;
        out[v] = off * unit * n;
        pr.offset_px = static_cast<float>(off * unit / fp[v]);
      }
    }
  }
  return out;
}

}  // namespace tetmvs::deform
