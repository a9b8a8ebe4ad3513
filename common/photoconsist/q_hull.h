// photo.q_hull: in a scene without any silhouette, the visual-hull test of the photoconsist
// stage from level 1 on (and of the face scores) uses silhouettes estimated from Q of the
// previous levels (common/q_silhouettes.h, shared with label: the points consistent in a
// view splatted, closed, holes filled, grown by photo.q_hull_margin_px). Without a hull photoconsist scores the
// whole box and marks a thick false band in the air around the object; this bounds it at
// the source (docs/colmap.md).
#pragma once
#include <opencv2/core.hpp>
#include <vector>

#include "common/photoconsist/files.h"
#include "common/photoconsist/options.h"
#include "common/scene.h"
#include "common/tetmesh/tetmesh.h"

namespace tetmvs::photoconsist {

struct QHull {
  std::vector<cv::Mat> sil;  // one per view (empty Mat: no estimate), or empty: none
  int views = 0;             // views given an estimate (0: use the scene's silhouettes)
};

// Nothing (views 0) when photo.q_hull is off, the scene has a silhouette in some view, or
// Q is empty. lat: the mesh's level-0 lattice (cell sizes per level).
QHull estimate_q_hull(const Scene& scene, const LeveledPoints& q, const tet::Lattice& lat, const Options& o);

}  // namespace tetmvs::photoconsist
