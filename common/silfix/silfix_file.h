// silfix.h5 as `silhouette-fix` writes it (schema tetmvs.labels with the constraints and
// per-view numbers, schemas/silfix.md): one table of its datasets and attributes; the
// stage's summary sentence, its pictures, and the --agreement mode's report.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "common/h5fields.h"
#include "common/scene.h"
#include "common/silfix/fix_labels.h"

namespace tetmvs::silfix {

const h5::Fields<Outcome>& silfix_fields();

// "S1 mean IoU ..., added N exterior (...), M interior (R rays: ...); ..." (scripts/
// bench_pipeline.py reads "R rays"), or the note when the labels were passed through.
std::string summary_line(const Outcome& out);

// view_<NNN>.png per view with a silhouette and sheet.png (all of them, captioned) in `dir`.
void write_pictures(const std::filesystem::path& dir, const Scene& scene, const Outcome& out, double margin_px);

// The --agreement mode: each surface's silhouette agreement, as one line each (info) and as
// JSON in json_out (when not empty); returns the lines joined by "; " (the summary).
std::string report_agreement(const Scene& scene, const std::vector<std::string>& plys,
                             const std::filesystem::path& json_out);

}  // namespace tetmvs::silfix
