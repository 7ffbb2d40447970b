#include <iostream>

#include "cli/commands.h"
#include "modeling/errors.h"

namespace flexure::cli {

int runFlexure(const std::vector<std::string>& args) {
  CLI::App app(
      "flexure: static minimizers of discrete bending energies on triangle meshes with fixed "
      "boundaries, and how the discretizations differ.",
      "flexure");
  app.set_version_flag("--version", std::string("flexure ") + FLEXURE_VERSION);
  app.require_subcommand(1);
  app.fallthrough();  // --quiet is accepted after the subcommand too
  GlobalOptions global;
  app.add_flag("-q,--quiet", global.quiet, "No progress or notices on stderr");
  app.footer(
      "Exit codes: 0 success, 2 bad input or usage, 3 numerical failure.\n"
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
  registerCompareCommand(app, global);
  registerFairCommand(app, global);

  std::vector<const char*> argv;
  for (const std::string& a : args) argv.push_back(a.c_str());
  try {
    app.parse(static_cast<int>(argv.size()), argv.data());
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::RuntimeError& e) {
    return e.get_exit_code();  // a failed `flexure run` step, already reported
  } catch (const CLI::ParseError& e) {
    std::cerr << "flexure: " << e.what() << "\n(run 'flexure --help' for usage)\n";
    return kExitInputError;
  } catch (const InputError& e) {
    std::cerr << "flexure: error: " << e.what() << '\n';
    return kExitInputError;
  } catch (const NumericalError& e) {
    std::cerr << "flexure: numerical failure: " << e.what() << '\n';
    return kExitNumericalError;
  }
  return 0;
}

}  // namespace flexure::cli
