// The scene: cameras, images, silhouettes and bounding box, as `ingest` writes them
// to scene.h5 (schema: schemas/scene.md).
#pragma once
#include <Eigen/Geometry>
#include <filesystem>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "common/camera.h"

namespace tetmvs {

struct Scene {
  std::vector<Camera> cams;       // width/height set
  std::vector<cv::Mat> rgb;       // CV_8UC3, RGB channel order, one per camera
  std::vector<cv::Mat> grey;      // CV_32F in [0, 1], filled by load_grey()
  std::vector<cv::Mat> sil;       // CV_8U, 255 = object; empty Mat when the view has none
  Eigen::AlignedBox3d box;        // bounding box of the object
  std::string box_source;         // "bbox.txt", "README.txt", "visual hull", "given"
  std::string dataset;            // dataset name (folder name)

  int size() const { return static_cast<int>(cams.size()); }
  bool has_silhouette(int v) const { return !sil[v].empty(); }
  int num_silhouettes() const;
  // Converts rgb to float grey (Rec. 601 luma) into `grey`.
  void load_grey();
  // True when pixel (u,v) (nearest) of view v is inside a valid silhouette.
  // Views without silhouette and pixels outside the image return `outside_value`.
  bool in_silhouette(int v, double u, double vv, bool outside_value) const;
};

// The largest angle (degrees) between a camera's direction to the box centre and the mean of
// those directions: about 46 for DTU's cameras, which all look from above, 83 for dinoRing's
// ring (90 - the elevation for a ring).
double camera_spread_deg(const Scene& s);

class Params;
// A capture from one side (docs/real-photos.md): every camera looks at the box centre from
// within photo.one_sided_deg of the cameras' mean direction (0: never). Under a surface seen
// from one side, every view scores the matter below it against the surface's texture, and
// visibility finds no interior there. Such a scene gets occlusion-aware scoring
// (photo.occlusion) and, when it has silhouettes and no hull core is set, the hull core at
// label.seed_core_px (label.hull_core_px): `p` is changed so, and the stage's outputs record
// the values used. Returns a sentence for the log, empty when the capture is not one-sided.
std::string adapt_to_one_sided_capture(const Scene& s, Params& p);

// Scenes that cannot give a meaningful reconstruction are refused: Error "<where>: <why>"
// for fewer than two cameras, a box that is not finite, a camera inside the box (the method
// reconstructs an object seen from outside its box), or fewer than two views that see any
// of the box. Returns warnings for the suspicious parts: each view that sees none of the
// box (it faces away, or the box falls outside its image), two cameras with the same pose
// (the Middlebury rings close on themselves: dinoRing's views 2 and 48).
std::vector<std::string> check_scene_geometry(const Scene& s, const std::string& where);
// The images (ingest): Error when every image is uniform (no texture to match, e.g. all
// black); a warning for each uniform one.
std::vector<std::string> check_scene_images(const Scene& s, const std::string& where);

// Reads scene.h5 (validated: schema, shapes, rotations, box, check_scene_geometry's
// refusals). images = false skips the colour images (cameras, box and silhouettes only).
Scene read_scene(const std::filesystem::path& file, bool images = true);

// The datasets and attributes of scene.h5: cameras, images, silhouettes, box.
namespace h5 { template <typename R> class Fields; class File; }
const h5::Fields<Scene>& scene_fields();
// Writes scene_fields() into an open HDF5 file (the caller writes the header and commits),
// after checking that there is a camera and that all images share one size.
void write_scene(h5::File& f, const Scene& s);

inline constexpr const char* kSceneSchema = "tetmvs.scene";
inline constexpr int kSceneVersion = 1;

}  // namespace tetmvs
