#include "common/synth/scene.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <fstream>
#include <regex>
#include <sstream>


#include "common/error.h"
#include "common/fileio.h"
#include "common/image.h"
#include "common/par_io.h"
#include "common/ply.h"
#include "common/synth/objects.h"
#include "common/trimesh/check.h"
#include "common/trimesh/raster.h"
#include "common/trimesh/rng.h"

namespace tetmvs::synth {

namespace {

Eigen::Matrix3d intrinsics(int w, int h, double f) {
  Eigen::Matrix3d K;
  K << f, 0, (w - 1) / 2.0, 0, f, (h - 1) / 2.0, 0, 0, 1;
  return K;
}
}  // namespace

Camera look_at(const Eigen::Vector3d& C, const Eigen::Vector3d& target, const Eigen::Vector3d& up, int w, int h,
               double focal) {
  require(w > 0 && h > 0 && focal > 0, "look_at: bad image size ", w, "x", h, " or focal ", focal);
  const Eigen::Vector3d z = (target - C).normalized();
  Eigen::Vector3d x = z.cross(up);
  if (x.norm() < 1e-9) x = z.cross(Eigen::Vector3d::UnitX());
  if (x.norm() < 1e-9) x = z.cross(Eigen::Vector3d::UnitY());
  x.normalize();
  const Eigen::Vector3d y = z.cross(x);
  Camera c;
  c.R.row(0) = x.transpose();
  c.R.row(1) = y.transpose();
  c.R.row(2) = z.transpose();
  c.t = -c.R * C;
  c.K = intrinsics(w, h, focal);
  c.width = w;
  c.height = h;
  return c;
}

std::vector<Camera> ring_cameras(int n, double elevation_deg, double radius, const Eigen::Vector3d& target, int w,
                                 int h, double focal) {
  require(n >= 1, "ring cameras: need at least one view, got ", n);
  require(radius > 0, "ring cameras: radius must be > 0, got ", radius);
  std::vector<Camera> cams;
  const double el = elevation_deg * std::numbers::pi / 180;
  for (int i = 0; i < n; ++i) {
    const double az = 2 * std::numbers::pi * i / n;
    const Eigen::Vector3d C =
        target + radius * Eigen::Vector3d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
    cams.push_back(look_at(C, target, Eigen::Vector3d::UnitZ(), w, h, focal));
    cams.back().name = std::to_string(i + 1);
  }
  return cams;
}

namespace {
// Cameras spread evenly (Fibonacci spiral) over the elevations el0..el1 (degrees) above target.
std::vector<Camera> spiral_cameras(const char* what, int n, double radius, const Eigen::Vector3d& target, int w, int h,
                                   double focal, double el0, double el1) {
  require(n >= 1, what, " cameras: need at least one view, got ", n);
  require(radius > 0, what, " cameras: radius must be > 0, got ", radius);
  std::vector<Camera> cams;
  const double s0 = std::sin(el0 * std::numbers::pi / 180), s1 = std::sin(el1 * std::numbers::pi / 180);
  const double golden = std::numbers::pi * (3 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double el = std::asin(s0 + (s1 - s0) * (i + 0.5) / n), az = i * golden;
    const Eigen::Vector3d C =
        target + radius * Eigen::Vector3d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
    cams.push_back(look_at(C, target, Eigen::Vector3d::UnitZ(), w, h, focal));
    cams.back().name = std::to_string(i + 1);
  }
  return cams;
}
}  // namespace

std::vector<Camera> hemisphere_cameras(int n, double radius, const Eigen::Vector3d& target, int w, int h,
                                       double focal) {
  return spiral_cameras("hemisphere", n, radius, target, w, h, focal, 10, 75);
}

std::vector<Camera> cap_cameras(int n, double radius, const Eigen::Vector3d& target, int w, int h, double focal) {
  return spiral_cameras("cap", n, radius, target, w, h, focal, 50, 85);
}

std::vector<Camera> subset_views(const std::vector<Camera>& cams, int n) {
  if (n <= 0 || n >= static_cast<int>(cams.size())) return cams;
  std::vector<Camera> out;
  for (int k = 0; k < n; ++k) out.push_back(cams[static_cast<std::size_t>(k) * cams.size() / n]);
  return out;
}

void resize_cameras(std::vector<Camera>& cams, int w, int h) {
  require(w > 0 && h > 0, "resize cameras: bad size ", w, "x", h);
  for (Camera& c : cams) {
    require(c.width > 0 && c.height > 0, "resize cameras: camera '", c.name, "' has no image size");
    const double sx = static_cast<double>(w) / c.width, sy = static_cast<double>(h) / c.height;
    c.K(0, 0) *= sx;
    c.K(0, 1) *= sx;
    c.K(0, 2) = (c.K(0, 2) + 0.5) * sx - 0.5;
    c.K(1, 1) *= sy;
    c.K(1, 2) = (c.K(1, 2) + 0.5) * sy - 0.5;
    c.width = w;
    c.height = h;
  }
}

bool read_readme_box(const std::filesystem::path& readme, Eigen::AlignedBox3d& box) {
  std::ifstream in(readme);
  if (!in) return false;
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  const std::size_t at = text.find("bounding box");
  if (at == std::string::npos) return false;
  static const std::regex triple(R"(\(\s*([-+0-9.eE]+)\s+([-+0-9.eE]+)\s+([-+0-9.eE]+)\s*\))");
  std::vector<Eigen::Vector3d> v;
  for (auto it = std::sregex_iterator(text.begin() + at, text.end(), triple); it != std::sregex_iterator() && v.size() < 2;
       ++it)
    v.emplace_back(std::stod((*it)[1]), std::stod((*it)[2]), std::stod((*it)[3]));
  if (v.size() < 2) return false;
  require((v[0].array() < v[1].array()).all(), readme.string(), ": bounding box min is not below max");
  box = Eigen::AlignedBox3d(v[0], v[1]);
  return true;
}

Eigen::Vector3d scene_up(const std::vector<Camera>& cams, const Eigen::Vector3d& centre) {
  require(!cams.empty(), "scene_up: no cameras");
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  double dist = 0;
  for (const Camera& c : cams) {
    mean += c.centre();
    dist += (c.centre() - centre).norm();
  }
  mean /= cams.size();
  dist /= cams.size();
  Eigen::Vector3d up = mean - centre;
  if (up.norm() < 0.05 * dist && cams.size() >= 3) {  // cameras all around: normal of their plane
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (const Camera& c : cams) cov += (c.centre() - mean) * (c.centre() - mean).transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
    up = es.eigenvectors().col(0);
    // Image "up" (-y of the cameras) decides the sign.
    Eigen::Vector3d img_up = Eigen::Vector3d::Zero();
    for (const Camera& c : cams) img_up -= c.R.row(1).transpose();
    if (up.dot(img_up) < 0) up = -up;
  }
  if (up.norm() == 0) up = Eigen::Vector3d::UnitZ();
  up.normalize();
  int k;
  up.cwiseAbs().maxCoeff(&k);
  if (std::abs(up[k]) > std::cos(30 * std::numbers::pi / 180)) {
    const double s = up[k] > 0 ? 1 : -1;
    up = Eigen::Vector3d::Zero();
    up[k] = s;
  }
  return up;
}

Placement fit_to_box(const TriMesh& canonical, const Eigen::AlignedBox3d& box, const Eigen::Vector3d& up, double fill) {
  require(fill > 0 && fill <= 1, "fit_to_box: fill must be in (0, 1], got ", fill);
  require(!box.isEmpty() && (box.sizes().array() > 0).all(), "fit_to_box: empty box");
  Placement p;
  p.R = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), up.normalized()).toRotationMatrix();
  Eigen::AlignedBox3d b;
  for (const auto& v : canonical.V) b.extend(p.R * v);
  const Eigen::Vector3d sz = b.sizes();
  double s = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k)
    if (sz[k] > 0) s = std::min(s, fill * box.sizes()[k] / sz[k]);
  p.scale = s;
  p.t = box.center() - s * b.center();
  return p;
}

TriMesh make_placed_object(const std::string& name, const Eigen::AlignedBox3d& box, const Eigen::Vector3d& up,
                           double fill, double edge, Placement* placement) {
  require(edge > 0, "object edge length must be > 0, got ", edge);
  TriMesh m;
  Placement p;
  const bool is_file = name.size() > 4 && name.substr(name.size() - 4) == ".ply";
  if (is_file) {
    m = read_ply(name);
    require(!m.F.empty(), name, ": the object PLY has no faces");
    p = fit_to_box(m, box, up, fill);
    if (!m.fprop("region")) m.set_fprop("region", std::vector<float>(m.F.size(), 0.0f));
  } else {
    const TriMesh coarse = make_object(name, 0.1);
    const Placement pc = fit_to_box(coarse, box, up, fill);
    m = make_object(name, edge / pc.scale);
    p = fit_to_box(m, box, up, fill);
  }
  transform(m, p.R, p.scale, p.t);
  compute_vertex_normals(m);
  if (placement) *placement = p;
  return m;
}

RenderedView render_view(const TriMesh& m, const Camera& cam, const SolidTexture& tex, const ShadingOptions& opt,
                         int view) {
  require(m.N.size() == m.V.size(), "render_view: the mesh needs vertex normals");
  require(opt.noise >= 0, "render_view: noise must be >= 0");
  RasterOptions ro;
  ro.supersample = opt.supersample;
  const Raster r = rasterize(m, cam, ro);
  const int W = cam.width, H = cam.height, s = r.ss;
  const Eigen::Matrix3d M = cam.R.transpose() * cam.K.inverse();
  const Eigen::Vector3d C = cam.centre();
  const Eigen::Vector3d L = opt.light.normalized();
  cv::Mat acc(H, W, CV_32FC3, cv::Scalar(0, 0, 0));
  const float bg = static_cast<float>(opt.background);
  const float inv = 1.0f / (s * s);
  for (int j = 0; j < H * s; ++j) {
    const int* T = r.tri.ptr<int>(j);
    cv::Vec3f* out = acc.ptr<cv::Vec3f>(j / s);
    const double v = r.sample_v(j);
    for (int i = 0; i < W * s; ++i) {
      const int f = T[i];
      cv::Vec3f col(bg, bg, bg);
      if (f >= 0) {
        const Eigen::Vector3d d = M * Eigen::Vector3d(r.sample_u(i), v, 1.0);
        const auto& t = m.F[f];
        const Eigen::Vector3d &a = m.V[t[0]], &b = m.V[t[1]], &c = m.V[t[2]];
        const Eigen::Vector3d n = (b - a).cross(c - a);
        const double den = n.dot(d);
        Eigen::Vector3d X = (a + b + c) / 3.0;
        Eigen::Vector3d nrm = n.normalized();
        if (den != 0) {
          X = C + d * (n.dot(a - C) / den);
          // Barycentrics from sub-triangle areas.
          const double nn = n.squaredNorm();
          const double w1 = n.dot((c - a).cross(X - a).eval()) * -1.0 / nn;  // weight of b
          const double w2 = n.dot((b - a).cross(X - a).eval()) / nn;          // weight of c
          const Eigen::Vector3d ni = (1 - w1 - w2) * m.N[t[0]].cast<double>() + w1 * m.N[t[1]].cast<double>() +
                                     w2 * m.N[t[2]].cast<double>();
          if (ni.norm() > 1e-12) nrm = ni.normalized();
        }
        const double shade = opt.ambient + opt.diffuse * std::max(0.0, nrm.dot(L));
        const Eigen::Vector3f al = tex.albedo(X);
        col = cv::Vec3f(al[0] * shade, al[1] * shade, al[2] * shade);
      }
      out[i / s] += col * inv;
    }
  }
  RenderedView rv;
  rv.rgb.create(H, W, CV_8UC3);
  Rng rng(opt.seed, 0x5EED0000ull + static_cast<std::uint64_t>(view));
  for (int y = 0; y < H; ++y) {
    const cv::Vec3f* a = acc.ptr<cv::Vec3f>(y);
    cv::Vec3b* o = rv.rgb.ptr<cv::Vec3b>(y);
    for (int x = 0; x < W; ++x)
      for (int k = 0; k < 3; ++k) {
        double val = a[x][k];
        if (opt.noise > 0) val += opt.noise * rng.normal();
        o[x][k] = static_cast<std::uint8_t>(std::clamp(std::lround(val * 255.0), 0L, 255L));
      }
  }
  if (s % 2 == 1) {
    rv.mask = r.centre_mask();
  } else {
    const Raster r1 = rasterize(m, cam);
    rv.mask = r1.centre_mask();
  }
  return rv;
}

std::vector<Camera> write_dataset(const std::filesystem::path& dir, const TriMesh& gt, std::vector<Camera> cams,
                                  const SolidTexture& tex, const ShadingOptions& shading, const DatasetInfo& info) {
  namespace fs = std::filesystem;
  require(!cams.empty(), "write_dataset: no cameras");
  require(!info.prefix.empty() && info.prefix.find('/') == std::string::npos, "write_dataset: bad prefix '",
          info.prefix, "'");
  const int n = static_cast<int>(cams.size());
  for (int i = 0; i < n; ++i) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%04d.png", i + 1);
    cams[i].name = info.prefix + buf;
  }
  std::vector<std::string> errors(n);
#pragma omp parallel for schedule(dynamic, 1)
  for (int i = 0; i < n; ++i) {
    try {
      const RenderedView rv = render_view(gt, cams[i], tex, shading, i);
      write_png_rgb(dir / cams[i].name, rv.rgb);
      write_text_atomic(dir / "silhouettes" / cams[i].name, encode_png(rv.mask));
    } catch (const std::exception& e) {
      errors[i] = e.what();
    }
  }
  for (const auto& e : errors)
    if (!e.empty()) throw Error(e);
  write_par(dir / (info.prefix + "_par.txt"), cams);
  std::ostringstream bb;
  bb.precision(17);
  const Eigen::Vector3d lo = info.box.min(), hi = info.box.max();
  bb << lo.x() << " " << lo.y() << " " << lo.z() << "\n" << hi.x() << " " << hi.y() << " " << hi.z() << "\n";
  write_text_atomic(dir / "bbox.txt", bb.str());
  PlyWriteOptions po;
  po.comment = "tetmvs synth ground truth";
  write_ply(dir / "gt.ply", gt, po);
  write_text_atomic(dir / "synth.json", info.meta.dump(2) + "\n");
  return cams;
}

}  // namespace tetmvs::synth

namespace tetmvs::synth {

namespace {
bool read_bbox_txt(const std::filesystem::path& f, Eigen::AlignedBox3d& box) {
  std::ifstream in(f);
  if (!in) return false;
  double v[6];
  for (double& x : v)
    if (!(in >> x)) fail(f.string(), ": expected two lines of three numbers (min x y z / max x y z)");
  require(v[0] < v[3] && v[1] < v[4] && v[2] < v[5], f.string(), ": box min is not below max");
  box = Eigen::AlignedBox3d(Eigen::Vector3d(v[0], v[1], v[2]), Eigen::Vector3d(v[3], v[4], v[5]));
  return true;
}
}  // namespace

void SynthConfig::check() const { check_param_ranges(*this); }

nlohmann::json synthesize(const SynthConfig& c, const std::filesystem::path& out) {
  namespace fs = std::filesystem;
  c.check();
  require(c.views >= 0, "--views must be >= 0, got ", c.views);
  require((c.width == 0) == (c.height == 0) && c.width >= 0 && c.height >= 0, "bad --size ", c.width, "x", c.height);
  std::vector<Camera> cams;
  Eigen::AlignedBox3d box;
  bool have_box = false;
  if (c.box) {
    box = *c.box;
    have_box = true;
  }
  if (c.cameras == "ring" || c.cameras == "hemisphere" || c.cameras == "cap") {
    if (!have_box) box = Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-c.box_size / 2), Eigen::Vector3d::Constant(c.box_size / 2));
    const int w = c.width ? c.width : 640, h = c.height ? c.height : 480;
    const int n = c.views ? c.views : 48;
    const double R = 0.5 * box.sizes().norm();
    require(c.camera_radius > 1.5 * R, "synth.camera_radius ", c.camera_radius, " is too close to the box (radius ", R, ")");
    const double f = c.focal > 0 ? c.focal : 0.5 * std::min(w, h) / std::tan(std::asin(R / c.camera_radius));
    cams = c.cameras == "ring"         ? ring_cameras(n, c.ring_elevation, c.camera_radius, box.center(), w, h, f)
           : c.cameras == "hemisphere" ? hemisphere_cameras(n, c.camera_radius, box.center(), w, h, f)
                                       : cap_cameras(n, c.camera_radius, box.center(), w, h, f);
  } else {
    const fs::path par = c.cameras;
    require(fs::exists(par), "camera file ", par.string(), " does not exist (give a par file, ring, hemisphere or cap)");
    cams = read_par(par);
    for (Camera& cam : cams) {
      cam.width = 640;
      cam.height = 480;
    }
    // The real images tell the size when they are there.
    const fs::path first = par.parent_path() / cams[0].name;
    if (fs::exists(first)) {
      const cv::Mat im = load_rgb(first);
      for (Camera& cam : cams) {
        cam.width = im.cols;
        cam.height = im.rows;
      }
    }
    if (c.width) resize_cameras(cams, c.width, c.height);
    cams = subset_views(cams, c.views);
    if (!have_box) have_box = read_bbox_txt(par.parent_path() / "bbox.txt", box);
    if (!have_box) have_box = read_readme_box(par.parent_path() / "README.txt", box);
    require(have_box, par.string(), ": no box (no README.txt or bbox.txt beside it): give --box");
  }
  const Eigen::Vector3d centre = box.center();
  for (const Camera& cam : cams)
    require(cam.depth(centre) > 0, "camera ", cam.name, " does not face the box centre");
  const Eigen::Vector3d up = scene_up(cams, centre);
  const double px = pixel_footprint(cams, centre);
  Placement pl;
  const TriMesh gt = make_placed_object(c.object, box, up, c.fill, c.edge_px * px, &pl);
  TextureOptions to;
  to.strength = c.texture;
  to.min_scale = c.texture_min_px * px;
  to.max_scale = c.texture_max_px * px;
  to.seed = c.seed;
  const SolidTexture tex(to);
  ShadingOptions sh;
  // Light from above, tilted toward the first camera.
  Eigen::Vector3d toward = cams[0].centre() - centre;
  toward -= toward.dot(up) * up;
  if (toward.norm() > 0) toward.normalize();
  sh.light = (up + toward).normalized();
  sh.ambient = c.ambient;
  sh.diffuse = c.diffuse;
  sh.background = c.background;
  sh.noise = c.noise;
  sh.supersample = c.supersample;
  sh.seed = c.seed;
  DatasetInfo info;
  info.prefix = c.prefix.empty() ? fs::path(c.object).stem().string() : c.prefix;
  info.box = box;
  const MeshCheck chk = check_mesh(gt);
  std::vector<int> genus;
  for (const auto& k : chk.components) genus.push_back(k.genus);
  info.meta = {{"schema", "tetmvs.synth"},
               {"schema_version", 1},
               {"object", c.object},
               {"cameras", c.cameras},
               {"views", cams.size()},
               {"image_size", {cams[0].width, cams[0].height}},
               {"box", {{box.min().x(), box.min().y(), box.min().z()}, {box.max().x(), box.max().y(), box.max().z()}}},
               {"up", {up.x(), up.y(), up.z()}},
               {"light", {sh.light.x(), sh.light.y(), sh.light.z()}},
               {"pixel_footprint", px},
               {"placement", {{"scale", pl.scale}, {"translation", {pl.t.x(), pl.t.y(), pl.t.z()}}}},
               {"gt", {{"vertices", gt.V.size()}, {"faces", gt.F.size()}, {"components", chk.components.size()},
                       {"closed", chk.closed}, {"genus", genus}, {"area", total_area(gt)}}},
               {"texture", c.texture},
               {"texture_scales", {to.min_scale, to.max_scale}},
               {"noise", c.noise},
               {"seed", c.seed},
               {"supersample", c.supersample},
               {"edge_length", c.edge_px * px},
               {"ambient", c.ambient},
               {"diffuse", c.diffuse},
               {"background", c.background}};
  write_dataset(out, gt, cams, tex, sh, info);
  return info.meta;
}

}  // namespace tetmvs::synth
