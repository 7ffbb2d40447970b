#include <glog/logging.h>

#include <algorithm>
#include <iostream>
#include <new>

#include "cli/commands.h"
#include "cli/option_names.h"
#include "modeling/atomic_write.h"
#include "modeling/errors.h"

namespace flexure::cli {
namespace {

// Levenshtein distance: how many single-character edits turn `a` into `b`.
std::size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// "; did you mean 'X'?" for the closest name within a third of the word's length (at least 2
// edits), else "".
std::string didYouMean(const std::string& word, const std::vector<std::string>& names) {
  std::string best;
  std::size_t bestDistance = std::max<std::size_t>(2, word.size() / 3) + 1;
  for (const std::string& name : names) {
    const std::size_t d = editDistance(word, name);
    if (d < bestDistance) bestDistance = d, best = name;
  }
  return best.empty() ? "" : "; did you mean '" + best + "'?";
}

std::vector<std::string> commandNames(CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; }))
    names.push_back(sub->get_name());
  return names;
}

// The long option names (--name) of `app`.
std::vector<std::string> optionNames(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::Option* option : app.get_options())
    for (const std::string& name : option->get_lnames()) names.push_back("--" + name);
  return names;
}

// The command word: the first argument that is not a global flag. Empty when there is none.
std::string commandWord(const std::vector<std::string>& args) {
  for (std::size_t k = 1; k < args.size(); ++k)
    if (args[k].empty() || args[k][0] != '-') return args[k];
  return "";
}

}  // namespace

int runFlexure(const std::vector<std::string>& args, bool checkOnly) {
  CLI::App app(
      "flexure: static minimizers of discrete bending energies on triangle meshes with fixed "
      "boundaries, and how the discretizations differ.",
      "flexure");
  app.set_version_flag("--version", std::string("flexure ") + FLEXURE_VERSION);
  app.require_subcommand(1);
  app.fallthrough();  // --quiet and --verbose are accepted after the subcommand too
  GlobalOptions global;
  global.checkOnly = checkOnly;
  app.add_flag("-q,--quiet", global.quiet, "No progress or notices on stderr");
  app.add_flag("--verbose", global.verbose,
               "Also on stderr: the Newton iterations of compare's solves (minimize and fair "
               "print theirs unless --quiet) and the solver library's own log (Ceres, glog)");
  app.footer(
      "Exit codes: 0 success, 2 bad input or usage, 3 numerical failure (or out of memory).\n"
      "Run 'flexure COMMAND --help' for a command's options.");

  registerMeshCommand(app, global);
  registerInfoCommand(app, global);
  registerConvertCommand(app, global);
  registerEnergyCommand(app, global);
  registerMinimizeCommand(app, global);
  registerConvergeCommand(app, global);
  registerDemoCommand(app, global);
  registerRunCommand(app, global);
  registerRenderCommand(app, global);
  registerViewCommand(app, global);
  registerCompareCommand(app, global);
  registerFairCommand(app, global);
  registerModesCommand(app, global);
  registerSimulateCommand(app, global);
  registerRepairCommand(app, global);

  // CLI11 would call an unknown command word "a subcommand is required".
  const std::string command = commandWord(args);
  const std::vector<std::string> commands = commandNames(app);
  if (!command.empty() && std::find(commands.begin(), commands.end(), command) == commands.end()) {
    std::cerr << "flexure: unknown command '" << command << "'" << didYouMean(command, commands)
              << "\n(run 'flexure --help' for the commands)\n";
    return kExitInputError;
  }
  // Ceres logs through glog: its lines (warnings about the linear solver, failed evaluations)
  // speak of Ceres' internals, not of the user's options, so they show only with --verbose. The
  // flag is read before parsing because the command runs inside the parse.
  const bool verbose = std::find(args.begin(), args.end(), "--verbose") != args.end();
  FLAGS_logtostderr = true;
  FLAGS_minloglevel = verbose ? google::GLOG_INFO : google::GLOG_FATAL;

  std::vector<const char*> argv;
  for (const std::string& a : args) argv.push_back(a.c_str());
  // The run's outputs are renamed into place only when it succeeds (atomic_write.h).
  modeling::OutputBatch outputs;
  try {
    app.parse(static_cast<int>(argv.size()), argv.data());
    outputs.commit();
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::RuntimeError& e) {
    return e.get_exit_code();  // a failed `flexure run` step, already reported
  } catch (const CLI::ParseError& e) {
    // A misspelt option is left over; CLI11 may first complain about the option it was meant to
    // be ("--energy is required" for --enrgy), so the hint comes with any parse error, first.
    // CLI11's own words for a left-over option ("The following arguments were not expected")
    // say less than the hint and are left out then.
    const std::vector<CLI::App*> parsed = app.get_subcommands();
    std::vector<std::string> names = optionNames(app);
    if (!parsed.empty()) {
      const std::vector<std::string> own = optionNames(*parsed.front());
      names.insert(names.end(), own.begin(), own.end());
    }
    bool hinted = false;
    for (const std::string& extra : app.remaining(true)) {
      const std::string word = extra.substr(0, extra.find('='));
      if (word.rfind("--", 0) != 0 || std::find(names.begin(), names.end(), word) != names.end())
        continue;
      std::cerr << "flexure: '" << word << "' is not an option" << didYouMean(word, names) << '\n';
      hinted = true;
    }
    if (!hinted || dynamic_cast<const CLI::ExtrasError*>(&e) == nullptr)
      std::cerr << "flexure: " << e.what() << '\n';
    std::cerr << "(run 'flexure " << (parsed.empty() ? "" : parsed.front()->get_name() + " ")
              << "--help' for usage)\n";
    return kExitInputError;
  } catch (const InputError& e) {
    std::cerr << "flexure: error: " << withFlagNames(e.what()) << '\n';
    return kExitInputError;
  } catch (const NumericalError& e) {
    std::cerr << "flexure: numerical failure: " << withFlagNames(e.what()) << '\n';
    return kExitNumericalError;
  } catch (const std::bad_alloc&) {
    // Caught here too so that the staged outputs are removed (the batch unwinds first).
    std::cerr << "flexure: out of memory: the job needs more memory than this machine has "
                 "available; try a smaller mesh (--n, --levels) or free memory\n";
    return kExitNumericalError;
  }
  return 0;
}

}  // namespace flexure::cli
