// Visual-hull test for lattice points and faces: a point is outside the hull when, in
// some view with a silhouette, it lies in front of the camera, projects inside the image
// and falls outside that silhouette dilated by a margin (pixels). Views without a
// silhouette and views the point projects outside of never exclude it. The true surface
// is inside the hull, so points outside it cannot be on the surface. (The image border is
// not an outline: common/silhouette/border.h.)
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "common/photo/views.h"

namespace tetmvs::photoconsist {

class HullTest {
 public:
  HullTest() = default;
  // sil: one (possibly empty) CV_8U mask per view (255 = object), as in Scene::sil.
  // core_px > 0 also sets up in_core() (label.hull_core_px: the hull-core prior).
  HullTest(const photo::Views& views, const std::vector<cv::Mat>& sil, double margin_px, double core_px = 0);
  bool inside(const Eigen::Vector3d& X) const;
  // inside(X) when X's homogeneous projections are known: h_of(v) returns
  // views[v].project_h(X) for view v of the views the test was made with.
  template <class Projection>
  bool inside_projected(const Projection& h_of) const {
    for (std::size_t s = 0; s < idx_.size(); ++s) {
      int x, y;
      if (pixel_of(s, h_of(idx_[s]), x, y) && !in_dilated(s, x, y)) return false;
    }
    return true;
  }
  // True when X projects at least core_px pixels inside the silhouette (distance to its
  // boundary, as label's prior measures it) in every view with a silhouette whose image
  // it falls in, and there is such a view. Always false when core_px is 0. With the
  // hull-core prior such points are matter, never surface: photoconsist skips them.
  bool in_core(const Eigen::Vector3d& X) const;
  // True when every point of triangle (a, b, c) is outside the hull: in some view with a
  // silhouette, the triangle is in front and projects inside the image, and the bounding
  // box of its projection holds no (dilated) silhouette pixel. False means "maybe".
  bool triangle_outside(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) const;
  int num_silhouettes() const { return static_cast<int>(idx_.size()); }
  const photo::Views* views() const { return views_; }

 private:
  // Nearest pixel (x, y) of X in the s-th view with a silhouette; false when X is behind
  // that camera or projects outside its image.
  bool pixel(std::size_t s, const Eigen::Vector3d& X, int& x, int& y) const;
  bool pixel_of(std::size_t s, const Eigen::Vector3d& h, int& x, int& y) const;
  // Whether pixel (x, y) of the s-th view with a silhouette is in its dilated silhouette.
  bool in_dilated(std::size_t s, int x, int y) const {
    const std::uint64_t word = bits_[s][static_cast<std::size_t>(y) * words_[s] + (static_cast<unsigned>(x) >> 6)];
    return (word >> (x & 63)) & 1u;
  }
  const photo::Views* views_ = nullptr;
  std::vector<int> idx_;          // views with a silhouette
  // their dilated silhouettes, a bit per pixel (rows of words_ 64-bit words): the lookups of
  // 48 views stay in the cache, where bytes per pixel would not
  std::vector<std::vector<std::uint64_t>> bits_;
  std::vector<std::size_t> words_;
  std::vector<cv::Mat> integral_; // integral images (CV_32S) of the dilated silhouettes
  std::vector<cv::Mat> core_;     // distance to the silhouette boundary >= core_px (CV_8U), if core_px > 0
};

}  // namespace tetmvs::photoconsist
