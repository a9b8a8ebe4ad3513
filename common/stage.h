// The frame every stage program shares: command line (CLI11) with --params, --set,
// --threads, --quiet; error handling (Error -> one line on stderr, exit 1); a summary
// line at the end (seconds, peak memory).
//
//   int main(int argc, char** argv) {
//     tetmvs::StageCli cli("refine", "Red-green refinement of the active cells.");
//     std::string in, out;
//     cli.app().add_option("--mesh", in, "input mesh (HDF5)")->required();
//     return cli.run(argc, argv, [&](tetmvs::StageContext& ctx) { ... });
//   }
#pragma once
#include <CLI/CLI.hpp>
#include <functional>
#include <string>

#include "common/log.h"
#include "common/params.h"

namespace tetmvs {

struct StageContext {
  std::string stage;
  Params params;
  bool quiet = false;
  int threads = 0;  // 0 = OpenMP default
  // Free-form summary fields printed at the end ("cells=123 faces=456").
  std::string summary;
};

class StageCli {
 public:
  StageCli(std::string stage, std::string description);
  CLI::App& app() { return app_; }
  // Parses, sets up params/threads, runs body; returns the process exit code.
  int run(int argc, char** argv, const std::function<void(StageContext&)>& body);

 private:
  std::string stage_;
  CLI::App app_;
  std::string params_file_;
  std::vector<std::string> sets_;
  bool quiet_ = false;
  int threads_ = 0;
};

}  // namespace tetmvs
