#include "common/stage.h"

#include <omp.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "common/budget.h"
#include "common/error.h"
#include "common/fileio.h"

namespace tetmvs {

StageOption& StageOption::required() {
  o_->required();
  return *this;
}

StageOption& StageOption::range(int lo, int hi) {
  o_->check(CLI::Range(lo, hi));
  return *this;
}

StageOption& StageOption::range(double lo, double hi) {
  o_->check(CLI::Range(lo, hi));
  return *this;
}

StageOption& StageOption::one_of(const std::vector<std::string>& values) {
  o_->check(CLI::IsMember(values));
  return *this;
}

StageOption& StageOption::needs(const StageOption& other) {
  o_->needs(other.o_);
  return *this;
}

StageCli::StageCli(std::string stage, std::string description)
    : stage_(std::move(stage)), app_(std::make_unique<CLI::App>(std::move(description), stage_)) {
  add_input("--params", params_file_,
            "JSON file of parameter overrides {\"key\": value} (e.g. a dataset's params.json)");
  app_->add_option("--set", sets_, "override one parameter: --set key=value (repeatable)");
  app_->add_option("--threads", threads_, "worker threads (default: all cores); results do not depend on it");
  app_->add_flag("-q,--quiet", quiet_, "no progress or info messages, only errors and the summary");
  app_->set_help_flag("-h,--help", "print this help and exit");
  app_->add_flag("--help-all", help_all_, "print this help with every parameter (the expert tier too) and exit");
  try {
    app_->footer(Params::defaults().help_for(stage_));
  } catch (const Error&) {
  }
}

StageCli::~StageCli() = default;

StageOption StageCli::add_input(const std::string& flags, std::string& var, const std::string& desc, PathKind kind) {
  CLI::Option* o = app_->add_option(flags, var, desc);
  inputs_.push_back({o, &var, nullptr, kind == PathKind::Folder});
  return StageOption(o);
}

StageOption StageCli::add_input(const std::string& flags, std::vector<std::string>& var, const std::string& desc) {
  CLI::Option* o = app_->add_option(flags, var, desc);
  inputs_.push_back({o, nullptr, &var, false});
  return StageOption(o);
}

StageOption StageCli::add_output(const std::string& flags, std::string& var, const std::string& desc, PathKind kind) {
  CLI::Option* o = app_->add_option(flags, var, desc);
  outputs_.push_back({o, &var, nullptr, kind == PathKind::Folder});
  return StageOption(o);
}

StageOption StageCli::add_option(const std::string& flags, std::string& var, const std::string& desc) {
  return StageOption(app_->add_option(flags, var, desc));
}

StageOption StageCli::add_option(const std::string& flags, std::vector<std::string>& var, const std::string& desc) {
  return StageOption(app_->add_option(flags, var, desc));
}

StageOption StageCli::add_option(const std::string& flags, int& var, const std::string& desc) {
  return StageOption(app_->add_option(flags, var, desc));
}

StageOption StageCli::add_option(const std::string& flags, double& var, const std::string& desc) {
  return StageOption(app_->add_option(flags, var, desc));
}

StageOption StageCli::add_flag(const std::string& flags, bool& var, const std::string& desc) {
  return StageOption(app_->add_flag(flags, var, desc));
}

std::vector<PathArg> StageCli::given(const std::vector<Declared>& d) {
  std::vector<PathArg> out;
  for (const auto& x : d) {
    if (x.opt->count() == 0) continue;  // not on the command line
    const std::string name = x.opt->get_name();
    if (x.one) out.push_back({name, *x.one, x.folder});
    if (x.many)
      for (const auto& p : *x.many) out.push_back({name, p, x.folder});
  }
  return out;
}

namespace {

// --threads within range, and without it the number the environment (OMP_NUM_THREADS) asks
// for: OpenMP aborts the program when it cannot make the threads.
void check_threads(int threads) {
  if (threads < 0 || threads > kMaxThreads)
    fail("--threads ", threads, ": must be from 1 to ", kMaxThreads, " (or 0: all cores)");
  if (threads == 0 && omp_get_max_threads() > kMaxThreads)
    fail("environment OMP_NUM_THREADS asks for ", omp_get_max_threads(), " threads, more than ", kMaxThreads,
         "; unset it or give --threads");
}

}  // namespace

int StageCli::run(int argc, char** argv, const std::function<void(StageContext&)>& body) {
  for (int a = 1; a < argc; ++a)
    if (std::string(argv[a]) == "--help-all") {
      try {
        app_->footer(Params::defaults().help_for(stage_, true));
      } catch (const Error&) {
      }
      std::fputs(app_->help().c_str(), stdout);
      return 0;
    }
  try {
    app_->parse(argc, argv);
  } catch (const CLI::Success& e) {  // --help
    return app_->exit(e);
  } catch (const CLI::ParseError& e) {
    // one line, like every other error
    std::fprintf(stderr, "%s: error: %s (see --help)\n", stage_.c_str(), e.what());
    return 2;
  }
  // A file size limit (ulimit -f) makes writes fail with an error we report, instead of
  // killing the stage with SIGXFSZ.
  std::signal(SIGXFSZ, SIG_IGN);
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<PathArg> inputs;
  try {
    StageContext ctx;
    ctx.stage = stage_;
    ctx.quiet = quiet_;
    set_quiet(quiet_);
    check_threads(threads_);
    ctx.params = Params::defaults();
    if (!params_file_.empty()) ctx.params.merge_file(params_file_);
    for (const auto& s : sets_) ctx.params.set(s);
    set_stage_memory_budget(memory_budget(ctx.params));
    // every path before any work
    inputs = given(inputs_);
    ctx.outputs = given(outputs_);
    check_output_paths(ctx.outputs, inputs);
    ctx.threads = threads_;
    if (threads_ > 0) {
      omp_set_num_threads(threads_);
      cv::setNumThreads(threads_);
    }
    cv::setRNGSeed(0);
    {
      CommitGroup outputs;  // the outputs appear together at the end, or not at all
      body(ctx);
      outputs.commit_all();
    }
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
      const char* tunables = std::getenv("GLIBC_TUNABLES");
      j["huge_pages"] = tunables && std::string(tunables).find("glibc.malloc.hugetlb=1") != std::string::npos;
      if (largest_memory_estimate() > 0) j["estimated_memory_mb"] = largest_memory_estimate() / 1048576.0;
      if (const auto w = warnings_given(); !w.empty()) j["warnings"] = w;
      if (FILE* f = std::fopen(log, "a")) {
        std::fprintf(f, "%s\n", j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace).c_str());
        std::fclose(f);
      }
    }
    return 0;
  } catch (const Error& e) {
    std::fprintf(stderr, "%s: error: %s\n", stage_.c_str(), e.what());
  } catch (const cv::Exception& e) {
    std::fprintf(stderr, "%s: error: OpenCV: %s\n", stage_.c_str(), e.err.c_str());
  } catch (const std::bad_alloc&) {
    std::string names;
    for (const auto& i : inputs) names += (names.empty() ? "" : ", ") + i.path.string();
    std::fprintf(stderr, "%s: error: out of memory%s; reduce the problem size (e.g. fewer levels)\n", stage_.c_str(),
                 names.empty() ? "" : (" working on " + names).c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: error: internal: %s\n", stage_.c_str(), e.what());
  }
  return 1;
}

}  // namespace tetmvs
