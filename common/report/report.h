// The run report: one self-contained HTML page (PNGs embedded) summarising a run directory:
// inputs and silhouettes, the mesh per level, Q, labels, the surfaces from several views,
// silhouette agreement, ground-truth metrics, time and memory of every stage, parameters.
#pragma once
#include <filesystem>
#include <string>

namespace tetmvs::report {

struct Options {
  std::filesystem::path run_dir;
  std::string title;
  double roughness_radius_px = 5;  // eval.roughness_radius_px
};

// Builds the page; returns its HTML text.
std::string build_report(const Options& o);

// Base64 of bytes (for data: URIs).
std::string base64(const std::string& bytes);

}  // namespace tetmvs::report
