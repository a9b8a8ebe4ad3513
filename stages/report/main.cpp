// report: a self-contained HTML page (PNGs embedded) of a run directory.
#include <filesystem>

#include "common/error.h"
#include "common/fileio.h"
#include "common/report/report.h"
#include "common/stage.h"

namespace fs = std::filesystem;
using namespace tetmvs;

int main(int argc, char** argv) {
  StageCli cli("report",
               "Writes one self-contained HTML page about a run directory: results against the "
               "silhouettes and ground truth, the surfaces from several views, input silhouettes, "
               "the mesh per level, Q, labels, silhouette fix, time and memory per stage, parameters.");
  std::string run, out, title;
  cli.add_input("run_dir", run, "run directory (RUN_DIR of pipeline.mk)", PathKind::Folder).required();
  cli.add_output("-o,--out", out, "output HTML (default RUN_DIR/report/index.html)");
  cli.add_option("--title", title, "page title");
  return cli.run(argc, argv, [&](StageContext& ctx) {
    require(fs::is_directory(run), run, ": is not a run directory (no such folder)");
    const fs::path target = out.empty() ? fs::path(run) / "report" / "index.html" : fs::path(out);
    if (out.empty()) check_output_paths({{"--out (default)", target, false}}, {});
    report::Options o;
    o.run_dir = run;
    o.roughness_radius_px = ctx.params.d("eval.roughness_radius_px");
    o.title = title.empty() ? "tetmvs run: " + fs::path(run).filename().string() : title;
    const std::string html = report::build_report(o);
    write_text_atomic(target, html);
    ctx.summary = target.string() + " (" + std::to_string(html.size() / 1024) + " KiB)";
  });
}
