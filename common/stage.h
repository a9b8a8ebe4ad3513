// The frame every stage program shares: command line (CLI11) with --params, --set,
// --threads, --quiet; the paths it reads and writes, checked before any work
// (common/outputs.h); its outputs committed together at the end, or none of them when it
// fails (common/fileio.h, CommitGroup); error handling (Error -> one line on stderr, exit 1);
// a summary line at the end (seconds, peak memory), and one JSON line in $TETMVS_LOG with
// the warnings the stage gave.
//
//   int main(int argc, char** argv) {
//     tetmvs::StageCli cli("refine", "Red-green refinement of the active cells.");
//     std::string in, out;
//     cli.add_input("--mesh", in, "input mesh (HDF5)").required();
//     cli.add_output("--out", out, "output mesh (HDF5)").required();
//     return cli.run(argc, argv, [&](tetmvs::StageContext& ctx) { ... });
//   }
//
// CLI11 stays inside common/stage.cpp: its header takes about ten seconds to compile, once
// per program that included it.
#pragma once
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "common/log.h"
#include "common/outputs.h"
#include "common/params.h"

namespace CLI {
class App;
class Option;
}  // namespace CLI

namespace tetmvs {

// Most worker threads --threads accepts (each costs a stack; far more than any machine's cores).
inline constexpr int kMaxThreads = 1024;

struct StageContext {
  std::string stage;
  Params params;
  bool quiet = false;
  int threads = 0;  // 0 = OpenMP default
  // Free-form summary fields printed at the end ("cells=123 faces=456").
  std::string summary;
  // The outputs the command line named (checked before the body runs).
  std::vector<PathArg> outputs;
  // An input found while working (e.g. the par file of a dataset folder): refused when it
  // is one of the outputs; `what` names it in the message.
  void add_input(const std::filesystem::path& file, const std::string& what) const {
    check_not_output({what, file, false}, outputs);
  }
};

enum class PathKind { File, Folder };

// One declared option; its checks apply when the command line is parsed.
class StageOption {
 public:
  explicit StageOption(CLI::Option* o) : o_(o) {}
  StageOption& required();
  StageOption& range(int lo, int hi);
  StageOption& range(double lo, double hi);
  StageOption& one_of(const std::vector<std::string>& values);
  StageOption& needs(const StageOption& other);  // given only together with `other`

 private:
  CLI::Option* o_;
};

class StageCli {
 public:
  StageCli(std::string stage, std::string description);
  ~StageCli();
  // Options naming what the stage reads and writes (see the top of the file).
  StageOption add_input(const std::string& flags, std::string& var, const std::string& desc,
                        PathKind kind = PathKind::File);
  StageOption add_input(const std::string& flags, std::vector<std::string>& var, const std::string& desc);
  StageOption add_output(const std::string& flags, std::string& var, const std::string& desc,
                         PathKind kind = PathKind::File);
  // Any other option or flag. A name without dashes is positional.
  StageOption add_option(const std::string& flags, std::string& var, const std::string& desc);
  StageOption add_option(const std::string& flags, std::vector<std::string>& var, const std::string& desc);
  StageOption add_option(const std::string& flags, int& var, const std::string& desc);
  StageOption add_option(const std::string& flags, double& var, const std::string& desc);
  StageOption add_flag(const std::string& flags, bool& var, const std::string& desc);
  // Parses, sets up params/threads, checks the paths, runs body, commits its outputs;
  // returns the process exit code.
  int run(int argc, char** argv, const std::function<void(StageContext&)>& body);

 private:
  struct Declared {
    CLI::Option* opt;
    std::string* one;
    std::vector<std::string>* many;
    bool folder;
  };
  static std::vector<PathArg> given(const std::vector<Declared>& d);
  std::string stage_;
  std::unique_ptr<CLI::App> app_;
  std::string params_file_;
  std::vector<std::string> sets_;
  bool quiet_ = false;
  bool help_all_ = false;  // --help-all (handled before parsing)
  int threads_ = 0;
  std::vector<Declared> inputs_, outputs_;
};

}  // namespace tetmvs
