// validate: which files of a run are damaged (common/validate.h). pipeline.mk runs it on
// the run's intermediates before it decides what to make, so that one truncated or
// overwritten after it was made is rebuilt instead of failing every later make.
#include <iostream>

#include "common/stage.h"
#include "common/validate.h"

using namespace tetmvs;

int main(int argc, char** argv) {
  StageCli cli("validate",
               "Checks that each file opens as what it is (HDF5 with a tetmvs schema, a PLY whose header fits its "
               "size, JSON that parses); prints one line per damaged file on stdout. Exit status 0 either way.");
  std::vector<std::string> files;
  bool names = false;
  cli.add_option("files", files, "files to check");
  cli.add_flag("--names", names, "print only the names of the damaged files");
  return cli.run(argc, argv, [&](StageContext& ctx) {
    int damaged = 0;
    for (const auto& f : files)
      if (const std::string why = file_problem(f); !why.empty()) {
        std::cout << (names ? f : why) << "\n";
        ++damaged;
      }
    ctx.summary = std::to_string(damaged) + " of " + std::to_string(files.size()) + " files damaged";
  });
}
