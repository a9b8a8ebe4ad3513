#include "common/camera.h"

#include <Eigen/Dense>
#include <algorithm>

#include "common/error.h"

namespace tetmvs {

bool Camera::sees(const Eigen::Vector3d& X, double margin) const {
  if (depth(X) <= 0) return false;
  const Eigen::Vector2d p = project(X);
  return p.x() >= margin && p.y() >= margin && p.x() <= width - 1 - margin &&
         p.y() <= height - 1 - margin;
}

Eigen::Vector3d Camera::ray_direction(double u, double v) const {
  const Eigen::Vector3d dc = K.inverse() * Eigen::Vector3d(u, v, 1.0);
  return (R.transpose() * dc).normalized();
}

Eigen::Vector3d Camera::backproject(double u, double v, double d) const {
  const Eigen::Vector3d dc = K.inverse() * Eigen::Vector3d(u, v, 1.0);  // z = 1
  return R.transpose() * (dc * d - t);
}

Eigen::Matrix<double, 3, 4> Camera::P() const {
  Eigen::Matrix<double, 3, 4> Rt;
  Rt.leftCols<3>() = R;
  Rt.col(3) = t;
  return K * Rt;
}

bool is_rotation(const Eigen::Matrix3d& R, double tol) {
  if (!R.allFinite()) return false;
  const double orth = (R * R.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  return orth <= tol && std::abs(R.determinant() - 1.0) <= tol;
}

double pixel_footprint(const std::vector<Camera>& cams, const Eigen::Vector3d& point) {
  require(!cams.empty(), "pixel_footprint: no cameras");
  std::vector<double> v;
  v.reserve(cams.size());
  for (const Camera& c : cams) v.push_back((c.centre() - point).norm() / c.focal());
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

}  // namespace tetmvs
