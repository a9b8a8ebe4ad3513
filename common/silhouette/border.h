// The image border is not the object's outline.
//
// A mask that touches the image border is cut there by the frame: the object goes on beyond
// it, and nothing is known about what lies outside the image. Every consumer of silhouettes
// (visual-hull tests and carving, silhouette-fix, deform's silhouette force, the silhouette
// agreement of evaluate and the report, the pictures) follows this one rule:
//  - a silhouette's outline is its object pixels with a background 4-neighbour inside the
//    image: object pixels on the border are outline only where real background touches them;
//  - distances to the outline ignore the border (pixels beyond it are neither object nor
//    background), so a pixel next to the border is as deep inside the object as its
//    distance to real background says;
//  - a point that projects outside the image is never carved by that view (and makes no
//    outline constraint there): only pixels inside the image say anything.
#pragma once
#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace tetmvs::silhouette {

// Outline pixels of a CV_8U mask (non-zero = object) under the rule above: CV_8U, 255 on
// object pixels with a background 4-neighbour inside the image, 0 elsewhere.
cv::Mat outline(const cv::Mat& mask);

// For each object pixel, the distance (pixels, CV_32F) to the nearest background pixel of the
// image, 0 on background; where the mask holds no background, a value larger than the image.
cv::Mat distance_inside(const cv::Mat& mask);

// For each background pixel, the distance to the nearest object pixel, 0 on the object;
// where the mask holds no object, a value larger than the image.
cv::Mat distance_outside(const cv::Mat& mask);

// True when some object pixel lies on the image border (the mask is cut by the frame).
bool touches_border(const cv::Mat& mask);

// The nearest pixel (x, y) of the image point p in a width x height image; false when that
// pixel is outside the image: the view then says nothing about the point (never carves it).
inline bool nearest_pixel_in_image(const Eigen::Vector2d& p, int width, int height, int& x, int& y) {
  if (!(p.x() > -0.5 && p.y() > -0.5 && p.x() < width - 0.5 && p.y() < height - 0.5)) return false;
  x = static_cast<int>(p.x() + 0.5);
  y = static_cast<int>(p.y() + 0.5);
  if (x >= width) x = width - 1;
  if (y >= height) y = height - 1;
  return true;
}

}  // namespace tetmvs::silhouette
