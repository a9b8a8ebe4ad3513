// Reading a dataset folder (Middlebury layout) into a Scene.
//
// A folder holds exactly one <prefix>_par.txt; the images it names; optionally
// silhouettes/ with masks (255 = object) named as find_mask says; optionally
// <prefix>_good_silhouette_images.txt (only those views get a silhouette); optionally a
// Middlebury README.txt stating the bounding box, or bbox.txt (two lines: min, max).
#pragma once
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "common/param_binding.h"
#include "common/params.h"
#include "common/scene.h"

namespace tetmvs {

struct SilhouetteOptions {
  double threshold = 0.19;  // max(R,G,B)/255 above this is object
  int dilate = 10;          // pixels
  int erode = 7;            // pixels
  double min_area = 0.002;  // fraction of the image; smaller blobs are removed
  bool fill_holes = true;   // background regions not touching the border become object
  void check() const;       // throws Error on a value outside its documented range
  static SilhouetteOptions from(const Params& p);

  static constexpr auto params() {  // the fields that hold parameters (common/param_binding.h)
    return std::to_array<ParamField<SilhouetteOptions>>({
        {"ingest.sil_threshold", &SilhouetteOptions::threshold},
        {"ingest.sil_dilate", &SilhouetteOptions::dilate},
        {"ingest.sil_erode", &SilhouetteOptions::erode},
        {"ingest.sil_min_area", &SilhouetteOptions::min_area},
        {"ingest.sil_fill_holes", &SilhouetteOptions::fill_holes},
    });
  }
};

// Silhouette of an RGB image with a dark background (the Middlebury recipe:
// threshold, dilate, erode, then small-blob removal and hole filling).
cv::Mat silhouette_from_dark_background(const cv::Mat& rgb, const SilhouetteOptions& o);

// Bounding box stated by a bbox.txt (two lines of three numbers) or by a Middlebury
// README.txt ("The (tight) bounding box for the ... model is (x y z) (x y z)").
// Returns nothing when the folder states none; throws on a malformed file.
std::optional<Eigen::AlignedBox3d> read_stated_box(const std::filesystem::path& dir,
                                                   std::string* source);

// Visual hull by voxel carving inside `region`: a voxel centre survives when it projects
// inside the silhouette of every view that has one and sees it (pixels outside an
// image never carve). Returns the bounding box of the surviving voxels (empty box when
// none survive) and their count.
Eigen::AlignedBox3d visual_hull_box(const Scene& s, const Eigen::AlignedBox3d& region, int res,
                                    long* voxels = nullptr);

// The scene box from the silhouettes: the visual hull's box inside `region`, carved again
// inside that box grown by 10 % for a tighter estimate, padded by ingest.box_padding of its
// diagonal (ingest.hull_resolution voxels along the longest side). An empty hull is an
// Error naming `where`, ending with `hint` (how to state a box instead).
Eigen::AlignedBox3d padded_hull_box(const Scene& s, const Eigen::AlignedBox3d& region, const Params& p,
                                    const std::string& where, const std::string& hint);

// Least-squares meeting point of the optical axes and a cube around it covering what the
// cameras see at that depth: the search region when nothing states a box.
Eigen::AlignedBox3d camera_search_region(const std::vector<Camera>& cams);

// Refuses, before any image is decoded, images whose headers declare more pixels than the
// memory budget holds for ingest (about 9 bytes a pixel: the RGB image, its silhouette and
// the copies written), naming the largest.
void check_images_budget(const Params& p, const std::vector<std::filesystem::path>& images);

// The mask of the image `image_name` (a name relative to the image folder) in `sildir`, by the
// common conventions in this order: the image's own name (Middlebury), its stem with .png
// (DTU, IDR/NeuS: `a.jpg` -> `a.png`), the name with .png appended (COLMAP: `a.jpg.png`).
// Nothing when none of them is a file.
std::optional<std::filesystem::path> find_mask(const std::filesystem::path& sildir, const std::string& image_name);

// A warning naming the views of a dataset with a silhouettes/ folder that have no mask
// there (they carry no silhouette); none when every view that should have one has it.
void warn_missing_masks(const std::filesystem::path& sildir, const std::vector<std::string>& missing, int views);

// The scene's geometry as read: nonsense refused and suspicious parts warned about
// (check_scene_geometry, common/scene.h), naming `where`. (The images are checked by ingest.)
void vet_scene(const Scene& s, const std::filesystem::path& where);

// Reads the whole folder into a Scene (images, silhouettes, box). Every failure is an
// Error naming the file and the problem.
Scene read_dataset(const std::filesystem::path& dir, const Params& p);

// A contact sheet: thumbnails of every view with its silhouette outlined (green) or
// marked "no silhouette", for a person to check the silhouettes at a glance.
cv::Mat contact_sheet(const Scene& s, int thumb_width = 160);

}  // namespace tetmvs
