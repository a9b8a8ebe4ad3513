#include "common/stage.h"

#include <omp.h>

#include <chrono>
#include <cstdlib>
#include <ctime>
#include <nlohmann/json.hpp>
#include <cstdio>
#include <opencv2/core.hpp>

#include "common/error.h"

namespace tetmvs {

StageCli::StageCli(std::string stage, std::string description)
    : stage_(std::move(stage)), app_(std::move(description), stage_) {
  app_.add_option("--params", params_file_,
                  "JSON file of parameter overrides {\"key\": value} (e.g. a dataset's params.json)");
  app_.add_option("--set", sets_, "override one parameter: --set key=value (repeatable)");
  app_.add_option("--threads", threads_, "worker threads (default: all cores); results do not depend on it");
  app_.add_flag("-q,--quiet", quiet_, "no progress or info messages, only errors and the summary");
  app_.set_help_flag("-h,--help", "print this help and exit");
  try {
    app_.footer(Params::defaults().help_for(stage_));
  } catch (const Error&) {
  }
}

int StageCli::run(int argc, char** argv, const std::function<void(StageContext&)>& body) {
  try {
    app_.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app_.exit(e);
  }
  const auto t0 = std::chrono::steady_clock::now();
  try {
    StageContext ctx;
    ctx.stage = stage_;
    ctx.quiet = quiet_;
    set_quiet(quiet_);
    ctx.params = Params::defaults();
    if (!params_file_.empty()) ctx.params.merge_file(params_file_);
    for (const auto& s : sets_) ctx.params.set(s);
    if (threads_ < 0) fail("--threads must be >= 0");
    ctx.threads = threads_;
    if (threads_ > 0) {
      omp_set_num_threads(threads_);
      cv::setNumThreads(threads_);
    }
    cv::setRNGSeed(0);
    body(ctx);
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::fprintf(stderr, "[%s] done in %.2f s, peak memory %.0f MB%s%s\n", stage_.c_str(), secs,
                 peak_memory_bytes() / 1048576.0, ctx.summary.empty() ? "" : "; ",
                 ctx.summary.c_str());
    // Run log for reports and benchmarks: one JSON line per stage run.
    if (const char* log = std::getenv("TETMVS_LOG"); log && *log) {
      nlohmann::json j = {{"stage", stage_}, {"seconds", secs},
                          {"peak_memory_mb", peak_memory_bytes() / 1048576.0},
                          {"threads", threads_ > 0 ? threads_ : omp_get_max_threads()},
                          {"summary", ctx.summary}, {"time", static_cast<long long>(std::time(nullptr))}};
      std::string args;
      for (int i = 1; i < argc; ++i) args += (i > 1 ? " " : "") + std::string(argv[i]);
      j["args"] = args;
      j["cpu_seconds"] = static_cast<double>(std::clock()) / CLOCKS_PER_SEC;
      if (FILE* f = std::fopen(log, "a")) {
        std::fprintf(f, "%s\n", j.dump().c_str());
        std::fclose(f);
      }
    }
    return 0;
  } catch (const Error& e) {
    std::fprintf(stderr, "%s: error: %s\n", stage_.c_str(), e.what());
  } catch (const cv::Exception& e) {
    std::fprintf(stderr, "%s: error: OpenCV: %s\n", stage_.c_str(), e.err.c_str());
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "%s: error: out of memory; reduce the problem size (e.g. fewer levels)\n",
                 stage_.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: error: internal: %s\n", stage_.c_str(), e.what());
  }
  return 1;
}

}  // namespace tetmvs
