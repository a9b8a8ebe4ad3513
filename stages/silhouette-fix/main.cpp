// silhouette-fix: the first surface S1 is rendered into every view with a silhouette; its
// disagreements with the true silhouettes become new hard labels for the second cut
// (paper section 3.2, Fig. 5). Writes silfix.h5 with the layout of labels.h5 plus the
// constraints it added (schemas/silfix.md), pictures of every view, and a summary.
// `--agreement PLY` (repeatable) instead only reports the silhouette agreement of surfaces.
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "common/budget.h"
#include "common/cut/inputs.h"
#include "common/cut/surface.h"
#include "common/error.h"
#include "common/fileio.h"
#include "common/h5io.h"
#include "common/image.h"
#include "common/ply.h"
#include "common/render/shaded.h"
#include "common/scene.h"
#include "common/silfix/silfix.h"
#include "common/stage.h"
#include "common/tetmesh/mesh_io.h"

namespace fs = std::filesystem;

// Memory estimate, bytes beyond the program (64 MB) and the mesh arrays: per face the two
// scores, per cell the labels, reasons and constraints, per pixel the silhouette and the
// renders (torus and cup: 1.2-1.4 times the measured peak).
constexpr double kBytesPerFace = 8, kBytesPerCell = 8, kBytesPerPixel = 4;
using namespace tetmvs;

namespace {

template <typename T, typename F>
std::vector<T> column(const std::vector<silfix::Constraint>& cs, F get) {
  std::vector<T> out;
  out.reserve(cs.size());
  for (const auto& c : cs) out.push_back(static_cast<T>(get(c)));
  return out;
}
template <typename T, typename F>
std::vector<T> view_column(const std::vector<silfix::ViewStats>& vs, F get) {
  std::vector<T> out;
  out.reserve(vs.size());
  for (const auto& v : vs) out.push_back(static_cast<T>(get(v)));
  return out;
}

// The --agreement mode: one line (and one JSON entry) per surface.
void report_agreement(const Scene& scene, const std::vector<std::string>& plys, const std::string& json_out,
                      std::string& summary) {
  nlohmann::json j = nlohmann::json::object();
  std::ostringstream os;
  for (const auto& p : plys) {
    const TriMesh m = read_ply(p);
    const SilhouetteAgreement a = silhouette_agreement(m, scene);
    std::ostringstream line;
    line << std::fixed << std::setprecision(4) << fs::path(p).filename().string() << ": mean IoU " << a.mean_iou
         << ", boundary error mean " << std::setprecision(2) << a.mean_boundary_px << " px, 95th percentile "
         << a.p95_boundary_px << " px (" << a.views.size() << " views)";
    info(line.str());
    os << (os.tellp() > 0 ? "; " : "") << line.str();
    j[fs::path(p).filename().string()] = {{"file", p},
                                           {"views", a.views},
                                           {"iou", a.iou},
                                           {"mean_iou", a.mean_iou},
                                           {"mean_boundary_px", a.mean_boundary_px},
                                           {"p95_boundary_px", a.p95_boundary_px}};
  }
  if (!json_out.empty()) write_text_atomic(json_out, j.dump(2) + "\n");
  summary = os.str();
}

}  // namespace

int main(int argc, char** argv) {
  StageCli cli("silhouette-fix",
               "Renders the first cut's surface into every view with a silhouette; pixels where it "
               "is too big make the cells on their rays exterior, pixels where it is too small give "
               "a few sure interior cells (centre of the front/back photo-consistency peaks). Writes "
               "the updated labels for the second cut, the constraints, and pictures.");
  std::string scene_file, mesh_file, scores_file, labels_file, cut_file, surface_file, out, png_dir, agree_json;
  std::vector<std::string> agreement;
  cli.add_input("--scene", scene_file, "scene.h5 (cameras and silhouettes)")->required();
  cli.add_input("--mesh", mesh_file, "final tetrahedral mesh (mesh_<L>.h5)");
  cli.add_input("--scores", scores_file, "face scores (scores.h5, /faces/omega)");
  cli.add_input("--labels", labels_file, "hard labels of the first cut (labels.h5)");
  cli.add_input("--cut", cut_file, "the first cut (cut1.h5, /cells/inside): S1 is rebuilt from it");
  cli.add_input("--surface", surface_file, "S1 as a PLY (cut1.ply) instead of rebuilding it from --cut");
  cli.add_output("--out", out, "updated labels plus constraints (silfix.h5, schemas/silfix.md)");
  cli.add_output("--png-dir", png_dir, "folder for pictures: view_<NNN>.png per view and sheet.png", PathKind::Folder);
  auto* agree_opt = cli.add_input(
      "--agreement", agreement,
      "only report the silhouette agreement of this surface (PLY; repeatable), e.g. cut1.ply cut2.ply");
  cli.add_output("--agreement-json", agree_json, "with --agreement: also write the numbers as JSON")->needs(agree_opt);
  return cli.run(argc, argv, [&](StageContext& ctx) {
    if (agreement.empty()) {
      require(!mesh_file.empty() && !scores_file.empty() && !labels_file.empty() && !out.empty(),
              "silhouette-fix needs --mesh, --scores, --labels and --out (or --agreement)");
      require(cut_file.empty() != surface_file.empty(), "silhouette-fix needs exactly one of --cut and --surface");
    }
    const Scene scene = read_scene(scene_file, false);
    // Without any silhouette there is nothing to fix: the labels pass through unchanged
    // (no constraints, attribute `note`), so that the second cut still has its input.
    const bool pass_through = scene.num_silhouettes() == 0;
    if (!agreement.empty()) {
      require(!pass_through, scene_file, ": the scene has no silhouettes; --agreement needs them");
      report_agreement(scene, agreement, agree_json, ctx.summary);
      return;
    }
    const char* kNote = "no view has a silhouette: silhouette-fix skipped, labels passed through unchanged";

    {
      const MeshCounts mc = mesh_counts(mesh_file);
      const double pixels = static_cast<double>(scene.size()) * scene.cams[0].width * scene.cams[0].height;
      const double bytes = 64.0 * 1048576.0 + mc.read_bytes() + kBytesPerFace * static_cast<double>(mc.faces) +
                           kBytesPerCell * static_cast<double>(mc.cells) + kBytesPerPixel * pixels;
      std::ostringstream what;
      what << "silhouette-fix: " << mesh_file << " (" << mc.cells << " cells, " << scene.size() << " views)";
      check_memory_budget(ctx.params, bytes, what.str(), "use a coarser final mesh (fewer LEVELS)");
    }
    const tet::TetMesh mesh = tet::read_mesh(mesh_file);
    const std::int64_t F = mesh.num_faces(), C = mesh.num_cells();
    const std::vector<float> omega = cut::read_omega(scores_file, F);
    const std::vector<std::int8_t> labels = cut::read_labels(labels_file, C);
    auto lf = h5::File::open(labels_file, "tetmvs.labels");  // its other datasets
    const auto reasons = lf.read<std::uint8_t>("/cells/reason", {C});
    const auto votes = lf.read<std::int32_t>("/cells/votes", {C});

    TriMesh s1;
    std::vector<fs::path> inputs = {scene_file, mesh_file, scores_file, labels_file};
    if (!cut_file.empty()) {
      auto cf = h5::File::open(cut_file, "tetmvs.cut");
      const auto inside = cf.read<std::uint8_t>("/cells/inside", {C});
      s1 = cut::cut_surface(mesh, inside.data);
      inputs.push_back(cut_file);
    } else {
      s1 = read_ply(surface_file);
      inputs.push_back(surface_file);
    }
    require(pass_through || s1.nf() > 0, "silhouette-fix: the first surface is empty");

    const silfix::Options o = silfix::Options::from_params(ctx.params);
    info("silhouette-fix: ", C, " cells, S1 ", s1.nf(), " triangles, ", scene.num_silhouettes(), " silhouettes");
    silfix::Result r;
    SilhouetteAgreement agree;
    if (pass_through) {
      info("silhouette-fix: ", kNote);
      r.label = labels;
      r.reason = reasons.data;
      r.s1_masks.resize(scene.size());
    } else {
      r = silfix::fix_silhouettes(mesh, scene, s1, omega, labels, reasons.data, o);
      agree = silhouette_agreement(s1, scene);
    }

    std::int64_t interior = 0, exterior = 0;
    for (auto l : r.label) interior += l > 0, exterior += l < 0;
    auto f = h5::File::create(out);
    f.write_header("tetmvs.labels", 1, "silhouette-fix", ctx.params.values_for("silhouette-fix"), inputs);
    f.write("/cells/label", r.label);
    f.write("/cells/reason", r.reason);
    f.write("/cells/votes", votes.data);
    for (const char* d : {"/cells/inside_evidence", "/cells/outside_evidence"})  // for the cut's visibility term
      if (lf.has(d)) f.write(d, lf.read<float>(d, {C}).data);
    for (const char* a : {"low_votes", "high_votes"})
      if (lf.has_attr("/", a)) f.set_attr("/", a, lf.attr_double("/", a));
    for (const char* a : {"rays", "boundary", "hull_exterior", "voted_out"})
      if (lf.has_attr("/", a)) f.set_attr("/", a, lf.attr_int("/", a));
    f.set_attr("/", "interior", interior);
    f.set_attr("/", "exterior", exterior);
    f.set_attr("/", "silfix_exterior", r.exterior_added);
    f.set_attr("/", "silfix_interior", r.interior_added);
    f.set_attr("/", "silfix_conflicts", r.conflicts);
    f.set_attr("/", "silfix_already", r.already);
    f.set_attr("/", "s1_mean_iou", agree.mean_iou);
    f.set_attr("/", "s1_mean_boundary_px", agree.mean_boundary_px);
    f.set_attr("/", "s1_p95_boundary_px", agree.p95_boundary_px);
    if (pass_through) f.set_attr("/", "note", std::string(kNote));
    const auto& cs = r.constraints;
    f.write("/constraints/view", column<std::int32_t>(cs, [](auto& c) { return c.view; }));
    f.write("/constraints/u", column<std::int32_t>(cs, [](auto& c) { return c.u; }));
    f.write("/constraints/v", column<std::int32_t>(cs, [](auto& c) { return c.v; }));
    f.write("/constraints/cell", column<std::int32_t>(cs, [](auto& c) { return c.cell; }));
    f.write("/constraints/kind", column<std::int8_t>(cs, [](auto& c) { return c.kind; }));
    f.write("/constraints/why", column<std::uint8_t>(cs, [](auto& c) { return c.why; }));
    f.write("/constraints/omega_front", column<float>(cs, [](auto& c) { return c.omega_front; }));
    f.write("/constraints/omega_back", column<float>(cs, [](auto& c) { return c.omega_back; }));
    f.write("/constraints/depth_front", column<float>(cs, [](auto& c) { return c.depth_front; }));
    f.write("/constraints/depth_back", column<float>(cs, [](auto& c) { return c.depth_back; }));
    const auto& vs = r.views;
    f.write("/views/view", view_column<std::int32_t>(vs, [](auto& v) { return v.view; }));
    f.write("/views/iou", view_column<double>(vs, [](auto& v) { return v.iou; }));
    f.write("/views/s1_px", view_column<std::int64_t>(vs, [](auto& v) { return v.s1_px; }));
    f.write("/views/true_px", view_column<std::int64_t>(vs, [](auto& v) { return v.true_px; }));
    f.write("/views/too_big_px", view_column<std::int64_t>(vs, [](auto& v) { return v.too_big_px; }));
    f.write("/views/too_small_px", view_column<std::int64_t>(vs, [](auto& v) { return v.too_small_px; }));
    f.write("/views/small_regions", view_column<std::int64_t>(vs, [](auto& v) { return v.small_regions; }));
    f.write("/views/exterior_rays", view_column<std::int64_t>(vs, [](auto& v) { return v.exterior_rays; }));
    f.write("/views/interior_rays", view_column<std::int64_t>(vs, [](auto& v) { return v.interior_rays; }));
    f.write("/views/straddling", view_column<std::int64_t>(vs, [](auto& v) { return v.straddling; }));
    f.write("/views/no_segment", view_column<std::int64_t>(vs, [](auto& v) { return v.no_segment; }));
    f.write("/views/multi_segment", view_column<std::int64_t>(vs, [](auto& v) { return v.multi_segment; }));
    f.write("/views/weak_peaks", view_column<std::int64_t>(vs, [](auto& v) { return v.weak_peaks; }));
    f.write("/views/corner_outside", view_column<std::int64_t>(vs, [](auto& v) { return v.corner_outside; }));
    f.write("/views/exterior_added", view_column<std::int64_t>(vs, [](auto& v) { return v.exterior_added; }));
    f.write("/views/interior_added", view_column<std::int64_t>(vs, [](auto& v) { return v.interior_added; }));
    f.write("/views/conflicts", view_column<std::int64_t>(vs, [](auto& v) { return v.conflicts; }));
    f.write("/views/already", view_column<std::int64_t>(vs, [](auto& v) { return v.already; }));
    f.commit();

    if (!png_dir.empty()) {
      std::vector<cv::Mat> pics;
      std::vector<std::string> caps;
      for (const auto& st : vs) {
        const int v = st.view;
        cv::Mat pic = silfix::view_picture(scene.sil[v], r.s1_masks[v], cs, v, o.margin_px);
        std::ostringstream name, cap;
        name << "view_" << std::setw(3) << std::setfill('0') << v << ".png";
        write_png_rgb(fs::path(png_dir) / name.str(), pic);
        cap << "v" << v << " IoU " << std::fixed << std::setprecision(3) << st.iou << " in+" << st.interior_added
            << " ex+" << st.exterior_added;
        pics.push_back(pic);
        caps.push_back(cap.str());
      }
      if (!pics.empty()) write_png_rgb(fs::path(png_dir) / "sheet.png", silfix::contact_sheet(pics, caps));
    }

    std::int64_t multi = 0, weak = 0, rays = 0, strad = 0, corner = 0, none = 0;
    for (const auto& st : vs)
      multi += st.multi_segment, weak += st.weak_peaks, rays += st.interior_rays, strad += st.straddling,
          corner += st.corner_outside, none += st.no_segment;
    std::ostringstream os;
    os << std::fixed << std::setprecision(4) << "S1 mean IoU " << agree.mean_iou << ", boundary error mean "
       << std::setprecision(2) << agree.mean_boundary_px << " px, p95 " << agree.p95_boundary_px << " px; added "
       << r.exterior_added << " exterior (" << strad << " straddling cells left free), " << r.interior_added
       << " interior (" << rays << " rays: " << multi << " several segments, " << none << " none, " << weak
       << " weak peaks, " << corner << " corner outside); " << r.conflicts << " conflicts, " << r.already
       << " already interior";
    ctx.summary = pass_through ? std::string(kNote) : os.str();
  });
}
