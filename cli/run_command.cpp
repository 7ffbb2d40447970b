// flexure run: a study kept as a file. A run spec is a JSON object naming a subcommand and its
// options, or {"steps": [ ... ]} for several in order:
//
//   {"command": "mesh",
//    "options": {"family": "delaunay", "n": 32, "seed": 7, "o": "plate.obj"},
//    "inputs": []}
//
// Each option becomes "--name value" ("-n value" for one-letter names); true becomes a bare flag,
// false or null is left out, an array passes several values. "inputs" are positional arguments.
// Relative paths resolve against the working directory, as on the command line; "${spec_dir}" in
// a string stands for the directory holding the spec, so a spec can name files kept beside it.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/sweep_dispatch.h"
#include "modeling/errors.h"

namespace flexure::cli {
namespace {

struct RunCommandOptions {
  std::string specFile;
  bool dryRun = false;
  bool checkOnly = false;
  std::string gridFile;   // a sweep: the spec run for every row of the grid (flexure.sweep)
  std::string scheduler;  // the sweep's Dask scheduler address ("": local worker processes)
  int workers = 0;        // local worker processes (0: one per CPU)
  std::string sweepDir = "sweep";
};

std::string expandSpecDir(std::string text, const std::string& specDir) {
  const std::string token = "${spec_dir}";
  for (size_t at = text.find(token); at != std::string::npos;
       at = text.find(token, at + specDir.size()))
    text.replace(at, token.size(), specDir);
  return text;
}

std::string scalarText(const nlohmann::json& value, const std::string& where) {
  if (value.is_string()) return value.get<std::string>();
  if (value.is_number_integer()) return std::to_string(value.get<long long>());
  if (value.is_number()) return value.dump();  // shortest round-trip form
  throw InputError(where + ": expected a string or a number, got " + value.dump());
}

std::vector<std::string> commandLine(const nlohmann::json& step, const std::string& where,
                                     const std::string& specDir) {
  if (!step.is_object() || !step.contains("command") || !step["command"].is_string()) {
    throw InputError(where + ": a step needs \"command\": the name of a flexure subcommand");
  }
  for (const auto& [key, value] : step.items()) {
    if (key != "command" && key != "options" && key != "inputs")
      throw InputError(where + ": unknown key \"" + key + "\" (expected command, options, inputs)");
  }
  const std::string command = step["command"];
  if (command == "run") throw InputError(where + ": a run spec cannot run another run spec");
  std::vector<std::string> args = {"flexure", command};
  const auto expand = [&](const nlohmann::json& v, const std::string& at) {
    return expandSpecDir(scalarText(v, at), specDir);
  };
  if (step.contains("options")) {
    if (!step["options"].is_object()) throw InputError(where + ".options: expected an object");
    for (const auto& [name, value] : step["options"].items()) {
      const std::string at = where + ".options." + name;
      const std::string flag = (name.size() == 1 ? "-" : "--") + name;
      if (value.is_null() || (value.is_boolean() && !value.get<bool>())) continue;
      args.push_back(flag);
      if (value.is_boolean()) continue;
      if (value.is_array()) {
        for (const auto& item : value) args.push_back(expand(item, at));
      } else {
        args.push_back(expand(value, at));
      }
    }
  }
  if (step.contains("inputs")) {
    if (!step["inputs"].is_array()) throw InputError(where + ".inputs: expected an array");
    for (const auto& input : step["inputs"]) args.push_back(expand(input, where + ".inputs"));
  }
  return args;
}

int runRunCommand(const RunCommandOptions& o, const GlobalOptions& global) {
  if (!o.gridFile.empty())
    return runSweep({o.specFile, o.gridFile, o.sweepDir, o.scheduler, o.workers}, global,
                    "flexure run --grid");
  std::ifstream in(o.specFile);
  if (!in) throw InputError(o.specFile + ": cannot open the run spec");
  nlohmann::json spec;
  try {
    spec = nlohmann::json::parse(in);
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(o.specFile + ": not valid JSON: " + e.what());
  }
  const std::string specDir = std::filesystem::absolute(o.specFile).parent_path().string();
  std::vector<std::vector<std::string>> steps;
  if (spec.is_object() && spec.contains("steps")) {
    if (!spec["steps"].is_array() || spec.size() != 1)
      throw InputError(o.specFile + ": expected {\"steps\": [ ... ]} and nothing else beside it");
    for (size_t k = 0; k < spec["steps"].size(); ++k)
      steps.push_back(commandLine(spec["steps"][k],
                                  o.specFile + ": steps[" + std::to_string(k) + "]", specDir));
  } else {
    steps.push_back(commandLine(spec, o.specFile, specDir));
  }

  // Every step's options and outputs are checked before the first step runs, so that a mistake in
  // the last step does not come after the work of the others. A step's directory and inputs may
  // not exist yet (an earlier step may make them).
  for (size_t k = 0; k < steps.size() && !o.dryRun; ++k) {
    const int code = runFlexure(steps[k], /*checkOnly=*/true);
    if (code != 0) {
      std::cerr << "flexure run: " << o.specFile << ": step " << k + 1 << " would fail (exit "
                << code << "); no step was run\n";
      return code;
    }
  }
  if (o.checkOnly) return 0;

  for (size_t k = 0; k < steps.size(); ++k) {
    std::vector<std::string> args = steps[k];
    if (global.quiet) args.insert(args.begin() + 1, "--quiet");
    if (global.verbose) args.insert(args.begin() + 1, "--verbose");
    std::string shown;
    for (size_t a = 0; a < args.size(); ++a) shown += (a ? " " : "") + args[a];
    if (o.dryRun) {
      std::cout << shown << '\n';
      continue;
    }
    if (!global.quiet)
      std::cerr << "flexure run: [" << k + 1 << "/" << steps.size() << "] " << shown << '\n';
    const int code = runFlexure(args);
    if (code != 0) {
      std::cerr << "flexure run: " << o.specFile << ": step " << k + 1 << " failed (exit " << code
                << ")\n";
      return code;
    }
  }
  return 0;
}

}  // namespace

void registerRunCommand(CLI::App& app, const GlobalOptions& global) {
  auto options = std::make_shared<RunCommandOptions>();
  CLI::App* sub = app.add_subcommand("run", "Run a study kept as a JSON run spec (see examples/)");
  sub->add_option("spec", options->specFile, "Run spec (.json)")->required();
  CLI::Option* dryRun = sub->add_flag("--dry-run", options->dryRun,
                                      "Print the command lines instead of running them");
  CLI::Option* check =
      sub->add_flag("--check", options->checkOnly,
                    "Check every step's options and outputs as a run does before its first step, "
                    "and run nothing (exit 0 or the exit a run would stop with)")
          ->excludes(dryRun);
  CLI::Option* grid = sub->add_option(
      "--grid", options->gridFile,
      "A sweep: run the spec, whose strings hold ${name} placeholders, for every row of this "
      "grid (.json: {name: [values]} or [{name: value}]) on Dask workers, each case in its own "
      "folder (docs/sweeps.md)");
  grid->excludes(dryRun)->excludes(check);
  sub->add_option("--scheduler", options->scheduler,
                  "With --grid: a Dask scheduler's address (default: local worker processes)")
      ->needs(grid);
  sub->add_option("--workers", options->workers,
                  "With --grid: local worker processes (default: one per CPU)")
      ->needs(grid)
      ->check(CLI::PositiveNumber);
  sub->add_option("-o,--output", options->sweepDir,
                  "With --grid: the sweep's folder (case folders and sweep.csv)")
      ->capture_default_str()
      ->needs(grid);
  sub->callback([options, &global] {
    const int code = runRunCommand(*options, global);
    if (code != 0) throw CLI::RuntimeError(code);
  });
}

}  // namespace flexure::cli
