// Pinhole camera of the Middlebury par files: x ~ K (R X + t).
// Pixel convention: the centre of pixel (u, v) is at continuous coordinate (u, v);
// u grows to the right, v downward, (0, 0) is the centre of the top-left pixel.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

namespace tetmvs {

struct Camera {
  std::string name;  // image file name, as in the par file
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // world -> camera rotation
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  int width = 0, height = 0;  // image size in pixels (0 when unknown)

  // Camera centre in world coordinates: -R^T t.
  Eigen::Vector3d centre() const { return -R.transpose() * t; }
  // Point in camera coordinates.
  Eigen::Vector3d to_camera(const Eigen::Vector3d& X) const { return R * X + t; }
  // Depth along the optical axis (z in camera coordinates); > 0 in front.
  double depth(const Eigen::Vector3d& X) const { return R.row(2).dot(X) + t.z(); }
  // Pixel of a world point. Valid only when depth(X) > 0.
  Eigen::Vector2d project(const Eigen::Vector3d& X) const {
    const Eigen::Vector3d x = K * (R * X + t);
    return {x.x() / x.z(), x.y() / x.z()};
  }
  // True when X is in front of the camera and projects within the image
  // (pixel centres 0..w-1, 0..h-1, with `margin` pixels kept free at the border).
  bool sees(const Eigen::Vector3d& X, double margin = 0.0) const;
  // Unit viewing direction (world frame) of the ray through pixel (u, v).
  Eigen::Vector3d ray_direction(double u, double v) const;
  // The point at depth d (camera z) on the ray through pixel (u, v).
  Eigen::Vector3d backproject(double u, double v, double d) const;
  // Optical axis (world frame), unit length.
  Eigen::Vector3d axis() const { return R.row(2).transpose(); }
  // 3x4 projection matrix K [R | t].
  Eigen::Matrix<double, 3, 4> P() const;
  // Focal length in pixels (mean of fx, fy): pixel footprint at depth d is d / f.
  double focal() const { return 0.5 * (K(0, 0) + K(1, 1)); }
};

// Median over cameras of distance(point, camera centre) / focal: the world size of one
// pixel at `point` (the upper median for an even count).
double pixel_footprint(const std::vector<Camera>& cams, const Eigen::Vector3d& point);

// Checks that R is a rotation (orthonormal, det +1) to within tol.
bool is_rotation(const Eigen::Matrix3d& R, double tol = 1e-6);

}  // namespace tetmvs
