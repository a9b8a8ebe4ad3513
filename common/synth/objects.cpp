#include "common/synth/objects.h"

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

#include "common/error.h"

namespace tetmvs::synth {

namespace {
struct PPoint { double r, z; int region; };
}  // namespace

void Profile::line(double r0, double z0, double r1, double z1, int region) {
  pieces_.push_back({false, r0, z0, r1, z1, 0, region});
}
void Profile::arc(double rc, double zc, double rad, double a0, double a1, int region) {
  pieces_.push_back({true, rc, zc, rad, a0, a1, region});
}

TriMesh Profile::revolve(double h) const {
  require(h > 0, "Profile::revolve: edge length must be > 0");
  require(!pieces_.empty(), "Profile::revolve: empty profile");
  // Sample the profile: each piece split into equal steps of at most h.
  std::vector<PPoint> pts;
  for (std::size_t k = 0; k < pieces_.size(); ++k) {
    const Piece& p = pieces_[k];
    const double len = p.is_arc ? std::abs(p.e - p.d) * p.c : std::hypot(p.c - p.a, p.d - p.b);
    const int n = std::max(1, static_cast<int>(std::ceil(len / h)));
    for (int i = 0; i < n; ++i) {  // end point belongs to the next piece
      const double s = static_cast<double>(i) / n;
      PPoint q;
      if (p.is_arc) {
        const double a = p.d + s * (p.e - p.d);
        q = {p.a + p.c * std::cos(a), p.b + p.c * std::sin(a), p.region};
      } else {
        q = {p.a + s * (p.c - p.a), p.b + s * (p.d - p.b), p.region};
      }
      pts.push_back(q);
    }
  }
  if (!periodic_) {  // final end point
    const Piece& p = pieces_.back();
    if (p.is_arc) pts.push_back({p.a + p.c * std::cos(p.e), p.b + p.c * std::sin(p.e), p.region});
    else pts.push_back({p.c, p.d, p.region});
    require(std::abs(pts.front().r) < 1e-12 && std::abs(pts.back().r) < 1e-12,
            "Profile::revolve: an open profile must start and end on the axis");
  }
  for (auto& q : pts) {
    if (std::abs(q.r) < 1e-12) q.r = 0;
    require(q.r >= 0, "Profile::revolve: profile has r < 0");
    require(periodic_ ? q.r > 0 : true, "Profile::revolve: a periodic profile must stay off the axis");
  }
  // Rings.
  TriMesh m;
  const int nr = static_cast<int>(pts.size());
  std::vector<int> first(nr), count(nr);
  for (int i = 0; i < nr; ++i) {
    const int n = pts[i].r == 0 ? 1 : std::max(3, static_cast<int>(std::ceil(2 * std::numbers::pi * pts[i].r / h)));
    first[i] = static_cast<int>(m.V.size());
    count[i] = n;
    const double off = (i % 2) * 0.5;
    for (int j = 0; j < n; ++j) {
      const double a = 2 * std::numbers::pi * (j + off) / n;
      m.V.emplace_back(pts[i].r * std::cos(a), pts[i].r * std::sin(a), pts[i].z);
    }
  }
  std::vector<float> region;
  auto stitch = [&](int ra, int rb, int reg) {
    const int na = count[ra], nb = count[rb];
    const double offa = (ra % 2) * 0.5, offb = (rb % 2) * 0.5;
    auto A = [&](int k) { return first[ra] + (k % na); };
    auto B = [&](int k) { return first[rb] + (k % nb); };
    int ia = 0, ib = 0;
    while (ia < na || ib < nb) {
      const double ta = (ia + 1 + offa) / na, tb = (ib + 1 + offb) / nb;
      Eigen::Vector3i t;
      if (ib >= nb || (ia < na && ta <= tb)) {
        t = {A(ia), B(ib), A(ia + 1)};
        ++ia;
      } else {
        t = {A(ia), B(ib), B(ib + 1)};
        ++ib;
      }
      if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) {
        m.F.push_back(t);
        region.push_back(static_cast<float>(reg));
      }
    }
  };
  for (int i = 0; i + 1 < nr; ++i) stitch(i, i + 1, pts[i].region);
  if (periodic_) stitch(nr - 1, 0, pts[nr - 1].region);
  m.fprops.emplace_back("region", std::move(region));
  if (signed_volume(m) < 0) flip_orientation(m);
  compute_vertex_normals(m);
  return m;
}

TriMesh make_sphere(double h) {
  Profile p;
  p.arc(0, 0, 1, -std::numbers::pi / 2, std::numbers::pi / 2, kBody);
  return p.revolve(h);
}

TriMesh make_torus(double h) {
  Profile p;
  p.arc(1.0, 0, 0.4, 0, 2 * std::numbers::pi, kBody);
  p.set_periodic(true);
  TriMesh m = p.revolve(h);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(60.0 * std::numbers::pi / 180.0, Eigen::Vector3d::UnitX()).toRotationMatrix();
  transform(m, R, 1.0, Eigen::Vector3d::Zero());
  return m;
}

TriMesh make_cup(double h, bool filled) {
  // Outer radius 1, height 2 (z from 0 to 2), wall 0.25, bottom 0.3, rounded rim and corners.
  const double Ro = 1.0, H = 2.0, w = 0.25, b = 0.3, f = 0.1, Ri = Ro - w, rr = w / 2;
  Profile p;
  p.line(0, 0, Ro - f, 0, kBody);                            // outer bottom
  p.arc(Ro - f, f, f, -std::numbers::pi / 2, 0, kBody);                   // outer bottom corner
  p.line(Ro, f, Ro, H - rr, kBody);                          // outer wall
  if (filled) {
    p.arc(Ro - rr, H - rr, rr, 0, std::numbers::pi / 2, kBody);           // outer half of the rim
    p.line(Ro - rr, H, 0, H, kBody);                         // flat lid
  } else {
    p.arc(Ri + rr, H - rr, rr, 0, std::numbers::pi, kBody);               // rounded rim
    p.line(Ri, H - rr, Ri, b + f, kCavity);                  // inner wall (down)
    p.arc(Ri - f, b + f, f, 0, -std::numbers::pi / 2, kCavity);           // inner bottom corner
    p.line(Ri - f, b, 0, b, kCavity);                        // inner bottom
  }
  return p.revolve(h);
}

TriMesh make_two(double h) {
  TriMesh a = make_sphere(h / 0.75);
  transform(a, Eigen::Matrix3d::Identity(), 0.75, Eigen::Vector3d(-0.85, 0, 0));
  TriMesh b = make_sphere(h / 0.55);
  transform(b, Eigen::Matrix3d::Identity(), 0.55, Eigen::Vector3d(0.75, 0, 0));
  append(a, b);
  return a;
}

TriMesh make_horn(double h) {
  // Horn: radius 0.12 at its base on the sphere, 0.04 at the tip, tip cap at z = 2.1.
  const double rb = 0.12, rt = 0.04, ztip = 2.1;
  const double ab = std::asin(rb);  // angle of the base circle, seen from the sphere centre: z = cos(ab)
  Profile p;
  p.arc(0, 0, 1, -std::numbers::pi / 2, std::numbers::pi / 2 - ab, kBody);
  p.line(rb, std::cos(ab), rt, ztip - rt, kProtrusion);
  p.arc(0, ztip - rt, rt, 0, std::numbers::pi / 2, kProtrusion);
  return p.revolve(h);
}

TriMesh make_relief(double h) {
  TriMesh m = make_sphere(h / 1.25);  // the relief's slopes (up to about 1) stretch the edges
  const auto egg_crate = [](const Eigen::Vector3d& u, double wavelength) {
    const double k = 2 * std::numbers::pi / wavelength;
    return std::sin(k * u.x()) * std::sin(k * u.y()) * std::sin(k * u.z());
  };
  for (Eigen::Vector3d& v : m.V) {
    const Eigen::Vector3d u = v.normalized();
    v = u * (1.0 + 0.025 * egg_crate(u, 0.25) + 0.008 * egg_crate(u, 0.1));
  }
  compute_vertex_normals(m);
  return m;
}

std::vector<std::string> object_names() { return {"sphere", "torus", "cup", "cup_filled", "two", "horn", "relief"}; }

TriMesh make_object(const std::string& name, double h) {
  if (name == "sphere") return make_sphere(h);
  if (name == "torus") return make_torus(h);
  if (name == "cup") return make_cup(h, false);
  if (name == "cup_filled") return make_cup(h, true);
  if (name == "two") return make_two(h);
  if (name == "horn") return make_horn(h);
  if (name == "relief") return make_relief(h);
  std::string all;
  for (const auto& n : object_names()) all += " " + n;
  fail("unknown object '", name, "' (known:", all, ")");
}

}  // namespace tetmvs::synth
