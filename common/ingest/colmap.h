// COLMAP reconstructions (sparse models) as a dataset: reading and writing the text
// (cameras.txt, images.txt, points3D.txt) and binary (.bin) model files, the cameras in
// this project's convention, undistortion of the images, and the scene of a COLMAP
// workspace (images/ + sparse/ or sparse/0/).
//
// Conventions, exactly as COLMAP documents them (doc/format.rst, doc/cameras.rst):
//  - the pose (QW QX QY QZ, TX TY TZ) maps world to camera: X_cam = R(q) X + t, with R(q)
//    the rotation of the unit Hamilton quaternion q (the one Eigen::Quaterniond gives);
//    the camera centre is -R^T t; x right, y down, z forward (as Camera).
//  - pixel coordinates have their origin at the upper-left CORNER of the upper-left pixel,
//    so that pixel's centre is (0.5, 0.5). This project puts that centre at (0, 0)
//    (common/camera.h): cx, cy and every 2-D observation are shifted by -0.5.
//  - models: SIMPLE_PINHOLE (f cx cy), PINHOLE (fx fy cx cy) are read as they are;
//    SIMPLE_RADIAL (f cx cy k), RADIAL (f cx cy k1 k2), OPENCV (fx fy cx cy k1 k2 p1 p2)
//    and FULL_OPENCV (fx fy cx cy k1 k2 p1 p2 k3 k4 k5 k6) are undistorted (OpenCV's remap
//    with the map cv::initUndistortRectifyMap would give) to a pinhole camera with the same K (their distortion is OpenCV's model with the
//    other coefficients zero); the fisheye models and FOV are refused with an error
//    that points to `colmap image_undistorter`.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "common/camera.h"
#include "common/params.h"
#include "common/scene.h"

namespace tetmvs::colmap {

inline constexpr std::uint64_t kNoPoint = ~std::uint64_t(0);  // POINT3D_ID -1

struct ModelInfo {
  int id;
  const char* name;
  int num_params;
};
// COLMAP's camera models (ids as in the binary files). nullptr when unknown.
const ModelInfo* model_by_name(const std::string& name);
const ModelInfo* model_by_id(int id);
std::string known_models();  // "SIMPLE_PINHOLE, PINHOLE, ..." for error messages

struct Intrinsics {
  std::uint32_t id = 0;
  int model = 1;                // ModelInfo::id
  std::uint64_t width = 0, height = 0;
  std::vector<double> params;   // COLMAP order and pixel convention
  std::string where;            // "cameras.txt:7" (for messages)
};

struct Observation {
  double x = 0, y = 0;             // COLMAP pixel coordinates (distorted image)
  std::uint64_t point3d = kNoPoint;
};

struct Image {
  std::uint32_t id = 0;
  Eigen::Vector4d q{1, 0, 0, 0};   // QW QX QY QZ
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  std::uint32_t camera_id = 0;
  std::string name;
  std::vector<Observation> points2d;
  std::string where;               // "images.txt:12"
};

struct TrackElement {
  std::uint32_t image_id = 0, point2d_idx = 0;
};

struct Point3D {
  std::uint64_t id = 0;
  Eigen::Vector3d xyz = Eigen::Vector3d::Zero();
  std::uint8_t rgb[3] = {0, 0, 0};
  double error = 0;
  std::vector<TrackElement> track;
};

struct Model {
  std::map<std::uint32_t, Intrinsics> cameras;
  std::vector<Image> images;    // in IMAGE_ID order
  std::vector<Point3D> points;  // in file order
  std::vector<std::filesystem::path> files;  // the three files read
};

// Reads a model folder: the binary files when cameras.bin, images.bin and points3D.bin
// are all there (COLMAP prefers them too), else the text files. Validates everything
// (camera ids, image ids, point ids, track indices, parameter counts, finite numbers);
// every failure is an Error naming the file and the line (text) or the record (binary).
Model read_model(const std::filesystem::path& dir);
Model read_text_model(const std::filesystem::path& dir);
Model read_binary_model(const std::filesystem::path& dir);
// True when dir holds a model (cameras.txt or cameras.bin).
bool is_model_dir(const std::filesystem::path& dir);

// Writers (used by synth --colmap and the tests); %.17g, so text round-trips exactly.
void write_text_model(const std::filesystem::path& dir, const Model& m);
void write_binary_model(const std::filesystem::path& dir, const Model& m);

// Rotation of a quaternion (w, x, y, z), normalised first; and back (w >= 0).
Eigen::Matrix3d quaternion_to_rotation(const Eigen::Vector4d& q);
Eigen::Vector4d rotation_to_quaternion(const Eigen::Matrix3d& R);

// The pinhole part of an intrinsics record in this project's convention (cx, cy - 0.5)
// and the OpenCV distortion coefficients (k1 k2 p1 p2 [k3 k4 k5 k6]; empty for the
// pinhole models). Throws for the models that cannot be undistorted here.
struct Pinhole {
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();
  std::vector<double> dist;
  bool distorted() const;
};
Pinhole pinhole_of(const Intrinsics& c);

// The camera of an image (name, K, R, t, width, height) after undistortion.
Camera camera_of(const Model& m, const Image& im);

// Where COLMAP's model puts world point X in the (distorted) image of `im`, in COLMAP
// pixel coordinates: what points2D records. For the supported models.
Eigen::Vector2d project_colmap(const Intrinsics& c, const Image& im, const Eigen::Vector3d& X);

// Undistorts an image of camera `p` (any type; masks with nearest = true) to the pinhole
// camera with the same K. Pixels that map outside the source become 0.
cv::Mat undistort(const cv::Mat& img, const Pinhole& p, bool nearest = false);

// A workspace: where the model and the images are.
struct Layout {
  std::filesystem::path root;       // the workspace (dataset name, bbox.txt, silhouettes/)
  std::filesystem::path model_dir;  // the folder holding cameras.txt / cameras.bin
  std::filesystem::path image_dir;  // image names are relative to it
};
// dir is a COLMAP workspace (images/ with sparse/ or sparse/0/ holding a model), or a
// model folder itself (its images in images/ beside it or one or two levels up).
// nullopt when dir holds no COLMAP model (a Middlebury folder).
std::optional<Layout> find_layout(const std::filesystem::path& dir);

// A box "minx,miny,minz,maxx,maxy,maxz" (commas or spaces) from parameter `key`;
// nullopt when the parameter is empty. Throws naming the key when malformed.
std::optional<Eigen::AlignedBox3d> box_param(const Params& p, const std::string& key);

// Robust box of a point cloud: per axis the [pct, 100 - pct] percentiles of the points
// inside `roi` (all when none), grown by padding * its diagonal, and clipped to the roi.
// Throws when fewer than min_points points are left.
Eigen::AlignedBox3d robust_box(const std::vector<Eigen::Vector3d>& pts, double pct, double padding,
                               const std::optional<Eigen::AlignedBox3d>& roi, int min_points,
                               const std::string& what);

// The scene of a workspace (views in image-name order, images loaded and undistorted, optional silhouettes/ with
// same-named masks, the box: the ingest.box parameter, a bbox.txt in the workspace, the
// visual hull of the silhouettes, or the robust box of the sparse points, in this order).
Scene read_scene(const Layout& l, const Params& p);

}  // namespace tetmvs::colmap
