// The files a command reads and writes, declared with its options, so that one check before any
// work covers every command: each output can be written (its directory exists and takes files, it
// is not a directory), no output is another output or overwrites an input (unless --force). The
// command's callback runs only after the check; its writes are staged (modeling::OutputBatch,
// opened in runFlexure), so a run that fails later still leaves no output. An output folder ends a
// successful run holding this run's files: the files an earlier run of the command wrote there and
// this one did not are removed; other files are left alone.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "cli/commands.h"

namespace flexure::cli {

enum class OutputKind {
  File,      // one file; its directory must exist
  Directory  // a folder, created if missing (with its parents)
};

// Whether a file name in an output folder is one the command writes there (a stale one, when this
// run did not write it).
using OwnedFiles = std::function<bool(const std::string& fileName)>;

class CommandFiles : public std::enable_shared_from_this<CommandFiles> {
 public:
  // Files of the subcommand `sub`; the returned object must outlive the parse (the callback
  // holds it).
  static std::shared_ptr<CommandFiles> of(CLI::App& sub);

  CLI::Option* input(const std::string& names, std::string& path, const std::string& help);
  CLI::Option* inputs(const std::string& names, std::vector<std::string>& paths,
                      const std::string& help);
  CLI::Option* output(const std::string& names, std::string& path, const std::string& help,
                      OutputKind kind = OutputKind::File, OwnedFiles owned = {});

  // Sets the subcommand's callback: check(), then `run`, then the removal of stale files from the
  // output folders (at the commit); with global.checkOnly, check() alone. Adds --force when the
  // command has input and output files.
  void onRun(const GlobalOptions& global, std::function<void()> run);
  // Throws InputError naming the option and the path of the first output that cannot be written.
  // With `directoriesMayAppear`, a missing directory is no error: in a run spec's check an earlier
  // step may create it.
  void check(bool directoriesMayAppear = false) const;

 private:
  explicit CommandFiles(CLI::App& sub) : sub_(sub) {}
  struct Declared {
    std::string option;  // as users see it: "--report", "mesh"
    const std::string* path = nullptr;
    const std::vector<std::string>* paths = nullptr;
    OutputKind kind = OutputKind::File;
    OwnedFiles owned;
  };
  void removeStaleFiles() const;
  CLI::App& sub_;
  std::vector<Declared> inputs_, outputs_;
  bool force_ = false;
};

// Validators for numeric options, whose failure CLI11 reports as "OPTION: message" (exit 2).
// [lo, hi], stated in the message.
CLI::Validator inRange(double lo, double hi);
// > 0.
CLI::Validator positive();
// A random seed: an integer in [0, 2^64 − 1], a negative one refused rather than wrapped.
CLI::Validator seedValue();
// A surface z = p(x, y) as modeling::PolynomialSurface::parse reads it (quadratic:a,b,c or
// polynomial:EXPR), read when the flags are, so `flexure run` refuses a misspelt one before any
// step runs.
CLI::Validator surfaceSpec();
// The largest --threads: 4 threads per core leaves room for hyper-threaded or shared machines
// while refusing values that only thrash (64 on 2 cores).
int maxThreads();

}  // namespace flexure::cli
