// The face score of the cut (the omega of Eq. 1, paper section 3.1): the mu x mu
// grid patch (patch.h) centred at the face centroid on the face plane, with one of
// the face's two normals. The patch may extend beyond a small triangle on its plane
// (intended: fine faces are smaller than mu pixels).
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "common/photo/patch.h"

namespace tetmvs::photo {

// Unit normal of triangle (a, b, c): (b - a) x (c - a) normalized, i.e. the side from
// which a, b, c appear counter-clockwise. Zero for a degenerate triangle.
Eigen::Vector3d triangle_normal(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                const Eigen::Vector3d& c);

// The patch of triangle (a, b, c) seen from the side of triangle_normal(a, b, c)
// (swap b and c for the other orientation). Invalid for a degenerate triangle.
PatchResult face_patch(const Views& views, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                       const Eigen::Vector3d& c, const Options& opts, Scratch& scratch);

// Both orientations of triangle (a, b, c) at once: `front` seen from the side of
// triangle_normal(a, b, c), `back` from the other (face_patch(a, b, c) and
// face_patch(a, c, b)); the views are projected once for both. Both invalid for a
// degenerate triangle.
void face_patches(const Views& views, const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                  const Options& opts, Scratch& scratch, PatchResult& front, PatchResult& back);
// face_patches after detail::prepare_centre(views, face_centroid(a, b, c), opts, scratch)
// (camera_select.h): the caller may use the projections in scratch in between.
void face_patches_prepared(const Views& views, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                           const Eigen::Vector3d& c, const Options& opts, Scratch& scratch, PatchResult& front,
                           PatchResult& back);
// The point the face patches are centred at: (a + b + c) / 3.
inline Eigen::Vector3d face_centroid(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  return (a + b + c) / 3.0;
}

// omega in [0, 1] of that oriented face: face_patch(...).omega() (0 when too few views).
inline float face_score(const Views& views, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                        const Eigen::Vector3d& c, const Options& opts, Scratch& scratch) {
  return face_patch(views, a, b, c, opts, scratch).omega();
}

}  // namespace tetmvs::photo
