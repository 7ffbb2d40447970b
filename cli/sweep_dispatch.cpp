#include "cli/sweep_dispatch.h"

#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <vector>

#include "modeling/errors.h"

namespace flexure::cli {

// The interpreter: $FLEXURE_PYTHON, else Debian's /usr/bin/python3 (the one the module is built
// for), else python3 on PATH; the package: the build tree's beside this executable
// (build/cli/flexure → build/python) ahead of PYTHONPATH, else the installed one.
int runSweep(const SweepDispatch& sweep, const GlobalOptions& global,
             const std::string& commandName) {
  namespace fs = std::filesystem;
  const fs::path self = fs::read_symlink("/proc/self/exe");
  const fs::path buildTreePackage = self.parent_path().parent_path() / "python";
  std::string pythonPath;
  if (fs::exists(buildTreePackage / "flexure" / "__init__.py")) {
    const char* path = std::getenv("PYTHONPATH");
    pythonPath = buildTreePackage.string() + (path && *path ? ":" + std::string(path) : "");
  }
  const char* chosen = std::getenv("FLEXURE_PYTHON");
  const std::string python =
      chosen && *chosen ? chosen
                        : (fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3");
  std::vector<std::string> args = {python,         "-m",           "flexure", "sweep",
                                   sweep.specFile, sweep.gridFile, "--out",   sweep.outputDir,
                                   "--command",    self.string()};
  if (!sweep.scheduler.empty()) args.insert(args.end(), {"--scheduler", sweep.scheduler});
  if (sweep.workers > 0) args.insert(args.end(), {"--workers", std::to_string(sweep.workers)});
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::cout.flush();
  const pid_t child = fork();
  if (child == 0) {
    if (!pythonPath.empty()) setenv("PYTHONPATH", pythonPath.c_str(), 1);
    execvp(argv[0], argv.data());
    std::cerr << commandName << ": cannot start " << python << " (" << std::strerror(errno)
              << "); a sweep needs Python 3 with flexure's module and Dask's distributed "
                 "(set FLEXURE_PYTHON to choose the interpreter)\n";
    _exit(kExitInputError);
  }
  int status = 0;
  if (child < 0 || waitpid(child, &status, 0) < 0)
    throw InputError(commandName + ": cannot start the sweep: " + std::strerror(errno));
  if (!global.quiet && WIFSIGNALED(status))
    std::cerr << commandName << ": the sweep was killed by signal " << WTERMSIG(status) << '\n';
  // Python's "No module named flexure / distributed" exits 1: a missing prerequisite, bad input.
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 3;
  return code == 1 ? kExitInputError : code;
}

}  // namespace flexure::cli
