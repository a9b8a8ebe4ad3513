#include "common/ingest/dataset.h"

#include <omp.h>

#include <Eigen/Dense>
#include <fstream>
#include <opencv2/imgproc.hpp>
#include <regex>
#include <set>
#include <sstream>

#include "common/budget.h"
#include "common/error.h"
#include "common/fileio.h"
#include "common/image.h"
#include "common/ingest/colmap.h"
#include "common/log.h"
#include "common/par_io.h"
#include "common/silhouette/border.h"

namespace tetmvs {
namespace fs = std::filesystem;

void SilhouetteOptions::check() const { check_param_ranges(*this); }

SilhouetteOptions SilhouetteOptions::from(const Params& p) {
  SilhouetteOptions o;
  read_params(p, o);
  o.check();
  return o;
}

namespace {
cv::Mat disk(int r) { return cv::getStructuringElement(cv::MORPH_ELLIPSE, {2 * r + 1, 2 * r + 1}); }

// Removes 8-connected foreground blobs smaller than min_area (fraction of the image).
void remove_small_blobs(cv::Mat& m, double min_area) {
  cv::Mat labels, stats, cents;
  cv::connectedComponentsWithStats(m, labels, stats, cents, 8, CV_32S);
  const double min_px = min_area * m.rows * m.cols;
  for (int y = 0; y < m.rows; ++y) {
    auto* d = m.ptr<std::uint8_t>(y);
    const auto* l = labels.ptr<int>(y);
    for (int x = 0; x < m.cols; ++x)
      if (d[x] && stats.at<int>(l[x], cv::CC_STAT_AREA) < min_px) d[x] = 0;
  }
}
}  // namespace

cv::Mat silhouette_from_dark_background(const cv::Mat& rgb, const SilhouetteOptions& o) {
  o.check();
  require(rgb.type() == CV_8UC3, "silhouette: expected an 8-bit RGB image");
  cv::Mat m(rgb.rows, rgb.cols, CV_8U);
  const int thr = static_cast<int>(std::floor(o.threshold * 255.0));
  for (int y = 0; y < rgb.rows; ++y) {
    const auto* s = rgb.ptr<cv::Vec3b>(y);
    auto* d = m.ptr<std::uint8_t>(y);
    for (int x = 0; x < rgb.cols; ++x) d[x] = std::max({s[x][0], s[x][1], s[x][2]}) > thr ? 255 : 0;
  }
  // Pad so that morphology near the border behaves as if the object continued.
  const int pad = std::max(o.dilate, o.erode) + 1;
  cv::Mat big;
  cv::copyMakeBorder(m, big, pad, pad, pad, pad, cv::BORDER_REPLICATE);
  if (o.dilate > 0) cv::dilate(big, big, disk(o.dilate));
  if (o.erode > 0) cv::erode(big, big, disk(o.erode));
  m = big(cv::Rect(pad, pad, rgb.cols, rgb.rows)).clone();
  remove_small_blobs(m, o.min_area);
  if (o.fill_holes) {
    // background components that do not touch the border are holes
    cv::Mat bg = m == 0;
    cv::Mat bl;
    const int nb = cv::connectedComponents(bg, bl, 4, CV_32S);
    std::vector<char> border(nb, 0);
    for (int x = 0; x < m.cols; ++x) border[bl.at<int>(0, x)] = border[bl.at<int>(m.rows - 1, x)] = 1;
    for (int y = 0; y < m.rows; ++y) border[bl.at<int>(y, 0)] = border[bl.at<int>(y, m.cols - 1)] = 1;
    for (int y = 0; y < m.rows; ++y) {
      auto* d = m.ptr<std::uint8_t>(y);
      const auto* l = bl.ptr<int>(y);
      for (int x = 0; x < m.cols; ++x)
        if (!d[x] && !border[l[x]]) d[x] = 255;
    }
  }
  return m;
}

std::optional<Eigen::AlignedBox3d> read_stated_box(const fs::path& dir, std::string* source) {
  const auto parse3 = [](const std::string& s, Eigen::Vector3d& v) {
    std::istringstream is(s);
    return static_cast<bool>(is >> v.x() >> v.y() >> v.z()) && v.allFinite();
  };
  const auto check = [](const fs::path& f, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    if (!(lo.array() < hi.array()).all())
      fail(f.string(), ": box minimum must be below its maximum on every axis");
    return Eigen::AlignedBox3d(lo, hi);
  };
  const fs::path bb = dir / "bbox.txt";
  if (fs::exists(bb)) {
    std::istringstream is(read_file(bb));
    std::string l1, l2;
    std::getline(is, l1);
    std::getline(is, l2);
    Eigen::Vector3d lo, hi;
    if (!parse3(l1, lo) || !parse3(l2, hi))
      fail(bb.string(), ": expected two lines of three numbers (min x y z, max x y z)");
    if (source) *source = "bbox.txt";
    return check(bb, lo, hi);
  }
  const fs::path rd = dir / "README.txt";
  if (fs::exists(rd)) {
    const std::string text = read_file(rd);
    const std::string num = R"(\s*([-+0-9.eE]+))";
    const std::regex re("bounding box[^\\n]*?is\\s*\\(" + num + num + num + R"(\s*\)\s*\()" + num +
                        num + num + R"(\s*\))");
    std::smatch m;
    if (std::regex_search(text, m, re)) {
      Eigen::Vector3d lo, hi;
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::stod(m[1 + k]);
        hi[k] = std::stod(m[4 + k]);
      }
      if (source) *source = "README.txt";
      return check(rd, lo, hi);
    }
  }
  return std::nullopt;
}

Eigen::AlignedBox3d camera_search_region(const std::vector<Camera>& cams) {
  // point closest to all optical axes: sum (I - a a^T) (x - c) = 0
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (const auto& c : cams) {
    const Eigen::Vector3d a = c.axis();
    const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - a * a.transpose();
    A += P;
    b += P * c.centre();
  }
  const Eigen::Vector3d x = A.ldlt().solve(b);
  double half = 0;
  for (const auto& c : cams)
    half = std::max(half, std::max(c.depth(x), 0.0) * 0.5 * std::max(c.width, c.height) / c.focal());
  require(half > 0 && x.allFinite(), "cameras do not look at a common region; give a bbox.txt");
  return Eigen::AlignedBox3d(x.array() - half, x.array() + half);
}

Eigen::AlignedBox3d padded_hull_box(const Scene& s, const Eigen::AlignedBox3d& region, const Params& p,
                                    const std::string& where, const std::string& hint) {
  const int res = p.i("ingest.hull_resolution");
  Eigen::AlignedBox3d hull = visual_hull_box(s, region, res);
  if (hull.isEmpty())
    fail(where, ": the visual hull of the silhouettes is empty (silhouettes inconsistent with the cameras?); ", hint);
  // refine once inside the first hull box for a tighter estimate
  const Eigen::Vector3d grow = hull.sizes() * 0.1;
  hull = visual_hull_box(s, Eigen::AlignedBox3d(hull.min() - grow, hull.max() + grow), res);
  const double pad = p.d("ingest.box_padding") * hull.diagonal().norm();
  return Eigen::AlignedBox3d(hull.min().array() - pad, hull.max().array() + pad);
}

Eigen::AlignedBox3d visual_hull_box(const Scene& s, const Eigen::AlignedBox3d& region, int res,
                                    long* voxels) {
  const Eigen::Vector3d size = region.sizes();
  const double h = size.maxCoeff() / res;
  const int nx = std::max(1, int(std::ceil(size.x() / h))), ny = std::max(1, int(std::ceil(size.y() / h))),
            nz = std::max(1, int(std::ceil(size.z() / h)));
  std::vector<std::uint8_t> keep(std::size_t(nx) * ny * nz, 0);
#pragma omp parallel for schedule(static)
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const Eigen::Vector3d X = region.min() + h * Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5);
        bool in = true;
        for (int v = 0; v < s.size() && in; ++v) {
          if (!s.has_silhouette(v) || s.cams[v].depth(X) <= 0) continue;
          const Eigen::Vector2d p = s.cams[v].project(X);
          in = s.in_silhouette(v, p.x(), p.y(), /*outside_value=*/true);
        }
        keep[(std::size_t(k) * ny + j) * nx + i] = in;
      }
  Eigen::AlignedBox3d box;  // empty
  long n = 0;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        if (keep[(std::size_t(k) * ny + j) * nx + i]) {
          ++n;
          const Eigen::Vector3d lo = region.min() + h * Eigen::Vector3d(i, j, k);
          box.extend(lo);
          box.extend(lo + Eigen::Vector3d::Constant(h));
        }
  if (voxels) *voxels = n;
  return box;
}

namespace {

std::set<std::string> read_good_list(const fs::path& dir, const std::vector<Camera>& cams,
                                     bool* present) {
  std::set<std::string> good;
  *present = false;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string n = e.path().filename().string();
    const std::string suffix = "_good_silhouette_images.txt";
    if (n.size() > suffix.size() && n.compare(n.size() - suffix.size(), suffix.size(), suffix) == 0) {
      *present = true;
      std::istringstream is(read_file(e.path()));
      std::string w;
      std::set<std::string> known;
      for (const auto& c : cams) known.insert(c.name);
      int line = 0;
      while (is >> w) {
        ++line;
        if (!known.count(w))
          fail(e.path().string(), ": lists '", w, "', which the par file does not name");
        good.insert(w);
      }
    }
  }
  return good;
}

// A silhouette that is empty or covers the whole image carries no information (and an
// empty one would carve everything): the view keeps no silhouette, with a warning.
void drop_degenerate_silhouettes(Scene& s) {
  const int n = s.size();
  for (int v = 0; v < n; ++v) {
    if (s.sil[v].empty()) continue;
    const double frac = cv::countNonZero(s.sil[v]) / double(s.sil[v].total());
    if (frac == 0.0) {
      warn(s.cams[v].name, ": silhouette is empty; the view will carry no silhouette");
      s.sil[v] = cv::Mat();
    } else if (frac == 1.0) {
      warn(s.cams[v].name, ": silhouette covers the whole image; the view will carry no silhouette");
      s.sil[v] = cv::Mat();
    }
  }
}

}  // namespace

void check_images_budget(const Params& p, const std::vector<fs::path>& images) {
  double pixels = 0, largest = -1;
  fs::path big;
  ImageSize big_size;
  for (const auto& f : images) {
    const auto s = fs::exists(f) ? read_image_size(f) : std::nullopt;
    if (!s) continue;
    const double px = static_cast<double>(s->width) * static_cast<double>(s->height);
    pixels += px;
    if (px > largest) largest = px, big = f, big_size = *s;
  }
  if (largest < 0) return;
  std::ostringstream what;
  what << "ingest: " << images.size() << " images, the largest " << big.string() << " (" << big_size.width << " x "
       << big_size.height << " pixels by its header)";
  check_memory_budget(p, 9.0 * pixels, what.str(), "use smaller images or fewer views");
}

std::optional<fs::path> find_mask(const fs::path& sildir, const std::string& image_name) {
  const fs::path own = sildir / image_name;
  for (const fs::path& f : {own, fs::path(own).replace_extension(".png"), fs::path(own.string() + ".png")})
    if (fs::is_regular_file(f)) return f;
  return std::nullopt;
}

void warn_missing_masks(const fs::path& sildir, const std::vector<std::string>& missing, int views) {
  if (missing.empty()) return;
  std::string names;
  for (std::size_t i = 0; i < missing.size() && i < 5; ++i) names += (i ? ", " : "") + missing[i];
  if (missing.size() > 5) names += ", ...";
  warn(sildir.string(), ": no mask for ", missing.size(), " of ", views, " views (", names,
       "; looked for the image's name, its stem with .png and its name with .png): they carry no silhouette");
}

Scene read_dataset(const fs::path& dir, const Params& p) {
  Scene s;
  const fs::path par = find_par_file(dir);
  s.cams = read_par(par);
  s.dataset = fs::absolute(dir).lexically_normal().filename().string();
  if (s.dataset.empty()) s.dataset = fs::absolute(dir).parent_path().filename().string();
  const int n = s.size();
  s.rgb.resize(n);
  s.sil.resize(n);
  {
    std::vector<fs::path> files;
    for (const auto& c : s.cams) files.push_back(dir / c.name);
    check_images_budget(p, files);
  }
  // images: loaded in parallel, errors collected and the first (in view order) reported
  std::vector<std::string> errors(n);
#pragma omp parallel for schedule(dynamic)
  for (int v = 0; v < n; ++v) {
    try {
      s.rgb[v] = load_rgb(dir / s.cams[v].name);
    } catch (const Error& e) {
      errors[v] = e.what();
    } catch (const std::exception& e) {  // nothing may leave the parallel region
      errors[v] = (dir / s.cams[v].name).string() + ": " + e.what();
    }
  }
  for (const auto& e : errors)
    if (!e.empty()) throw Error(e);
  for (int v = 0; v < n; ++v) {
    s.cams[v].width = s.rgb[v].cols;
    s.cams[v].height = s.rgb[v].rows;
    if (s.rgb[v].size() != s.rgb[0].size())
      fail((dir / s.cams[v].name).string(), ": image is ", s.rgb[v].cols, "x", s.rgb[v].rows,
           " but ", s.cams[0].name, " is ", s.rgb[0].cols, "x", s.rgb[0].rows,
           "; all images of a dataset must share one size");
  }
  // silhouettes
  bool has_list = false;
  const auto good = read_good_list(dir, s.cams, &has_list);
  const fs::path sildir = dir / "silhouettes";
  const auto opts = SilhouetteOptions::from(p);
  const bool given = fs::is_directory(sildir);
  std::vector<char> no_mask(n, 0);
#pragma omp parallel for schedule(dynamic)
  for (int v = 0; v < n; ++v) {
    if (has_list && !good.count(s.cams[v].name)) continue;
    try {
      if (given) {
        const auto found = find_mask(sildir, s.cams[v].name);
        if (!found) {  // a view without a mask carries no silhouette
          no_mask[v] = 1;
          continue;
        }
        const fs::path& mf = *found;
        cv::Mat m = load_mask(mf);
        if (m.size() != s.rgb[v].size())
          fail(mf.string(), ": mask is ", m.cols, "x", m.rows, " but its image is ", s.rgb[v].cols,
               "x", s.rgb[v].rows);
        s.sil[v] = m;
      } else if (p.b("ingest.auto_silhouettes")) {
        s.sil[v] = silhouette_from_dark_background(s.rgb[v], opts);
      }
    } catch (const Error& e) {
      errors[v] = e.what();
    } catch (const std::exception& e) {
      errors[v] = (sildir / s.cams[v].name).string() + ": " + e.what();
    }
  }
  for (const auto& e : errors)
    if (!e.empty()) throw Error(e);
  {
    std::vector<std::string> missing;
    for (int v = 0; v < n; ++v)
      if (no_mask[v]) missing.push_back(s.cams[v].name);
    warn_missing_masks(sildir, missing, n);
  }
  drop_degenerate_silhouettes(s);
  // bounding box
  std::string src;
  if (auto given_box = colmap::box_param(p, "ingest.box")) {  // the ingest.box parameter wins
    s.box = *given_box;
    s.box_source = "given";
  } else if (auto box = read_stated_box(dir, &src)) {
    s.box = *box;
    s.box_source = src;
  } else {
    if (s.num_silhouettes() == 0)
      fail(dir.string(), ": no bounding box stated (bbox.txt or README.txt) and no silhouettes to "
                         "compute one from; add a bbox.txt with two lines: min x y z, max x y z (or set ingest.box)");
    s.box = padded_hull_box(s, camera_search_region(s.cams), p, dir.string(), "add a bbox.txt");
    s.box_source = "visual hull";
  }
  vet_scene(s, par);  // (before the box is projected below)
  // Automatic silhouettes: nothing outside the projected bounding box can be the object
  // (background clutter such as the temple's cloth is removed this way).
  if (!given && s.box_source != "visual hull") {
    for (int v = 0; v < n; ++v) {
      if (s.sil[v].empty()) continue;
      std::vector<cv::Point> corners;
      bool front = true;
      for (int c = 0; c < 8; ++c) {
        const Eigen::Vector3d X = s.box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c));
        front = front && s.cams[v].depth(X) > 0;
        const Eigen::Vector2d q = s.cams[v].project(X);
        corners.emplace_back(int(std::lround(q.x())), int(std::lround(q.y())));
      }
      if (!front) continue;
      std::vector<cv::Point> hull;
      cv::convexHull(corners, hull);
      cv::Mat inside = cv::Mat::zeros(s.sil[v].size(), CV_8U);
      cv::fillConvexPoly(inside, hull, cv::Scalar(255));
      cv::dilate(inside, inside, disk(std::max(2, opts.dilate)));
      s.sil[v] &= inside;
      remove_small_blobs(s.sil[v], opts.min_area);
    }
  }
  drop_degenerate_silhouettes(s);
  return s;
}

void vet_scene(const Scene& s, const fs::path& where) {
  for (const auto& w : check_scene_geometry(s, where.string())) warn(w);
}

cv::Mat contact_sheet(const Scene& s, int thumb_width) {
  const int n = s.size();
  const int cols = std::min(8, n), rows = (n + cols - 1) / cols;
  const double scale = double(thumb_width) / s.rgb[0].cols;
  const int tw = thumb_width, th = int(std::round(s.rgb[0].rows * scale));
  cv::Mat sheet(rows * (th + 16), cols * tw, CV_8UC3, cv::Scalar(40, 40, 40));
  for (int v = 0; v < n; ++v) {
    cv::Mat img = s.rgb[v].clone();
    if (s.has_silhouette(v)) {  // its outline (not the image border: common/silhouette/border.h)
      cv::Mat line = silhouette::outline(s.sil[v]);
      const int r = std::max(1, int(0.75 / scale));
      cv::dilate(line, line, cv::getStructuringElement(cv::MORPH_RECT, {2 * r + 1, 2 * r + 1}));
      img.setTo(cv::Scalar(0, 255, 0), line);
    }
    cv::Mat small;
    cv::resize(img, small, {tw, th}, 0, 0, cv::INTER_AREA);
    const int r = v / cols, c = v % cols;
    small.copyTo(sheet(cv::Rect(c * tw, r * (th + 16), tw, th)));
    const std::string label = s.cams[v].name + (s.has_silhouette(v) ? "" : " (no sil.)");
    cv::putText(sheet, label, {c * tw + 3, r * (th + 16) + th + 12}, cv::FONT_HERSHEY_SIMPLEX, 0.35,
                s.has_silhouette(v) ? cv::Scalar(220, 220, 220) : cv::Scalar(255, 120, 120), 1, cv::LINE_AA);
  }
  return sheet;
}

}  // namespace tetmvs
