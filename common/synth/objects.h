// Closed triangle meshes with outward normals for synthetic scenes. Each object is built
// in a canonical frame (up = +z, size about 2 units) with a target edge length, and
// carries a per-face float property "region": 0 body, 1 cavity, 2 protrusion.
#pragma once
#include <string>
#include <vector>

#include "common/trimesh/trimesh.h"

namespace tetmvs::synth {

enum Region : int { kBody = 0, kCavity = 1, kProtrusion = 2 };

// A closed curve in the (r, z) half-plane (r >= 0), revolved about the z axis. An open
// profile must start and end on the axis (r == 0); a closed one (periodic) must stay
// off the axis. Pieces are added in order; each carries a region label.
class Profile {
 public:
  void line(double r0, double z0, double r1, double z1, int region);
  // Arc around (rc, zc) of radius rad from angle a0 to a1 (radians, measured from +r toward +z).
  void arc(double rc, double zc, double rad, double a0, double a1, int region);
  void set_periodic(bool p) { periodic_ = p; }
  // Revolves with triangle edges of about h. The result is closed, with outward normals
  // (orientation fixed by the sign of the volume) and vertex normals.
  TriMesh revolve(double h) const;

 private:
  struct Piece { bool is_arc; double a, b, c, d, e; int region; };
  std::vector<Piece> pieces_;
  bool periodic_ = false;
};

// Canonical objects (edge length h in canonical units).
TriMesh make_sphere(double h);                      // radius 1
TriMesh make_torus(double h);                       // R = 1, r = 0.4, axis tilted 60 deg from z about x
TriMesh make_cup(double h, bool filled = false);    // radius 1, height 2, open at +z; filled = its convex lid closed
TriMesh make_two(double h);                         // two disjoint spheres (r 0.75 and 0.55) side by side along x
TriMesh make_horn(double h);                        // sphere r 1 with a thin horn along +z up to z = 2.1
// Sphere r 1 with a relief of two scales, moved along the radius: bumps of wavelength 0.25 and
// height +-0.025, and on them ripples of wavelength 0.1 and height +-0.008 (on dinoRing's
// cameras about 38 px and 4 px, then 15 px and 1.2 px): geometric detail for the final mesh to
// keep.
TriMesh make_relief(double h);

// Names understood by make_object: sphere torus cup cup_filled two horn relief.
std::vector<std::string> object_names();
TriMesh make_object(const std::string& name, double h);

}  // namespace tetmvs::synth
