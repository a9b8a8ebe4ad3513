// Synthetic scenes for the photo-consistency tests: a textured plane seen by pinhole
// cameras, rendered by ray casting; the texture is a procedural function of the 3-D
// point, so all views agree exactly on the surface.
#pragma once
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <opencv2/core.hpp>
#include <vector>

#include "common/camera.h"

namespace tetmvs::testing {

// Hash of an integer lattice point -> [0, 1).
inline double lattice_hash(int64_t x, int64_t y, int64_t z) {
  uint64_t h = static_cast<uint64_t>(x) * 0x9E3779B97F4A7C15ull ^ static_cast<uint64_t>(y) * 0xC2B2AE3D27D4EB4Full ^
               static_cast<uint64_t>(z) * 0x165667B19E3779F9ull;
  h ^= h >> 31;
  h *= 0xD6E8FEB86659FD93ull;
  h ^= h >> 32;
  return static_cast<double>(h >> 11) * (1.0 / 9007199254740992.0);
}

// Smooth 3-D value noise with lattice cell `cell`, in [0, 1].
inline double value_noise(const Eigen::Vector3d& p, double cell) {
  const Eigen::Vector3d q = p / cell;
  const double fx = std::floor(q.x()), fy = std::floor(q.y()), fz = std::floor(q.z());
  const auto s = [](double t) { return t * t * (3 - 2 * t); };
  const double tx = s(q.x() - fx), ty = s(q.y() - fy), tz = s(q.z() - fz);
  const int64_t x = static_cast<int64_t>(fx), y = static_cast<int64_t>(fy), z = static_cast<int64_t>(fz);
  double c[2][2][2];
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      for (int k = 0; k < 2; ++k) c[i][j][k] = lattice_hash(x + i, y + j, z + k);
  const auto l = [](double a, double b, double t) { return a + (b - a) * t; };
  return l(l(l(c[0][0][0], c[1][0][0], tx), l(c[0][1][0], c[1][1][0], tx), ty),
           l(l(c[0][0][1], c[1][0][1], tx), l(c[0][1][1], c[1][1][1], tx), ty), tz);
}

// Grey texture in [0.1, 0.9] with detail at about `cell` and 2.5 `cell`.
inline double texture(const Eigen::Vector3d& p, double cell) {
  return 0.1 + 0.8 * (0.7 * value_noise(p, cell) + 0.3 * value_noise(p, 2.5 * cell));
}

// Camera at C looking at target (x right, y down in the image).
inline Camera look_at(const Eigen::Vector3d& C, const Eigen::Vector3d& target, double f, int w, int h) {
  Camera cam;
  const Eigen::Vector3d z = (target - C).normalized();
  Eigen::Vector3d up(0, 0, 1);
  if (std::abs(z.dot(up)) > 0.9) up = Eigen::Vector3d(0, 1, 0);
  const Eigen::Vector3d x = z.cross(up).normalized();
  const Eigen::Vector3d y = z.cross(x);
  cam.R.row(0) = x.transpose();
  cam.R.row(1) = y.transpose();
  cam.R.row(2) = z.transpose();
  cam.t = -cam.R * C;
  cam.K << f, 0, (w - 1) / 2.0, 0, f, (h - 1) / 2.0, 0, 0, 1;
  cam.width = w;
  cam.height = h;
  return cam;
}

// A textured plane through O with unit normal N, seen by cameras at distance D from
// O, in a cone around N: camera i at polar angle polar[i] (degrees) from N and
// azimuth 360 i / n.
struct PlaneScene {
  Eigen::Vector3d O{0, 0, 0}, N{0, 0, 1};
  double cell = 0.03;  // texture cell (world units)
  int supersample = 3;  // rays per pixel side (box filter against aliasing)
  std::vector<Camera> cams;
  std::vector<cv::Mat> grey;
  double footprint = 0;  // pixel footprint at O in the nearest view (world units)

  PlaneScene(const Eigen::Vector3d& normal, const std::vector<double>& polar_deg, double D = 4.0,
             double f = 300.0, int w = 200, int h = 150, double cell_ = 0.03, int supersample_ = 3)
      : N(normal.normalized()), cell(cell_), supersample(supersample_) {
    const Eigen::Vector3d a = std::abs(N.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
    const Eigen::Vector3d e1 = N.cross(a).normalized(), e2 = N.cross(e1);
    const int n = static_cast<int>(polar_deg.size());
    footprint = D / f;
    for (int i = 0; i < n; ++i) {
      const double th = polar_deg[i] * std::numbers::pi / 180, ph = 2 * std::numbers::pi * i / n;
      const Eigen::Vector3d dir =
          std::cos(th) * N + std::sin(th) * (std::cos(ph) * e1 + std::sin(ph) * e2);
      cams.push_back(look_at(O + D * dir, O, f, w, h));
      grey.push_back(render(cams.back()));
    }
  }

  cv::Mat render(const Camera& cam) const {
    cv::Mat img(cam.height, cam.width, CV_32F);
    const Eigen::Vector3d C = cam.centre();
    const Eigen::Matrix3d Kinv = cam.K.inverse(), R = cam.R;
    for (int v = 0; v < cam.height; ++v)
      for (int u = 0; u < cam.width; ++u) {
        double val = 0.0;
        for (int a = 0; a < supersample; ++a)
          for (int b = 0; b < supersample; ++b) {
            const double du = (a + 0.5) / supersample - 0.5, dv = (b + 0.5) / supersample - 0.5;
            const Eigen::Vector3d d = (R.transpose() * (Kinv * Eigen::Vector3d(u + du, v + dv, 1))).normalized();
            const double den = N.dot(d);
            if (std::abs(den) > 1e-12) {
              const double t = N.dot(O - C) / den;
              if (t > 0) val += texture(C + t * d, cell);
            }
          }
        img.at<float>(v, u) = static_cast<float>(val / (supersample * supersample));
      }
    return img;
  }
};

}  // namespace tetmvs::testing
