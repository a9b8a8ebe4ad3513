// Silhouettes estimated from the points Q, for scenes without any silhouette (a COLMAP
// workspace without masks, docs/colmap.md). Used by photoconsist (its visual-hull test from
// level 1 on) and by label (cells outside are exterior, points of Q outside are dropped), with
// one parameter set, photo.q_hull*.
//
// Per view: the points of Q photo-consistent in it, splatted as discs of splat_cells cells
// (at each point's depth, at least 1 pixel), closed by a disc of max(close_px, close_cells
// cells projected at Q's median depth), holes filled, grown by margin_px. Q's points are about
// a cell apart: small splats joined by a closing of about a cell fill the object's outline
// without growing it by the splat size.
#pragma once
#include <array>
#include <vector>

#include <opencv2/core.hpp>

#include "common/param_binding.h"
#include "common/qpoints.h"
#include "common/scene.h"

namespace tetmvs {
class Params;

struct QSilhouetteOptions {
  bool on = true;            // photo.q_hull: estimate them at all
  double splat_cells = 0.5;  // photo.q_hull_splat_cells: splat radius, in cells
  double close_cells = 1.0;  // photo.q_hull_close_cells: closing radius, in cells at Q's median depth ...
  double close_px = 6;       // photo.q_hull_close_px: ... and at least this many pixels
  double margin_px = 4;      // photo.q_hull_margin_px: the estimate is grown by this
  int min_points = 50;       // photo.q_hull_min_points: views with fewer consistent points get none
  void check() const;        // throws Error on a value outside its documented range
  static QSilhouetteOptions from_params(const Params& p);  // reads photo.q_hull*, then check()s

  static constexpr auto params() {  // the fields that hold parameters (common/param_binding.h)
    return std::to_array<ParamField<QSilhouetteOptions>>({
        {"photo.q_hull", &QSilhouetteOptions::on},
        {"photo.q_hull_splat_cells", &QSilhouetteOptions::splat_cells},
        {"photo.q_hull_close_cells", &QSilhouetteOptions::close_cells},
        {"photo.q_hull_close_px", &QSilhouetteOptions::close_px},
        {"photo.q_hull_margin_px", &QSilhouetteOptions::margin_px},
        {"photo.q_hull_min_points", &QSilhouetteOptions::min_points},
    });
  }
};

// One CV_8U mask per view (255 = object), an empty Mat for views that have a silhouette or
// fewer than min_points consistent points; all empty when the scene has a silhouette in some
// view, `on` is false or q is empty. cell: the cell size (world units) of Q's level.
std::vector<cv::Mat> estimate_q_silhouettes(const Scene& s, const QPoints& q, double cell, const QSilhouetteOptions& o);

// The splat, close, fill and grow steps alone, with the splat radius and the closing radius
// given (world units and pixels); views with a silhouette get none.
std::vector<cv::Mat> q_silhouettes(const Scene& s, const QPoints& q, double splat, double close_px, double margin_px,
                                   int min_points);

}  // namespace tetmvs
