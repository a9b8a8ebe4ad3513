// Surface roughness without ground truth: for sample vertices of a mesh, the RMS distance of
// the vertices within `radius` of it to their least-squares plane; the median over the
// samples (and the 90th percentile). A smooth surface sampled finely measures near 0 (a
// sphere of radius R: radius^2 / (4 sqrt(3) R)); facets, bumps and noise raise it. Thin parts
// narrower than the radius (two sheets in one ball) also raise it, so compare the same
// object at the same radius.
#pragma once
#include <cstdint>
#include <vector>

#include "common/camera.h"
#include "common/trimesh/trimesh.h"

namespace tetmvs {

struct Roughness {
  double radius = 0;         // world units
  double median = 0, p90 = 0;  // world units; 0 when samples == 0
  std::int64_t samples = 0;  // sample vertices with enough neighbours (>= 6)
};

// At most `max_samples` vertices, evenly spaced in the vertex order (deterministic).
Roughness surface_roughness(const TriMesh& mesh, double radius, int max_samples = 20000);

// The same with the radius in pixels at the object (pixel_footprint at the centre of the
// mesh's bounding box).
Roughness surface_roughness_px(const TriMesh& mesh, const std::vector<Camera>& cams, double radius_px,
                               int max_samples = 20000);

}  // namespace tetmvs
