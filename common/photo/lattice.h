// Sampling helpers for the photoconsist stage (paper section 2.3): the triangular
// lattice on a face, spaced so that no pixel is skipped when it is projected into
// the images, and pixel footprints.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "common/photo/views.h"

namespace tetmvs::photo {

// Smallest pixel footprint (depth / focal, world units per pixel) at X over the views
// in which X is in front and inside the image; +infinity when no view sees X.
double finest_footprint(const Views& views, const Eigen::Vector3d& X);

// Largest length in pixels of the projections of the edges of triangle (a, b, c) over
// the views that have all three corners in front and the centroid inside the image;
// 0 when no view sees the triangle.
double max_projected_edge_px(const Views& views, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                             const Eigen::Vector3d& c);

// Segments per edge of a lattice on (a, b, c) whose neighbouring points are at most
// max_px pixels apart in every view that sees it: ceil(max_projected_edge_px / max_px),
// at least 1. (Round it up to a power of two to share points with the 4 children.)
int lattice_divisions(const Views& views, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                      const Eigen::Vector3d& c, double max_px = 1.0);

// The (n+1)(n+2)/2 points a + (i/n)(b - a) + (j/n)(c - a), i, j >= 0, i + j <= n, in
// order of j then i. Appends to out.
void triangle_lattice(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                      int n, std::vector<Eigen::Vector3d>& out);

}  // namespace tetmvs::photo
