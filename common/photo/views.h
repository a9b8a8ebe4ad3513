// Per-view data of the photo-consistency measure, precomputed once per stage run:
// projection matrices (3x4, scaled so the third coordinate is the depth), camera
// centres, 1/focal, and the float grey images (and optional silhouettes), shared
// (not copied) with the caller's cv::Mats. Immutable after construction: safe to use
// from many threads.
#pragma once
#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "common/camera.h"

namespace tetmvs::photo {

struct View {
  Eigen::Matrix<double, 3, 4> P;  // K [R | t] / K(2,2): (P [X;1]).z() = depth of X
  Eigen::Vector3d centre;         // camera centre, world frame
  double inv_focal = 0;           // 1 / focal in pixels: pixel footprint at depth d = d * inv_focal
  cv::Mat grey;                   // CV_32F in [0, 1] (shallow copy of the caller's image)
  cv::Mat sil;                    // CV_8U, 255 = object; empty when the view has none
  // CV_8U: per silhouette pixel, its distance in pixels to the nearest pixel outside the
  // silhouette (capped at 255; the image border is not an outline), 0 outside; empty
  // without a silhouette or unless asked for (Views' outline_distances). Tells a patch that
  // lies wholly inside (Options::outline_fill).
  cv::Mat inside_px;
  int width = 0, height = 0;

  // Homogeneous image point of X: (u w, v w, w) with w = depth.
  Eigen::Vector3d project_h(const Eigen::Vector3d& X) const {
    return P.leftCols<3>() * X + P.col(3);
  }
  // Image-space direction of a world direction d (homogeneous, w = 0 part).
  Eigen::Vector3d project_dir(const Eigen::Vector3d& d) const { return P.leftCols<3>() * d; }
  // Nearest-pixel silhouette test; true when the view has no silhouette.
  bool in_silhouette(double u, double v) const;
};

class Views {
 public:
  Views() = default;
  // grey[i]: CV_32F of the camera's size (cams[i].width/height when set). sil: empty
  // vector, or one (possibly empty) CV_8U Mat per camera. outline_distances: also
  // View::inside_px (here and in reduced views). Throws Error on mismatches.
  Views(const std::vector<Camera>& cams, const std::vector<cv::Mat>& grey,
        const std::vector<cv::Mat>& sil = {}, bool outline_distances = false);
  int size() const { return static_cast<int>(views_.size()); }
  const View& operator[](int i) const { return views_[i]; }
  bool has_silhouettes() const { return has_sil_; }
  // The same views at image-pyramid level `level` (>= 0): each grey image reduced `level`
  // times by cv::pyrDown (Gaussian 5-tap, then every other pixel), the projections scaled
  // so that pixel (u, v) of the reduced image is pixel (2^level u, 2^level v) of the original
  // (pyrDown centres output pixel i on input pixel 2i), silhouettes reduced by nearest
  // sampling at those pixels. Level 0 is a shallow copy. Pixel footprints grow by 2^level.
  Views reduced(int level) const;

 private:
  std::vector<View> views_;
  bool has_sil_ = false;
  bool outline_distances_ = false;
};

}  // namespace tetmvs::photo
