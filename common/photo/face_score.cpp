#include "common/photo/face_score.h"

namespace tetmvs::photo {

Eigen::Vector3d triangle_normal(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                const Eigen::Vector3d& c) {
  const Eigen::Vector3d e1 = b - a, e2 = c - a;
  const Eigen::Vector3d n = e1.cross(e2);
  const double ln = n.norm();
  if (!(ln > 1e-12 * e1.norm() * e2.norm()) || !(ln > 0)) return Eigen::Vector3d::Zero();
  return n / ln;
}

PatchResult face_patch(const Views& views, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                       const Eigen::Vector3d& c, const Options& opts, Scratch& scratch) {
  const Eigen::Vector3d n = triangle_normal(a, b, c);
  if (n.isZero()) return PatchResult{};
  return score_patch(views, (a + b + c) / 3.0, n, opts, scratch);
}

}  // namespace tetmvs::photo
