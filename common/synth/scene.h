// Synthetic scenes: cameras (from a par file, a ring, a hemisphere or a cap), the object placed
// to fill a box, and rendering into a Middlebury-style dataset folder:
//   <prefix>_par.txt, <prefix>NNNN.png, silhouettes/<prefix>NNNN.png (255 = object),
//   bbox.txt (min x y z / max x y z), gt.ply (the exact ground truth mesh, world frame,
//   per-face float "region": 0 body, 1 cavity, 2 protrusion), synth.json (how it was made).
#pragma once
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/camera.h"
#include "common/param_binding.h"
#include "common/synth/texture.h"
#include "common/trimesh/trimesh.h"

namespace tetmvs::synth {

// Cameras on a horizontal ring (world up = +z) around `target`, looking at it. Image
// w x h, principal point at the image centre, focal f (pixels). Names "<i>" (1-based).
std::vector<Camera> ring_cameras(int n, double elevation_deg, double radius, const Eigen::Vector3d& target,
                                 int w, int h, double focal);
// Cameras spread evenly (Fibonacci spiral) over the upper hemisphere, elevations 10..75 deg.
std::vector<Camera> hemisphere_cameras(int n, double radius, const Eigen::Vector3d& target, int w, int h,
                                       double focal);
// Cameras spread evenly (Fibonacci spiral) over a cap above `target`, elevations 50..85 deg:
// all within about 40 deg of their mean direction, a capture from one side like DTU's.
std::vector<Camera> cap_cameras(int n, double radius, const Eigen::Vector3d& target, int w, int h, double focal);
// Camera looking from C at target with world up `up` (image v points down).
Camera look_at(const Eigen::Vector3d& C, const Eigen::Vector3d& target, const Eigen::Vector3d& up, int w,
               int h, double focal);
// n of the cameras, evenly spaced in their order (all when n <= 0 or n >= size).
std::vector<Camera> subset_views(const std::vector<Camera>& cams, int n);
// Cameras for images resized to w x h (K scaled about pixel centres).
void resize_cameras(std::vector<Camera>& cams, int w, int h);
// Reads the box from a Middlebury README.txt ("... bounding box ... is (x y z) (x y z)").
// Returns false when the file has no such sentence.
bool read_readme_box(const std::filesystem::path& readme, Eigen::AlignedBox3d& box);

// The scene's up direction: from the box centre toward the mean camera centre (or the
// normal of the cameras' plane when the cameras surround the centre), snapped to the
// nearest world axis when within 30 degrees of it.
Eigen::Vector3d scene_up(const std::vector<Camera>& cams, const Eigen::Vector3d& centre);

struct Placement {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  double scale = 1;
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  Eigen::Vector3d apply(const Eigen::Vector3d& x) const { return scale * (R * x) + t; }
};
// Rotates the canonical +z to `up`, then scales and centres the mesh so its bounding box
// fills `fill` of the box along the tightest axis.
Placement fit_to_box(const TriMesh& canonical, const Eigen::AlignedBox3d& box, const Eigen::Vector3d& up,
                     double fill);

// Builds the object `name` (see objects.h, or a .ply path) placed in `box`, with world
// triangle edges of about `edge` (world units). A PLY file is kept as is (only placed).
TriMesh make_placed_object(const std::string& name, const Eigen::AlignedBox3d& box, const Eigen::Vector3d& up,
                           double fill, double edge, Placement* placement = nullptr);

struct ShadingOptions {
  Eigen::Vector3d light = Eigen::Vector3d::UnitZ();  // direction toward the light (unit)
  double ambient = 0.3;      // added to diffuse * max(0, n . light)
  double diffuse = 0.7;
  double background = 0.03;  // grey level of the background
  double noise = 0.01;       // Gaussian noise sigma (grey levels in [0, 1])
  int supersample = 3;       // s x s samples per pixel (anti-aliasing)
  std::uint64_t seed = 1;    // noise seed (the view index is mixed in)
};

struct RenderedView {
  cv::Mat rgb;   // CV_8UC3, RGB order
  cv::Mat mask;  // CV_8U, 255 where the pixel centre sees the mesh
};

// One view of the mesh (vertex normals required). Deterministic for (seed, view).
RenderedView render_view(const TriMesh& m, const Camera& cam, const SolidTexture& tex,
                         const ShadingOptions& opt, int view);

struct DatasetInfo {
  std::string prefix;     // file prefix (<prefix>_par.txt, <prefix>0001.png...)
  Eigen::AlignedBox3d box;
  nlohmann::json meta;    // written to synth.json
};
// Renders every camera (OpenMP over views) and writes the dataset folder. Camera names
// are replaced by <prefix>NNNN.png. Returns the cameras as written.
std::vector<Camera> write_dataset(const std::filesystem::path& dir, const TriMesh& gt,
                                  std::vector<Camera> cams, const SolidTexture& tex,
                                  const ShadingOptions& shading, const DatasetInfo& info);

}  // namespace tetmvs::synth

namespace tetmvs::synth {

// Everything the synth program needs (parameters synth.* of params/defaults.json, bound in
// params(); the rest from its command line).
struct SynthConfig {
  std::string object;            // objects.h name, or a .ply file
  std::string cameras;           // a par file, "ring", "hemisphere" or "cap"
  int views = 0;                 // 0 = all (par) / 48 (generated)
  int width = 0, height = 0;     // 0 = 640 x 480 (par: the images are taken as 640 x 480 unless given)
  double texture = 1, noise = 0.01;
  std::uint64_t seed = 1;
  int supersample = 3;
  double edge_px = 0.8, fill = 0.85, texture_min_px = 3, texture_max_px = 40;
  double ambient = 0.3, diffuse = 0.7, background = 0.03;
  double ring_elevation = 20, camera_radius = 0.65, focal = 0, box_size = 0.07;
  std::optional<Eigen::AlignedBox3d> box;  // scene box; default: the par folder's README.txt/bbox.txt, or the cube
  std::string prefix;            // default: the object name (a file's stem)
  void check() const;            // throws Error on a parameter outside its documented range

  static constexpr auto params() {  // the fields that hold parameters (common/param_binding.h)
    return std::to_array<ParamField<SynthConfig>>({
        {"synth.texture", &SynthConfig::texture},
        {"synth.noise", &SynthConfig::noise},
        {"synth.seed", &SynthConfig::seed},
        {"synth.supersample", &SynthConfig::supersample},
        {"synth.edge_px", &SynthConfig::edge_px},
        {"synth.fill", &SynthConfig::fill},
        {"synth.texture_min_px", &SynthConfig::texture_min_px},
        {"synth.texture_max_px", &SynthConfig::texture_max_px},
        {"synth.ambient", &SynthConfig::ambient},
        {"synth.diffuse", &SynthConfig::diffuse},
        {"synth.background", &SynthConfig::background},
        {"synth.ring_elevation", &SynthConfig::ring_elevation},
        {"synth.camera_radius", &SynthConfig::camera_radius},
        {"synth.focal", &SynthConfig::focal},
        {"synth.box_size", &SynthConfig::box_size},
    });
  }
};

// Builds the scene and writes the dataset folder; returns the synth.json content.
nlohmann::json synthesize(const SynthConfig& c, const std::filesystem::path& out);

}  // namespace tetmvs::synth
