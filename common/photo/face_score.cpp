#include "common/photo/face_score.h"

#include "common/photo/camera_select.h"
#include "common/photo/orientations.h"

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

void face_patches(const Views& views, const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                  const Options& opts, Scratch& scratch, PatchResult& front, PatchResult& back) {
  front = PatchResult{};
  back = PatchResult{};
  if (triangle_normal(a, b, c).isZero()) return;
  detail::prepare_centre(views, face_centroid(a, b, c), opts, scratch);
  face_patches_prepared(views, a, b, c, opts, scratch, front, back);
}

void face_patches_prepared(const Views& views, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                           const Eigen::Vector3d& c, const Options& opts, Scratch& scratch, PatchResult& front,
                           PatchResult& back) {
  front = PatchResult{};
  back = PatchResult{};
  const Eigen::Vector3d n = triangle_normal(a, b, c);
  if (n.isZero()) return;
  // the axes of score_patch for n and -n
  for (const double sign : {1.0, -1.0}) {
    const Eigen::Vector3d u = sign * n;
    const Eigen::Vector3d a1 = stable_perpendicular(u);
    const Eigen::Vector3d a2 = u.cross(a1);
    detail::score_prepared(views, u, a1, &a2, opts, scratch, sign > 0 ? front : back);
  }
}

}  // namespace tetmvs::photo
