#include "common/scene.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numbers>
#include <optional>
#include <sstream>

#include "common/error.h"
#include "common/h5fields.h"
#include "common/image.h"
#include "common/params.h"
#include "common/silhouette/border.h"

namespace tetmvs {

double camera_spread_deg(const Scene& s) {
  const Eigen::Vector3d centre = s.box.center();
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> dir;
  for (const Camera& c : s.cams) {
    const Eigen::Vector3d d = centre - c.centre();
    if (d.norm() > 0) dir.push_back(d.normalized()), mean += dir.back();
  }
  if (dir.empty() || mean.norm() == 0) return 180;
  mean.normalize();
  double spread = 0;
  for (const auto& d : dir) spread = std::max(spread, std::acos(std::clamp(d.dot(mean), -1.0, 1.0)) * 180 / std::numbers::pi);
  return spread;
}

std::string adapt_to_one_sided_capture(const Scene& s, Params& p) {
  const double cone = p.d("photo.one_sided_deg"), spread = camera_spread_deg(s);
  if (!(cone > 0 && spread <= cone)) return {};
  std::ostringstream why;
  why << "the cameras see the object from one side (all within " << spread << " degrees of their mean direction, "
      << "photo.one_sided_deg " << cone << "): photo.occlusion on";
  p.set("photo.occlusion=true");
  if (s.num_silhouettes() > 0 && p.d("label.hull_core_px") == 0 && p.d("label.seed_core_px") > 0) {
    p.set("label.hull_core_px=" + std::to_string(p.d("label.seed_core_px")));
    why << ", label.hull_core_px " << p.d("label.hull_core_px") << " (label.seed_core_px)";
  }
  return why.str();
}

int Scene::num_silhouettes() const {
  int n = 0;
  for (const auto& m : sil) n += !m.empty();
  return n;
}

void Scene::load_grey() {
  grey.resize(rgb.size());
  for (size_t i = 0; i < rgb.size(); ++i) grey[i] = rgb_to_grey(rgb[i]);
}

bool Scene::in_silhouette(int v, double u, double vv, bool outside_value) const {
  if (sil[v].empty()) return outside_value;
  int x, y;  // outside the image the view says nothing (common/silhouette/border.h)
  if (!silhouette::nearest_pixel_in_image(Eigen::Vector2d(u, vv), sil[v].cols, sil[v].rows, x, y)) return outside_value;
  return sil[v].at<std::uint8_t>(y, x) != 0;
}

namespace {

std::uint64_t width(const Scene& s) { return static_cast<std::uint64_t>(s.cams[0].width); }
std::uint64_t height(const Scene& s) { return static_cast<std::uint64_t>(s.cams[0].height); }

// A 3 x 3 matrix per camera, row-major: shape (n, 3, 3).
h5::Array<double> per_camera(const Scene& s, const Eigen::Matrix3d Camera::*member) {
  h5::Array<double> a{{}, {s.cams.size(), 3, 3}};
  for (const auto& c : s.cams)
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) a.data.push_back((c.*member)(r, k));
  return a;
}

std::vector<std::string> camera_names(const Scene& s) {
  std::vector<std::string> names;
  for (const auto& c : s.cams) names.push_back(c.name);
  return names;
}

std::vector<std::array<double, 3>> camera_translations(const Scene& s) {
  std::vector<std::array<double, 3>> t;
  for (const auto& c : s.cams) t.push_back({c.t[0], c.t[1], c.t[2]});
  return t;
}

std::vector<std::array<std::int32_t, 2>> image_sizes(const Scene& s) {
  std::vector<std::array<std::int32_t, 2>> size;
  for (const auto& c : s.cams) size.push_back({c.width, c.height});
  return size;
}

// (n, H, W, 3) RGB; none when the scene holds no images.
std::optional<h5::Array<std::uint8_t>> images(const Scene& s) {
  if (s.rgb.empty()) return std::nullopt;
  const std::uint64_t n = s.cams.size(), H = height(s), W = width(s);
  h5::Array<std::uint8_t> a{std::vector<std::uint8_t>(n * H * W * 3), {n, H, W, 3}};
  for (std::uint64_t i = 0; i < n; ++i)
    for (std::uint64_t y = 0; y < H; ++y)
      std::memcpy(&a.data[(i * H + y) * W * 3], s.rgb[i].ptr(static_cast<int>(y)), W * 3);
  return a;
}

// (n, H, W), 255 inside; zeros for a view without a silhouette.
h5::Array<std::uint8_t> silhouette_masks(const Scene& s) {
  const std::uint64_t n = s.cams.size(), H = height(s), W = width(s);
  h5::Array<std::uint8_t> a{std::vector<std::uint8_t>(n * H * W, 0), {n, H, W}};
  for (std::uint64_t i = 0; i < n; ++i) {
    if (s.sil.size() <= i || s.sil[i].empty()) continue;
    for (std::uint64_t y = 0; y < H; ++y) std::memcpy(&a.data[(i * H + y) * W], s.sil[i].ptr(static_cast<int>(y)), W);
  }
  return a;
}

std::vector<std::uint8_t> silhouette_valid(const Scene& s) {
  std::vector<std::uint8_t> valid(s.cams.size(), 0);
  for (std::size_t i = 0; i < valid.size(); ++i) valid[i] = s.sil.size() > i && !s.sil[i].empty();
  return valid;
}

std::vector<double> corner(const Eigen::Vector3d& p) { return {p.x(), p.y(), p.z()}; }

h5::Fields<Scene> make_scene_fields() {
  h5::Fields<Scene> t;
  t.dataset("/cameras/names", camera_names)
      .dataset("/cameras/K", [](const Scene& s) { return per_camera(s, &Camera::K); })
      .dataset("/cameras/R", [](const Scene& s) { return per_camera(s, &Camera::R); })
      .dataset("/cameras/t", camera_translations)
      .dataset("/cameras/size", image_sizes)
      .dataset("/images/rgb", images)
      .dataset("/silhouettes/mask", silhouette_masks)
      .dataset("/silhouettes/valid", silhouette_valid)
      .dataset("/box/min", [](const Scene& s) { return corner(s.box.min()); })
      .dataset("/box/max", [](const Scene& s) { return corner(s.box.max()); })
      .attr("/box", "source", &Scene::box_source)
      .attr("/", "dataset", &Scene::dataset);
  return t;
}

}  // namespace

const h5::Fields<Scene>& scene_fields() {
  static const h5::Fields<Scene> t = make_scene_fields();
  return t;
}

void write_scene(h5::File& f, const Scene& s) {
  const int n = s.size();
  require(n > 0, f.path().string(), ": a scene needs at least one camera");
  const int W = s.cams[0].width, H = s.cams[0].height;
  for (const auto& c : s.cams)
    require(c.width == W && c.height == H, f.path().string(), ": image ", c.name, " is ", c.width,
            "x", c.height, " but the first image is ", W, "x", H, "; all images must share one size");
  if (!s.rgb.empty())
    for (int i = 0; i < n; ++i) {
      const cv::Mat& m = s.rgb[i];
      require(m.type() == CV_8UC3 && m.cols == W && m.rows == H, "write_scene: bad image ", i);
    }
  scene_fields().write(f, s);
}

Scene read_scene(const std::filesystem::path& file, bool images) {
  auto f = h5::File::open(file, kSceneSchema, kSceneVersion, kSceneVersion);
  const std::string fn = file.string();
  Scene s;
  s.dataset = f.has_attr("/", "dataset") ? f.attr_string("/", "dataset") : "";
  const auto names = f.read_strings("/cameras/names");
  const std::int64_t N = names.size();
  require(N > 0, fn, ": /cameras/names is empty");
  const auto K = f.read<double>("/cameras/K", {N, 3, 3});
  const auto R = f.read<double>("/cameras/R", {N, 3, 3});
  const auto t = f.read<double>("/cameras/t", {N, 3});
  const auto sz = f.read<std::int32_t>("/cameras/size", {N, 2});
  s.cams.resize(N);
  for (std::int64_t i = 0; i < N; ++i) {
    Camera& c = s.cams[i];
    c.name = names[i];
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) {
        c.K(r, k) = K.data[i * 9 + r * 3 + k];
        c.R(r, k) = R.data[i * 9 + r * 3 + k];
      }
    c.t = Eigen::Vector3d(t.data[i * 3], t.data[i * 3 + 1], t.data[i * 3 + 2]);
    c.width = sz.data[i * 2];
    c.height = sz.data[i * 2 + 1];
    require(c.width > 0 && c.height > 0, fn, ": camera ", i, " has a non-positive image size");
    require(is_rotation(c.R, 1e-4), fn, ": camera ", i, " (", c.name, ") R is not a rotation");
    require(c.K(0, 0) > 0 && c.K(1, 1) > 0, fn, ": camera ", i, " has non-positive focal length");
  }
  const int W = s.cams[0].width, H = s.cams[0].height;
  if (images) {
    const auto img = f.read<std::uint8_t>("/images/rgb", {N, H, W, 3});
    s.rgb.resize(N);
    for (std::int64_t i = 0; i < N; ++i) {
      s.rgb[i] = cv::Mat(H, W, CV_8UC3);
      std::memcpy(s.rgb[i].data, &img.data[std::size_t(i) * H * W * 3], std::size_t(H) * W * 3);
    }
  }
  const auto mask = f.read<std::uint8_t>("/silhouettes/mask", {N, H, W});
  const auto valid = f.read<std::uint8_t>("/silhouettes/valid", {N});
  s.sil.resize(N);
  for (std::int64_t i = 0; i < N; ++i) {
    if (!valid.data[i]) continue;
    s.sil[i] = cv::Mat(H, W, CV_8U);
    std::memcpy(s.sil[i].data, &mask.data[std::size_t(i) * H * W], std::size_t(H) * W);
  }
  const auto lo = f.read<double>("/box/min", {3}).data, hi = f.read<double>("/box/max", {3}).data;
  for (int k = 0; k < 3; ++k)
    require(lo[k] < hi[k], fn, ": /box/min must be below /box/max on every axis");
  s.box = Eigen::AlignedBox3d(Eigen::Vector3d(lo[0], lo[1], lo[2]), Eigen::Vector3d(hi[0], hi[1], hi[2]));
  s.box_source = f.has_attr("/box", "source") ? f.attr_string("/box", "source") : "";
  check_scene_geometry(s, fn);  // refusals only: ingest gave the warnings
  return s;
}

namespace {
std::string name_of(const Scene& s, int v) { return "view " + std::to_string(v) + " (" + s.cams[v].name + ")"; }
std::string xyz(const Eigen::Vector3d& p) {
  std::ostringstream os;
  os << "(" << p.x() << " " << p.y() << " " << p.z() << ")";
  return os.str();
}
}  // namespace

std::vector<std::string> check_scene_geometry(const Scene& s, const std::string& where) {
  const int n = s.size();
  require(n >= 2, where, ": ", n, " view; photo-consistency needs at least two views of the object");
  const Eigen::Vector3d lo = s.box.min(), hi = s.box.max();
  require(lo.allFinite() && hi.allFinite() && (hi - lo).allFinite() && (lo.array() < hi.array()).all(), where,
          ": the box ", xyz(lo), " - ", xyz(hi), " is not a finite box with min below max");
  std::vector<std::string> warnings;
  std::vector<int> blind;
  for (int v = 0; v < n; ++v) {
    const Camera& c = s.cams[v];
    const Eigen::Vector3d C = c.centre();
    require(C.allFinite(), where, ": ", name_of(s, v), " has no finite centre");
    require(!s.box.contains(C), where, ": the camera of ", name_of(s, v), " at ", xyz(C), " is inside the box ",
            xyz(lo), " - ", xyz(hi), "; the object must be seen from outside its box: check the box "
            "(bbox.txt, README.txt or ingest.box) and the cameras");
    // sees any of 5 x 5 x 5 points spread over the box (corners, faces, inside)?
    bool sees = false;
    for (int k = 0; k < 125 && !sees; ++k) {
      const Eigen::Vector3d f((k % 5) / 4.0, (k / 5 % 5) / 4.0, (k / 25) / 4.0);
      sees = c.sees(lo + f.cwiseProduct(hi - lo));
    }
    if (!sees) blind.push_back(v);
  }
  if (n - static_cast<int>(blind.size()) < 2)
    fail(where, ": only ", n - static_cast<int>(blind.size()), " of ", n, " views see the box ", xyz(lo), " - ",
         xyz(hi), "; photo-consistency needs two: check the box and the cameras (is a camera facing away?)");
  for (int v : blind)
    warnings.push_back(where + ": " + name_of(s, v) + " sees none of the box (it faces away, or the box lies outside "
                       "its image): it contributes nothing");
  const double diag = s.box.diagonal().norm();
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b)
      if ((s.cams[a].centre() - s.cams[b].centre()).norm() < 1e-6 * diag &&
          (s.cams[a].axis() - s.cams[b].axis()).norm() < 1e-6)
        warnings.push_back(where + ": " + name_of(s, a) + " and " + name_of(s, b) +
                           " have the same pose (centre and direction): their photos agree at any depth, so "
                           "photo-consistency between the two measures nothing");
  return warnings;
}

std::vector<std::string> check_scene_images(const Scene& s, const std::string& where) {
  std::vector<std::string> warnings;
  int uniform = 0;
  for (int v = 0; v < static_cast<int>(s.rgb.size()); ++v) {
    cv::Scalar mean, sd;
    cv::meanStdDev(s.rgb[v], mean, sd);
    if (sd[0] < 0.5 && sd[1] < 0.5 && sd[2] < 0.5) {
      ++uniform;
      std::ostringstream os;
      os << where << ": " << name_of(s, v) << " is uniform (every pixel about (" << std::lround(mean[0]) << ", "
         << std::lround(mean[1]) << ", " << std::lround(mean[2]) << ")): it has no texture to match";
      warnings.push_back(os.str());
    }
  }
  if (!s.rgb.empty() && uniform == static_cast<int>(s.rgb.size()))
    fail(where, ": every image is uniform (", warnings.front().substr(where.size() + 2),
         "); there is nothing to reconstruct from");
  return warnings;
}

}  // namespace tetmvs
