#include "common/deform/forces.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "common/image.h"
#include "common/photo/camera_select.h"
#include "common/photo/ncc.h"
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
  RasterOptions ro;
  ro.cull_back = true;  // closed outward mesh: back faces are always hidden behind front ones
  const Raster ras = rasterize(mesh, cam, ro);
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

std::vector<double> mean_curvature(const std::vector<Eigen::Vector3d>& V, const std::vector<Eigen::Vector3d>& N,
                                   const Topology& topo, int rounds) {
  const int nv = static_cast<int>(V.size());
  // normals averaged over the 1-ring `rounds` times: vertex normals of a rough mesh
  // scatter by degrees, which 1-ring differences of ~1 px turn into curvatures of 1/(10 px)
  std::vector<Eigen::Vector3d> Ns = N, Nt(nv);
  for (int r = 0; r < rounds; ++r) {
#pragma omp parallel for schedule(static)
    for (int v = 0; v < nv; ++v) {
      Eigen::Vector3d sum = Ns[v];
      for (int q = topo.nbr_start[v]; q < topo.nbr_start[v + 1]; ++q) sum += Ns[topo.nbr[q]];
      const double l = sum.norm();
      Nt[v] = l > 0 ? Eigen::Vector3d(sum / l) : Ns[v];
    }
    Ns.swap(Nt);
  }
  std::vector<double> H(nv, 0.0), tmp(nv, 0.0);
#pragma omp parallel for schedule(static)
  for (int v = 0; v < nv; ++v) {
    double sum = 0;
    int cnt = 0;
    for (int q = topo.nbr_start[v]; q < topo.nbr_start[v + 1]; ++q) {
      const int j = topo.nbr[q];
      const Eigen::Vector3d e = V[j] - V[v];
      const double l2 = e.squaredNorm();
      if (!(l2 > 0)) continue;
      sum += (Ns[j] - Ns[v]).dot(e) / l2;
      ++cnt;
    }
    H[v] = cnt ? sum / cnt : 0.0;
  }
  for (int r = 0; r < rounds; ++r) {
#pragma omp parallel for schedule(static)
    for (int v = 0; v < nv; ++v) {
      double sum = H[v];
      for (int q = topo.nbr_start[v]; q < topo.nbr_start[v + 1]; ++q) sum += H[topo.nbr[q]];
      tmp[v] = sum / (1 + topo.nbr_start[v + 1] - topo.nbr_start[v]);
    }
    H.swap(tmp);
  }
  return H;
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

std::vector<std::uint8_t> vertex_visibility(const std::vector<Eigen::Vector3d>& V, const std::vector<Camera>& cams,
                                            const std::vector<ViewRaster>& rasters, double tol_px) {
  const int nv = static_cast<int>(V.size()), nc = static_cast<int>(cams.size());
  std::vector<std::uint8_t> vis(static_cast<size_t>(nv) * nc, 0);
#pragma omp parallel for schedule(static)
  for (int v = 0; v < nv; ++v)
    for (int i = 0; i < nc; ++i) {
      const Camera& c = cams[i];
      const double d = c.depth(V[v]);
      if (!(d > 0)) continue;
      const Eigen::Vector2d p = c.project(V[v]);  // c.sees(X), projecting once
      if (!(p.x() >= 0.0 && p.y() >= 0.0 && p.x() <= c.width - 1 - 0.0 && p.y() <= c.height - 1 - 0.0)) continue;
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

namespace {

// Grey image of one view for the texture probe: float rows, bounds for bilinear sampling.
struct GreyView {
  const float* data = nullptr;
  size_t stride = 0;  // floats per row
  int w = 0, h = 0;
  bool inside(double u, double v) const { return u >= 0 && v >= 0 && u < w - 1 && v < h - 1; }
  float at(double u, double v) const {
    const int x = static_cast<int>(u), y = static_cast<int>(v);
    const float a = static_cast<float>(u - x), b = static_cast<float>(v - y);
    const float* r0 = data + y * stride + x;
    const float* r1 = r0 + stride;
    return (1 - b) * ((1 - a) * r0[0] + a * r0[1]) + b * ((1 - a) * r1[0] + a * r1[1]);
  }
};

// The mu x mu patch on the plane through X (axes e1, e2: world steps between samples)
// seen in view `view`: projected with the affine approximation of the projection at X
// (the patch spans ~mu pixels at ~1000 pixels of depth: the error is far below a
// hundredth of a pixel). False when a sample falls outside the image.
bool sample_patch(const photo::View& view, const GreyView& g, const Eigen::Vector3d& X, const Eigen::Vector3d& e1,
                  const Eigen::Vector3d& e2, int mu, float* out) {
  const Eigen::Vector3d h = view.project_h(X);
  if (!(h.z() > 0)) return false;
  const double iz = 1.0 / h.z(), u0 = h.x() * iz, v0 = h.y() * iz;
  const Eigen::Vector3d d1 = view.project_dir(e1), d2 = view.project_dir(e2);
  const double u1 = (d1.x() - u0 * d1.z()) * iz, v1 = (d1.y() - v0 * d1.z()) * iz;
  const double u2 = (d2.x() - u0 * d2.z()) * iz, v2 = (d2.y() - v0 * d2.z()) * iz;
  const double c = mu / 2;
  // the four corners bound the (affine) patch
  for (const double si : {-c, c})
    for (const double sj : {-c, c})
      if (!g.inside(u0 + si * u1 + sj * u2, v0 + si * v1 + sj * v2)) return false;
  // rows start in double, samples step in float (error ~1e-4 px at 640 px)
  const float fu1 = static_cast<float>(u1), fv1 = static_cast<float>(v1);
  for (int j = 0; j < mu; ++j) {
    const float uj = static_cast<float>(u0 + (j - c) * u2 - c * u1);
    const float vj = static_cast<float>(v0 + (j - c) * v2 - c * v1);
    float* o = out + j * mu;
    for (int i = 0; i < mu; ++i) {
      const float u = uj + static_cast<float>(i) * fu1, v = vj + static_cast<float>(i) * fv1;
      // (the corners are inside in double; float rounding could reach the last row/column)
      const int x = std::min(static_cast<int>(u), g.w - 2), y = std::min(static_cast<int>(v), g.h - 2);
      const float a = u - static_cast<float>(x), b = v - static_cast<float>(y);
      const float* r0 = g.data + static_cast<size_t>(y) * g.stride + x;
      const float* r1 = r0 + g.stride;
      o[i] = (1 - b) * ((1 - a) * r0[0] + a * r0[1]) + b * ((1 - a) * r1[0] + a * r1[1]);
    }
  }
  return true;
}

// photo::normalize_patch(_detrended) and ncc_normalized (ncc.h) with the sums in SIMD
// lanes: the same formulas, the additions in another (fixed) order.
struct PatchKernel {
  int n = 0;
  float min_std = 0, ramp = 0;
  bool detrend = false;
  std::vector<float> t1, t2;  // offsets of each sample along the two axes (i - c, j - c)
  PatchKernel(int mu, bool detrend_, float min_std_) : n(mu * mu), min_std(min_std_), detrend(detrend_) {
    const int c = mu / 2;
    t1.resize(n);
    t2.resize(n);
    for (int j = 0; j < mu; ++j)
      for (int i = 0; i < mu; ++i) {
        t1[j * mu + i] = static_cast<float>(i - c);
        t2[j * mu + i] = static_cast<float>(j - c);
      }
    ramp = photo::ramp_norm2(mu, mu);
  }
  // In place; false (and zeros) when the residual is constant.
  bool normalize(float* x) const {
    float mean = 0.f;
#pragma omp simd reduction(+ : mean)
    for (int i = 0; i < n; ++i) mean += x[i];
    mean /= static_cast<float>(n);
    float ss = 0.f;
    if (detrend) {
      const float* a = t1.data();
      const float* b = t2.data();
      float s1 = 0.f, s2 = 0.f;
#pragma omp simd reduction(+ : s1, s2)
      for (int i = 0; i < n; ++i) {
        const float v = x[i] - mean;
        x[i] = v;
        s1 += v * a[i];
        s2 += v * b[i];
      }
      const float g1 = s1 / ramp, g2 = s2 / ramp;
#pragma omp simd reduction(+ : ss)
      for (int i = 0; i < n; ++i) {
        const float r = (x[i] - g1 * a[i]) - g2 * b[i];
        x[i] = r;
        ss += r * r;
      }
    } else {
#pragma omp simd reduction(+ : ss)
      for (int i = 0; i < n; ++i) {
        const float v = x[i] - mean;
        x[i] = v;
        ss += v * v;
      }
    }
    if (!(ss > static_cast<float>(n) * min_std * min_std) || ss <= 0.f) {
      for (int i = 0; i < n; ++i) x[i] = 0.f;
      return false;
    }
    const float inv = 1.f / std::sqrt(ss);
#pragma omp simd
    for (int i = 0; i < n; ++i) x[i] *= inv;
    return true;
  }
  float ncc(const float* a, const float* b) const {
    float s = 0.f;
#pragma omp simd reduction(+ : s)
    for (int i = 0; i < n; ++i) s += a[i] * b[i];
    return std::clamp(s, -1.f, 1.f);
  }
};

}  // namespace

std::vector<Eigen::Vector3d> texture_force(const std::vector<Eigen::Vector3d>& V,
                                           const std::vector<Eigen::Vector3d>& N, const std::vector<double>& fp,
                                           const photo::Views& views, const std::vector<std::uint8_t>& vis,
                                           const std::vector<std::uint8_t>& active, const Options& opt,
                                           const photo::Options& popt, std::vector<TextureProbe>& probes,
                                           const std::vector<double>& curvature, double px_scale) {
  const int nv = static_cast<int>(V.size()), nc = views.size();
  std::vector<Eigen::Vector3d> out(nv, Eigen::Vector3d::Zero());
  probes.assign(nv, TextureProbe{});
  std::vector<GreyView> grey(nc);
  for (int i = 0; i < nc; ++i) {
    const cv::Mat& g = views[i].grey;
    grey[i] = {g.ptr<float>(), g.step1(), g.cols, g.rows};
  }
  const int mu = opt.texture_mu, ns = mu * mu;
  const int M = opt.texture_partners;
  const double cos_cone = std::cos(opt.texture_cone_deg * M_PI / 180.0);
  const double cos_bmin = std::cos(opt.texture_baseline_min_deg * M_PI / 180.0);
  const double cos_bmax = std::cos(opt.texture_baseline_max_deg * M_PI / 180.0);
  const PatchKernel kernel(mu, popt.detrend, static_cast<float>(popt.min_std));
  double m2 = 0;  // mean squared sample offset along one patch axis, in samples
  for (int i = 0; i < mu; ++i) m2 += (i - mu / 2) * (i - mu / 2);
  m2 /= mu;
  // Coarse offsets every texture_coarse_px over -range..range; around the best, halving
  // steps down to texture_step_px (each level keeps the best of the peak and its two
  // neighbours); at the finest level a parabola through the peak and its neighbours.
  // Offsets are integer multiples ("keys") of the finest step hmin.
  int L = 0;
  while (opt.texture_coarse_px / (1 << (L + 1)) >= opt.texture_step_px * (1 - 1e-9) && L < 8) ++L;
  const double hmin = opt.texture_coarse_px / (1 << L);
  const int Jc = std::max(1, static_cast<int>(std::lround(opt.texture_range_px / opt.texture_coarse_px)));
  // wide search (texture_far_px): the coarse profile extended to -far..far when the near
  // one shows no clear peak; prof[j] is the offset (j - Jf) coarse steps
  const int Jf = std::max(Jc, static_cast<int>(std::lround(opt.texture_far_px / opt.texture_coarse_px)));
  const int nco = 2 * Jf + 1;
#pragma omp parallel
  {
    std::vector<float> buf(static_cast<size_t>(M + 1) * ns);
    std::vector<float> prof(nco);
    std::vector<std::pair<int, float>> cache;  // (key, score) evaluated for the current vertex
    std::vector<std::pair<double, int>> cand;
    int sel[64];
#pragma omp for schedule(dynamic, 256)
    for (int v = 0; v < nv; ++v) {
      if (!active.empty() && !active[v]) continue;
      probes[v].probed = true;
      const Eigen::Vector3d& n = N[v];
      if (n.squaredNorm() == 0) continue;
      const Eigen::Vector3d& X = V[v];
      // Reference: the visible view that faces the vertex most; partners: the visible
      // views at a baseline angle of texture_baseline_min..max_deg from the reference,
      // most frontal first.
      cand.clear();
      for (int i = 0; i < nc; ++i) {
        if (!vis.empty() && !vis[static_cast<size_t>(v) * nc + i]) continue;
        const double c = n.dot((views[i].centre - X).normalized());
        if (c >= cos_cone) cand.emplace_back(-c, i);
      }
      if (static_cast<int>(cand.size()) < 1 + opt.texture_min_partners) continue;
      std::sort(cand.begin(), cand.end());
      const int ref = cand[0].second;
      const Eigen::Vector3d dref = (views[ref].centre - X).normalized();
      int np = 0;
      for (size_t q = 1; q < cand.size() && np < M; ++q) {
        const double cb = dref.dot((views[cand[q].second].centre - X).normalized());
        if (cb <= cos_bmin && cb >= cos_bmax) sel[np++] = cand[q].second;
      }
      if (np < opt.texture_min_partners) continue;
      const double unit = fp[v] * px_scale;  // world length of one pixel (of these views) along n
      const double spacing = views[ref].project_h(X).z() * views[ref].inv_focal;
      const Eigen::Vector3d a1 = photo::stable_perpendicular(n) * spacing;
      const Eigen::Vector3d a2 = n.cross(a1);
      const auto normalize = [&](float* x) { kernel.normalize(x); };
      // Score at offset t (pixels): mean NCC of the reference with its partners.
      const auto score_at = [&](double t) -> float {
        const Eigen::Vector3d Xt = X + (t * unit) * n;
        float* r = buf.data();
        if (!sample_patch(views[ref], grey[ref], Xt, a1, a2, mu, r)) return photo::kNoScore;
        normalize(r);
        float sum = 0.f;
        int cnt = 0;
        for (int q = 0; q < np; ++q) {
          float* p = buf.data() + static_cast<size_t>(q + 1) * ns;
          if (!sample_patch(views[sel[q]], grey[sel[q]], Xt, a1, a2, mu, p)) continue;
          normalize(p);
          sum += kernel.ncc(r, p);
          ++cnt;
        }
        return cnt >= opt.texture_min_partners ? sum / static_cast<float>(cnt) : photo::kNoScore;
      };
      cache.clear();
      const auto get = [&](int key) -> float {
        for (const auto& c : cache)
          if (c.first == key) return c.second;
        const float sc = score_at(key * hmin);
        cache.emplace_back(key, sc);
        return sc;
      };
      // Best of the evaluated coarse offsets j0..j1 and whether it is a clear peak: the
      // profile drops by the contrast on both sides of it (-1: no score at all).
      int best = -1;
      bool clear = false;
      const auto find_peak = [&](int j0, int j1, double min_score, double min_contrast) {
        best = -1;
        for (int j = j0; j <= j1; ++j)
          if (prof[j] != photo::kNoScore && (best < 0 || prof[j] > prof[best])) best = j;
        if (best < 0) return;
        float lo_left = 2.f, lo_right = 2.f;
        for (int j = j0; j < best; ++j)
          if (prof[j] != photo::kNoScore) lo_left = std::min(lo_left, prof[j]);
        for (int j = best + 1; j <= j1; ++j)
          if (prof[j] != photo::kNoScore) lo_right = std::min(lo_right, prof[j]);
        const float contrast = prof[best] - std::max(lo_left, lo_right);
        clear = prof[best] >= min_score && contrast >= min_contrast;
      };
      for (int j = Jf - Jc; j <= Jf + Jc; ++j) prof[j] = get((j - Jf) << L);
      find_peak(Jf - Jc, Jf + Jc, opt.texture_min_score, opt.texture_min_contrast);
      if (!clear && Jf > Jc) {
        // no clear peak within -range..range (none, or at one of its ends): look farther
        for (int j = 0; j < Jf - Jc; ++j) prof[j] = get((j - Jf) << L);
        for (int j = Jf + Jc + 1; j < nco; ++j) prof[j] = get((j - Jf) << L);
        find_peak(0, nco - 1, std::max(opt.texture_min_score, opt.texture_far_min_score),
                  std::max(opt.texture_min_contrast, opt.texture_far_min_contrast));
        probes[v].far = true;
      }
      if (best < 0) continue;
      TextureProbe& pr = probes[v];
      pr.best_score = prof[best];
      if (!clear) continue;
      int kb = (best - Jf) << L;
      float sb = prof[best];
      for (int lev = L - 1; lev >= 0; --lev) {
        const int h = 1 << lev;
        const float sm = get(kb - h), sp = get(kb + h);
        if (sm != photo::kNoScore && sm > sb && !(sp != photo::kNoScore && sp > sm)) {
          kb -= h;
          sb = sm;
        } else if (sp != photo::kNoScore && sp > sb) {
          kb += h;
          sb = sp;
        }
      }
      double off = kb * hmin;
      // the parabola's neighbours (one step of hmin; at L = 0 the coarse neighbours)
      const float fm = get(kb - 1), fp = get(kb + 1);
      if (fm != photo::kNoScore && fp != photo::kNoScore) {
        const double den = fm - 2.0 * sb + fp;
        if (den < 0) off += std::clamp(0.5 * (fm - fp) / den, -0.5, 0.5) * hmin;
      }
      // the sag of the curved surface under the plane patch (see forces.h)
      if (!curvature.empty()) off += curvature[v] * m2 * spacing * spacing / unit;
      pr.best_score = sb;
      pr.applied = true;
      pr.offset_px = static_cast<float>(off);
      out[v] = (off * unit) * n;
    }
  }
  return out;
}

}  // namespace tetmvs::deform
