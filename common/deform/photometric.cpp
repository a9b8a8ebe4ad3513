#include "common/deform/photometric.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "common/error.h"
#include "common/trimesh/raster.h"

namespace tetmvs::deform {

namespace {

// Views i with i % kSlots == s are summed into slot s, in view order: the sums do not
// depend on the thread count.
constexpr int kSlots = 8;
// Neighbouring pixels whose depths differ by more than this many pixel footprints lie on
// either side of an occluding contour.
constexpr double kDiscontinuity = 4.0;
// Pixels this close (pixels of the level's images) to an occluding contour or the background
// are not used: the pyramid's blur mixes the two sides there.
constexpr int kCleanPx = 2;
// Grey level added to each window's standard deviation: windows with no more contrast than
// the image noise weigh little.
constexpr double kNoiseGrey = 0.005;
// Each window's terms are weighted by (c / (1 - NCC + c))^2, the derivative of the robust
// cost (1 - NCC) / (1 - NCC + c): windows that do not match (image noise on textureless
// parts, occlusions the z-buffers miss) weigh little. Textureless synthetic sphere: the
// completeness at 1.25 mm 0.992 without, 1.000 with; textured scenes unchanged.
constexpr double kRobust = 0.1;
// Faces seen more grazing than this (|cos| between normal and ray) are not used.
constexpr double kMinCos = 0.2;
// A point is seen in view j when it lies at most this many pixel footprints behind j's z-buffer.
constexpr double kDepthTolPx = 1.5;
// photometric_steps: damping on the full images (share of the median curvature) and on the
// reduced ones (share of the median curvature per pixel pair, times the vertex's pairs), rounds
// of 1-ring averaging (on a mesh whose edges are measured in the level's pixels), largest step
// (pixels of the level).
constexpr double kDamping = 0.1;
constexpr double kPairDamping = 0.2;
constexpr int kRingRounds = 2;
constexpr double kMaxStepPx = 2.0;

// Central-difference gradients of a CV_32F image (zero on the border).
void image_gradients(const cv::Mat& g, cv::Mat& gx, cv::Mat& gy) {
  gx = cv::Mat::zeros(g.size(), CV_32F);
  gy = cv::Mat::zeros(g.size(), CV_32F);
  for (int y = 1; y + 1 < g.rows; ++y) {
    const float* r = g.ptr<float>(y);
    const float* up = g.ptr<float>(y - 1);
    const float* dn = g.ptr<float>(y + 1);
    float* ox = gx.ptr<float>(y);
    float* oy = gy.ptr<float>(y);
    for (int x = 1; x + 1 < g.cols; ++x) {
      ox[x] = 0.5f * (r[x + 1] - r[x - 1]);
      oy[x] = 0.5f * (dn[x] - up[x]);
    }
  }
}

// Bilinear sample of a CV_32F image; (u, v) within [0, cols - 1) x [0, rows - 1).
inline float bilinear(const cv::Mat& m, double u, double v) {
  const int x = static_cast<int>(u), y = static_cast<int>(v);
  const float fx = static_cast<float>(u - x), fy = static_cast<float>(v - y);
  const float* r0 = m.ptr<float>(y) + x;
  const float* r1 = m.ptr<float>(y + 1) + x;
  return (1 - fy) * ((1 - fx) * r0[0] + fx * r0[1]) + fy * ((1 - fx) * r1[0] + fx * r1[1]);
}

// CV_8U mask of the pixels whose value belongs to the mesh alone: covered, with no
// background and no depth discontinuity within kCleanPx.
cv::Mat clean_pixels(const Raster& r, double focal) {
  cv::Mat bad(r.height, r.width, CV_8U, cv::Scalar(0));
  const double slope = kDiscontinuity / focal;
  for (int y = 0; y < r.height; ++y) {
    const float* z = r.depth.ptr<float>(y);
    const float* zd = y + 1 < r.height ? r.depth.ptr<float>(y + 1) : nullptr;
    std::uint8_t* b = bad.ptr<std::uint8_t>(y);
    std::uint8_t* bd = y + 1 < r.height ? bad.ptr<std::uint8_t>(y + 1) : nullptr;
    for (int x = 0; x < r.width; ++x) {
      if (!std::isfinite(z[x])) {
        b[x] = 255;
        continue;
      }
      if (x + 1 < r.width && std::abs(z[x + 1] - z[x]) > slope * z[x]) b[x] = b[x + 1] = 255;
      if (zd && std::abs(zd[x] - z[x]) > slope * z[x]) b[x] = bd[x] = 255;
    }
  }
  cv::dilate(bad, bad, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * kCleanPx + 1, 2 * kCleanPx + 1)));
  return bad == 0;
}

// Sums over w x w windows (w odd, zero outside) of K interleaved channels of a rows x cols
// image, streamed a row at a time: row(y, out) writes row y's K x cols values, sink(y, sums)
// receives row y's window sums. Running sums along the row, then down the columns, with
// only the window's rows of row sums held (cache-resident where whole-image arrays are not).
template <int K>
class BoxSums {
 public:
  template <class Row, class Sink>
  void run(int cols, int rows, int w, Row&& row, Sink&& sink) {
    const int h = w / 2;
    const size_t n = static_cast<size_t>(cols) * K;
    in_.resize(n);
    ring_.resize(n * static_cast<size_t>(w));
    col_.assign(n, 0.0);
    const auto row_sums = [&](int y) {  // window sums along row y into its ring slot
      row(y, in_.data());
      double* out = ring_.data() + n * static_cast<size_t>(y % w);
      double s[K] = {};
      for (int x = 0; x < std::min(h, cols); ++x)
        for (int c = 0; c < K; ++c) s[c] += in_[static_cast<size_t>(x) * K + c];
      for (int x = 0; x < cols; ++x) {
        if (x + h < cols)
          for (int c = 0; c < K; ++c) s[c] += in_[static_cast<size_t>(x + h) * K + c];
        for (int c = 0; c < K; ++c) out[static_cast<size_t>(x) * K + c] = s[c];
        if (x - h >= 0)
          for (int c = 0; c < K; ++c) s[c] -= in_[static_cast<size_t>(x - h) * K + c];
      }
      return out;
    };
    for (int y = 0; y < std::min(h, rows); ++y) {
      const double* r = row_sums(y);
      for (size_t k = 0; k < n; ++k) col_[k] += r[k];
    }
    for (int y = 0; y < rows; ++y) {
      if (y + h < rows) {
        const double* r = row_sums(y + h);
        for (size_t k = 0; k < n; ++k) col_[k] += r[k];
      }
      sink(y, static_cast<const double*>(col_.data()));
      if (y - h >= 0) {
        const double* r = ring_.data() + n * static_cast<size_t>((y - h) % w);
        for (size_t k = 0; k < n; ++k) col_[k] -= r[k];
      }
    }
  }

 private:
  std::vector<double> in_, ring_, col_;
};

struct Slot {
  std::vector<double> grad, hess, pairs;
  std::int64_t pixels = 0, windows = 0;
  double ncc_sum = 0;
};

// The pixels of view i that a partner can use: the rectangle around the clean covered
// pixels (grown by half a window), and per pixel its face, ray (unit depth) and hit point.
struct ViewPixels {
  int x0 = 0, y0 = 0, cols = 0, rows = 0;
  std::vector<float> I;
  std::vector<int> face;  // -1: not used
  std::vector<Eigen::Vector3d> ray, X;
  size_t size() const { return I.size(); }
};

ViewPixels view_pixels(const Raster& R, const cv::Mat& clean, const cv::Mat& grey, const Camera& c,
                       const std::vector<Eigen::Vector3d>& fn, const std::vector<double>& fd, int half_window) {
  ViewPixels p;
  int x0 = R.width, y0 = R.height, x1 = -1, y1 = -1;
  for (int y = 0; y < R.height; ++y) {
    const std::uint8_t* m = clean.ptr<std::uint8_t>(y);
    for (int x = 0; x < R.width; ++x)
      if (m[x]) {
        x0 = std::min(x0, x);
        x1 = std::max(x1, x);
        y0 = std::min(y0, y);
        y1 = std::max(y1, y);
      }
  }
  if (x1 < 0) return p;
  p.x0 = std::max(0, x0 - half_window);
  p.y0 = std::max(0, y0 - half_window);
  p.cols = std::min(R.width - 1, x1 + half_window) - p.x0 + 1;
  p.rows = std::min(R.height - 1, y1 + half_window) - p.y0 + 1;
  const size_t np = static_cast<size_t>(p.cols) * p.rows;
  p.I.assign(np, 0.f);
  p.face.assign(np, -1);
  p.ray.resize(np);
  p.X.resize(np);
  const Eigen::Vector3d C = c.centre();
  const Eigen::Matrix3d RtKi = c.R.transpose() * c.K.inverse();
  for (int r = 0; r < p.rows; ++r) {
    const int y = p.y0 + r;
    const int* t = R.tri.ptr<int>(y);
    const float* g = grey.ptr<float>(y);
    const std::uint8_t* m = clean.ptr<std::uint8_t>(y);
    for (int q = 0; q < p.cols; ++q) {
      const int x = p.x0 + q;
      const size_t k = static_cast<size_t>(r) * p.cols + q;
      p.I[k] = g[x];
      const int f = t[x];
      if (f < 0 || !m[x]) continue;
      const Eigen::Vector3d d = RtKi * Eigen::Vector3d(x, y, 1.0);
      const double den = fn[f].dot(d);
      if (!(den < -kMinCos * d.norm())) continue;
      p.face[k] = f;
      p.ray[k] = d;
      p.X[k] = C + d * ((fd[f] - fn[f].dot(C)) / den);
    }
  }
  return p;
}

}  // namespace

std::vector<Camera> reduced_cameras(const std::vector<Camera>& cams, int level) {
  require(level >= 0 && level <= 12, "reduced_cameras: pyramid level ", level, " must lie in [0, 12]");
  std::vector<Camera> out = cams;
  const double s = 1.0 / static_cast<double>(1 << level);
  for (Camera& c : out) {
    c.K.row(0) *= s;
    c.K.row(1) *= s;
    for (int l = 0; l < level; ++l) {
      c.width = (c.width + 1) / 2;
      c.height = (c.height + 1) / 2;
    }
  }
  return out;
}

std::vector<std::vector<int>> photometric_partners(const std::vector<Camera>& cams, const Eigen::Vector3d& centre,
                                                   double min_deg, double max_deg, int count) {
  const int n = static_cast<int>(cams.size());
  std::vector<Eigen::Vector3d> dir(n);
  for (int i = 0; i < n; ++i) dir[i] = (cams[i].centre() - centre).normalized();
  constexpr double kDeg = 180.0 / 3.14159265358979323846;
  std::vector<std::vector<int>> out(n);
  for (int i = 0; i < n; ++i) {
    std::vector<std::pair<double, int>> cand;
    for (int j = 0; j < n; ++j) {
      if (j == i) continue;
      const double a = std::acos(std::clamp(dir[i].dot(dir[j]), -1.0, 1.0)) * kDeg;
      if (a >= min_deg && a <= max_deg) cand.emplace_back(a, j);
    }
    std::sort(cand.begin(), cand.end());
    for (int k = 0; k < std::min<int>(count, static_cast<int>(cand.size())); ++k) out[i].push_back(cand[k].second);
  }
  return out;
}

PhotoLevel make_photo_level(const photo::Views& full, const std::vector<Camera>& cams, int level) {
  PhotoLevel lv;
  lv.level = level;
  lv.views = level == 0 ? full : full.reduced(level);
  lv.cams = reduced_cameras(cams, level);
  const int nc = lv.views.size();
  lv.gx.resize(nc);
  lv.gy.resize(nc);
#pragma omp parallel for schedule(dynamic, 1)
  for (int i = 0; i < nc; ++i) image_gradients(lv.views[i].grey, lv.gx[i], lv.gy[i]);
  return lv;
}

PhotometricGradient photometric_gradient(const std::vector<Eigen::Vector3d>& V, const std::vector<Eigen::Vector3i>& F,
                                         const std::vector<Eigen::Vector3d>& N, const PhotoLevel& lv,
                                         const std::vector<std::vector<int>>& partners, int window,
                                         const std::vector<const Raster*>& rasters) {
  require(window >= 3 && window % 2 == 1, "photometric_gradient: the window (", window, ") must be odd and >= 3");
  const photo::Views& views = lv.views;
  const std::vector<Camera>& cams = lv.cams;
  const std::vector<cv::Mat>& gx = lv.gx;
  const std::vector<cv::Mat>& gy = lv.gy;
  const int nv = static_cast<int>(V.size()), nf = static_cast<int>(F.size()), nc = views.size();
  require(static_cast<int>(cams.size()) == nc && static_cast<int>(partners.size()) == nc &&
              static_cast<int>(gx.size()) == nc && (rasters.empty() || static_cast<int>(rasters.size()) == nc),
          "photometric_gradient: ", cams.size(), " cameras, ", gx.size(), " gradient images, ", rasters.size(),
          " rasters and ", partners.size(), " partner lists for ", nc, " views");

  std::vector<Eigen::Vector3d> fn(nf);  // unit face normals
  std::vector<double> fd(nf);           // plane offsets fn . x
#pragma omp parallel for schedule(static)
  for (int f = 0; f < nf; ++f) {
    const Eigen::Vector3d& a = V[F[f][0]];
    const Eigen::Vector3d n = (V[F[f][1]] - a).cross(V[F[f][2]] - a);
    const double l = n.norm();
    fn[f] = l > 0 ? Eigen::Vector3d(n / l) : Eigen::Vector3d::Zero();
    fd[f] = fn[f].dot(a);
  }

  std::vector<Raster> own(rasters.empty() ? nc : 0);
  std::vector<const Raster*> rp = rasters;
  if (rasters.empty()) {
    TriMesh tm;
    tm.V = V;
    tm.F = F;
#pragma omp parallel for schedule(dynamic, 1)
    for (int i = 0; i < nc; ++i) {
      RasterOptions ro;
      ro.cull_back = true;  // a closed outward mesh: back faces are hidden
      own[i] = rasterize(tm, cams[i], ro);
    }
    for (int i = 0; i < nc; ++i) rp.push_back(&own[i]);
  }
  std::vector<cv::Mat> clean(nc);
#pragma omp parallel for schedule(dynamic, 1)
  for (int i = 0; i < nc; ++i) clean[i] = clean_pixels(*rp[i], cams[i].focal());

  std::vector<Slot> slots(kSlots);
  const int hw = window / 2;
  const double min_n = 0.5 * window * window;  // a window needs half its pixels
  const double noise2 = kNoiseGrey * kNoiseGrey;

#pragma omp parallel for schedule(dynamic, 1)
  for (int s = 0; s < kSlots; ++s) {
    Slot& acc = slots[s];
    acc.grad.assign(nv, 0.0);
    acc.hess.assign(nv, 0.0);
    acc.pairs.assign(nv, 0.0);
    BoxSums<7> stats, coefs;
    std::vector<double> coef;
    std::vector<float> J, G;
    std::vector<double> pg, ph;
    std::vector<int> pn;
    std::vector<std::uint8_t> valid;
    for (int i = s; i < nc; i += kSlots) {
      if (partners[i].empty()) continue;
      const ViewPixels P = view_pixels(*rp[i], clean[i], views[i].grey, cams[i], fn, fd, hw);
      const size_t np = P.size();
      if (np == 0) continue;
      J.assign(np, 0.f);
      G.assign(np, 0.f);
      // per pixel, dE/dt and the curvature summed over the partners (the weights that take
      // them to the vertices do not depend on the partner)
      pg.assign(np, 0.0);
      ph.assign(np, 0.0);
      pn.assign(np, 0);
      for (int j : partners[i]) {
        const photo::View& vj = views[j];
        const Eigen::Matrix<double, 3, 4>& Pj = vj.P;
        valid.assign(np, 0);
        // I_ij and its derivative along each pixel's ray
        for (size_t k = 0; k < np; ++k) {
          const int f = P.face[k];
          if (f < 0) continue;
          const Eigen::Vector3d toj = P.X[k] - vj.centre;
          if (!(fn[f].dot(toj) < -kMinCos * toj.norm())) continue;
          const Eigen::Vector3d ph = Pj.leftCols<3>() * P.X[k] + Pj.col(3);
          if (!(ph.z() > 0)) continue;
          const double u = ph.x() / ph.z(), v = ph.y() / ph.z();
          if (!(u >= 1 && v >= 1 && u < vj.width - 2 && v < vj.height - 2)) continue;
          const int ui = static_cast<int>(round_nearest(u)), vi = static_cast<int>(round_nearest(v));
          if (!clean[j].at<std::uint8_t>(vi, ui)) continue;
          if (!(ph.z() <= rp[j]->depth.at<float>(vi, ui) + kDepthTolPx * ph.z() * vj.inv_focal)) continue;
          const Eigen::Vector3d dp = Pj.leftCols<3>() * P.ray[k];
          const double dudt = (dp.x() - u * dp.z()) / ph.z(), dvdt = (dp.y() - v * dp.z()) / ph.z();
          J[k] = bilinear(vj.grey, u, v);
          G[k] = static_cast<float>(bilinear(gx[j], u, v) * dudt + bilinear(gy[j], u, v) * dvdt);
          valid[k] = 1;
        }
        // window statistics of the valid pixels (count, sums of I, I_ij, their squares and
        // product, and of g), then per window the NCC and the coefficients of its derivative
        // with respect to I_ij, dNCC/dI_ij(q) = A I(q) - B - C I_ij(q) + D, and of the
        // Gauss-Newton curvature of the depths, sum over the window of (g(q) - mean g)^2 E =
        // g(q)^2 E - 2 g(q) Fg + Gg (centred: a window-wide change of I_ij is not seen by the NCC)
        coef.assign(np * 7, 0.0);
        stats.run(
            P.cols, P.rows, window,
            [&](int y, double* out) {
              for (int x = 0; x < P.cols; ++x, out += 7) {
                const size_t k = static_cast<size_t>(y) * P.cols + x;
                if (!valid[k]) {
                  std::fill(out, out + 7, 0.0);
                  continue;
                }
                const double a = P.I[k], b = J[k];
                out[0] = 1;
                out[1] = a;
                out[2] = b;
                out[3] = a * a;
                out[4] = b * b;
                out[5] = a * b;
                out[6] = G[k];
              }
            },
            [&](int y, const double* sum) {
              for (int x = 0; x < P.cols; ++x, sum += 7) {
                const double n = sum[0];
                if (n < min_n) continue;
                double* c = coef.data() + (static_cast<size_t>(y) * P.cols + x) * 7;
                const double mi = sum[1] / n, mj = sum[2] / n;
                const double vi2 = std::max(0.0, sum[3] / n - mi * mi) + noise2;
                const double vj2 = std::max(0.0, sum[4] / n - mj * mj) + noise2;
                const double sij2 = std::sqrt(vi2 * vj2);
                const double ncc = (sum[5] / n - mi * mj) / sij2;
                acc.ncc_sum += ncc;
                ++acc.windows;
                const double w = kRobust * kRobust / ((1 - ncc + kRobust) * (1 - ncc + kRobust));
                c[0] = w / (n * sij2);
                c[1] = mi * c[0];
                c[2] = w * ncc / (n * vj2);
                c[3] = mj * c[2];
                c[4] = w / (n * vj2);
                const double mg = sum[6] / n;
                c[5] = mg * c[4];
                c[6] = mg * c[5];
              }
            });
        // per pixel: dE/dt along its ray, from the coefficients summed over the windows
        // that hold it
        coefs.run(
            P.cols, P.rows, window,
            [&](int y, double* out) {
              std::copy_n(coef.data() + static_cast<size_t>(y) * P.cols * 7, static_cast<size_t>(P.cols) * 7, out);
            },
            [&](int y, const double* c) {
              for (int x = 0; x < P.cols; ++x, c += 7) {
                const size_t k = static_cast<size_t>(y) * P.cols + x;
                if (!valid[k] || !(c[4] > 0)) continue;
                const double dEdJ = -(P.I[k] * c[0] - c[1] - J[k] * c[2] + c[3]);
                const double g = G[k];
                pg[k] += dEdJ * g;
                ph[k] += std::max(0.0, g * g * c[4] - 2 * g * c[5] + c[6]);
                ++pn[k];
              }
            });
      }
      // then to the vertices of each pixel's face
      for (size_t k = 0; k < np; ++k) {
        if (pn[k] == 0) continue;
        const int f = P.face[k];
        const Eigen::Vector3d& a = V[F[f][0]];
        const Eigen::Vector3d e1 = V[F[f][1]] - a, e2 = V[F[f][2]] - a, q = P.X[k] - a;
        const double d11 = e1.dot(e1), d12 = e1.dot(e2), d22 = e2.dot(e2), q1 = q.dot(e1), q2 = q.dot(e2);
        const double det = d11 * d22 - d12 * d12;
        if (!(det > 0)) continue;
        const double b1 = std::clamp((d22 * q1 - d12 * q2) / det, 0.0, 1.0);
        const double b2 = std::clamp((d11 * q2 - d12 * q1) / det, 0.0, 1.0 - b1);
        const double b[3] = {1.0 - b1 - b2, b1, b2};
        const double den = fn[f].dot(P.ray[k]);
        for (int c = 0; c < 3; ++c) {
          const int vtx = F[f][c];
          const double r = fn[f].dot(N[vtx]) / den;  // d(depth) / d(offset of vtx), per unit weight
          acc.grad[vtx] += pg[k] * b[c] * r;
          acc.hess[vtx] += ph[k] * b[c] * r * r;
          acc.pairs[vtx] += pn[k] * b[c] * r * r;
        }
        acc.pixels += pn[k];
      }
    }
  }

  PhotometricGradient out;
  out.grad.assign(nv, 0.0);
  out.hess.assign(nv, 0.0);
  out.pairs.assign(nv, 0.0);
  double ncc = 0;
  std::int64_t windows = 0;
  for (const Slot& a : slots) {
    if (a.grad.empty()) continue;
    for (int v = 0; v < nv; ++v) {
      out.grad[v] += a.grad[v];
      out.hess[v] += a.hess[v];
      out.pairs[v] += a.pairs[v];
    }
    out.pixels += a.pixels;
    ncc += a.ncc_sum;
    windows += a.windows;
  }
  out.mean_ncc = windows > 0 ? ncc / static_cast<double>(windows) : 0.0;
  return out;
}

std::vector<double> photometric_steps(const PhotometricGradient& pg, const Topology& topo, int level,
                                      int mesh_level, const std::vector<double>& fp, double noise_floor) {
  const int nv = static_cast<int>(pg.grad.size());
  require(topo.num_vertices == nv && static_cast<int>(fp.size()) == nv && pg.pairs.size() == pg.hess.size(),
          "photometric_steps: topology, footprints and gradient disagree");
  std::vector<double> g = pg.grad, h = pg.hess, n = pg.pairs;
  const int rounds = kRingRounds << std::max(0, level - mesh_level);
  for (auto* x : {&g, &h, &n}) ring_average(*x, topo, rounds);
  // The damping. On the reduced images it is per pixel pair, so that a vertex few views see (a
  // cavity's deep part, 2-7 views) takes the step its windows warrant rather than one cut short
  // by a damping set by the mesh's busier vertices ("Damping", docs/deform.md). On the full
  // images a share of the median curvature, and the noise floor below.
  const bool per_pair = level >= 1;
  std::vector<double> pos;
  for (int v = 0; v < nv; ++v)
    if (h[v] > 0 && n[v] > 0) pos.push_back(per_pair ? h[v] / n[v] : h[v]);
  double damping = 0;  // per pixel pair on the reduced images, per vertex on the full ones
  if (!pos.empty()) {
    std::nth_element(pos.begin(), pos.begin() + pos.size() / 2, pos.end());
    damping = (per_pair ? kPairDamping : kDamping) * pos[pos.size() / 2];
  }
  std::vector<double> step(nv, 0.0);
  const double max_px = kMaxStepPx * static_cast<double>(1 << level);
  for (int v = 0; v < nv; ++v) {
    if (!(h[v] > 0)) continue;
    const double lim = max_px * fp[v];
    // the noise floor: as if each pixel pair also saw a normalised gradient of sqrt(floor) a pixel
    const double floor = level == 0 ? noise_floor * n[v] / (fp[v] * fp[v]) : 0.0;
    step[v] = std::clamp(-g[v] / (h[v] + (per_pair ? damping * n[v] : damping) + floor), -lim, lim);
  }
  return step;
}

}  // namespace tetmvs::deform
