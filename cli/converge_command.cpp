// flexure converge: the convergence study — C1, C2, nonlinear C2 and refinement — over energies,
// mesh families and levels, written as results.json, results.csv, summary.md and PNG plots.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

#include "cli/bending_arguments.h"
#include "cli/command_files.h"
#include "cli/commands.h"
#include "cli/solver_arguments.h"
#include "cli/spectrum_outputs.h"
#include "cli/study_outputs.h"
#include "cli/sweep_dispatch.h"
#include "modeling/atomic_write.h"
#include "modeling/errors.h"
#include "modeling/mesh_io.h"
#include "optimize/studies/convergence_study.h"
#include "reports/study_parts.h"

namespace flexure::cli {
namespace {

struct ConvergeCommandOptions {
  std::vector<std::string> energies, families, meshFiles;
  std::vector<std::uint64_t> seeds = {1};
  int n = 8, levels = 3, amplitudes = 4, threads = 2;
  std::string quadratics, solution = optimize::kDefaultSolution;
  std::optional<double> poisson;
  std::string outputDir;
  SolverArguments solver;
  // --measure modes: the vibration spectrum (reports/spectrum_outputs.h) in place of C1/C2.
  std::string measure = "c1c2", support = "simply-supported";
  int count = 6;
  // The energies as the cases of a Dask sweep (cli/sweep_dispatch.h): a scheduler's address, or
  // local worker processes; threadsGiven: --threads was given (each case's, else 1).
  std::string scheduler;
  int workers = 0;
  bool threadsGiven = false;
};

// "a,b,c;a,b,c;…" → quadratics. Throws InputError quoting the entry.
std::vector<optimize::Quadratic> parseQuadratics(const std::string& text) {
  std::vector<optimize::Quadratic> quadratics;
  std::istringstream entries(text);
  std::string entry;
  while (std::getline(entries, entry, ';')) {
    double values[3];
    const char* cursor = entry.c_str();
    bool ok = true;
    for (int k = 0; k < 3 && ok; ++k) {
      char* end = nullptr;
      values[k] = std::strtod(cursor, &end);
      ok = end != cursor;
      cursor = end;
      while (*cursor == ' ') ++cursor;
      if (k < 2) ok = ok && *cursor++ == ',';
    }
    if (!ok || *cursor != '\0') {
      throw InputError("--quadratics '" + text + "': entry '" + entry +
                       "' is not a,b,c (expected triples separated by ';', e.g. "
                       "\"1,0,0;0.3,-0.7,0.5\" for x² and 0.3x² − 0.7xy + 0.5y²)");
    }
    quadratics.push_back({values[0], values[1], values[2]});
  }
  return quadratics;
}

optimize::StudyOptions studyOptions(const ConvergeCommandOptions& o, bool familiesGiven) {
  optimize::StudyOptions study;
  study.energies = o.energies.empty() ? optimize::defaultEnergyVariants(o.poisson)
                                      : optimize::parseEnergyVariants(o.energies, o.poisson);
  // With --mesh, the generated families run only when named.
  if (familiesGiven || !o.meshFiles.empty())
    study.families = optimize::parseStudyFamilies(o.families);
  study.seeds = o.seeds;
  for (const std::string& file : o.meshFiles)
    study.userMeshes.push_back({file, modeling::readMesh(file)});
  study.baseN = o.n;
  study.levels = o.levels;
  if (!o.quadratics.empty()) study.quadratics = parseQuadratics(o.quadratics);
  study.amplitudes = o.amplitudes;
  study.solution = o.solution == "none" ? "" : o.solution;
  study.threads = o.threads;
  optimize::MinimizeOptions solver;
  applySolverArguments(o.solver, solver);
  study.solver = solver.solver;
  study.hessian = solver.hessian;
  return study;
}

optimize::SpectrumStudyOptions spectrumOptions(const ConvergeCommandOptions& o,
                                               bool familiesGiven) {
  const optimize::StudyOptions study = studyOptions(o, familiesGiven);
  optimize::SpectrumStudyOptions spectrum;
  spectrum.energies = reports::spectrumEnergies(
      o.energies.empty() ? std::vector<optimize::EnergyVariant>{} : study.energies, o.poisson);
  spectrum.families = familiesGiven
                          ? study.families
                          : std::vector<modeling::MeshFamily>{modeling::MeshFamily::Patch48,
                                                              modeling::MeshFamily::Delaunay};
  spectrum.seeds = o.seeds;
  spectrum.baseN = o.n;
  spectrum.levels = o.levels;
  spectrum.count = o.count;
  spectrum.support = optimize::parseSupport(o.support);
  return spectrum;
}

// The run spec of one energy's part of the study: `flexure converge` with the command's options,
// ${energy} for --energies, writing to the case folder's part/. Meshes by absolute path (a case
// runs in its own folder).
nlohmann::json convergePartSpec(const ConvergeCommandOptions& o, bool familiesGiven) {
  nlohmann::json options = {{"energies", "${energy}"},
                            {"seeds", o.seeds},
                            {"n", o.n},
                            {"levels", o.levels},
                            {"amplitudes", o.amplitudes},
                            {"solution", o.solution},
                            {"threads", o.threadsGiven ? o.threads : 1},
                            {"solver", o.solver.solver},
                            {"hessian", o.solver.hessian},
                            {"o", "part"}};
  if (familiesGiven) options["families"] = o.families;
  nlohmann::json meshes = nlohmann::json::array();
  for (const std::string& file : o.meshFiles)
    meshes.push_back(std::filesystem::absolute(file).string());
  if (!meshes.empty()) options["mesh"] = meshes;
  if (!o.quadratics.empty()) options["quadratics"] = o.quadratics;
  if (o.poisson) options["poisson"] = *o.poisson;
  return {{"command", "converge"}, {"options", options}};
}

// The parts' results.json (DIR/cases/<case>/part/), in the sweep table's row order (the energies'),
// read back and joined; user meshes renamed from the absolute paths the parts were given to the
// names the command was given.
optimize::StudyResults joinConvergeParts(const ConvergeCommandOptions& o,
                                         const optimize::StudyOptions& study,
                                         const std::filesystem::path& cases) {
  const auto readJson = [](const std::filesystem::path& path) {
    std::ifstream in(path);
    if (!in) throw InputError(path.string() + ": cannot be read");
    try {
      return nlohmann::json::parse(in);
    } catch (const nlohmann::json::parse_error& e) {
      throw InputError(path.string() + ": not valid JSON: " + e.what());
    }
  };
  const nlohmann::json table = readJson(cases / "sweep.json");
  std::vector<optimize::StudyResults> parts;
  for (const nlohmann::json& row : table) {
    const auto file = cases / row.at("case").get<std::string>() / "part" / "results.json";
    parts.push_back(reports::studyResultsFromJson(readJson(file), study, file.string()));
  }
  if (parts.size() != study.energies.size())
    throw InputError((cases / "sweep.json").string() + ": " + std::to_string(parts.size()) +
                     " parts for " + std::to_string(study.energies.size()) + " energies");
  optimize::StudyResults joined = reports::joinStudyParts(std::move(parts));
  for (const std::string& file : o.meshFiles) {
    const std::string absolute = std::filesystem::absolute(file).string();
    for (optimize::StudyRecord& r : joined.records)
      if (r.family == absolute) r.family = file;
  }
  return joined;
}

// --scheduler / --workers: each energy's part of the study is a case of a Dask sweep in
// DIR/cases/ (resumable: a rerun runs only the parts not done), then the parts are joined and
// written as a local run writes them; the tables equal a local run's.
void runConvergeSweep(const ConvergeCommandOptions& o, bool familiesGiven,
                      const GlobalOptions& global) {
  const optimize::StudyOptions study = studyOptions(o, familiesGiven);
  study.validate();
  nlohmann::json energies = nlohmann::json::array();
  for (const optimize::EnergyVariant& v : study.energies)
    energies.push_back(optimize::energyVariantSpec(v));
  const std::filesystem::path cases = std::filesystem::path(o.outputDir) / "cases";
  modeling::createOutputDirectory(cases.string());
  modeling::writeFileNow((cases / "part.json").string(),
                         convergePartSpec(o, familiesGiven).dump(1) + "\n");
  modeling::writeFileNow((cases / "grid.json").string(),
                         nlohmann::json{{"energy", energies}}.dump(1) + "\n");
  const int code = runSweep({(cases / "part.json").string(), (cases / "grid.json").string(),
                             cases.string(), o.scheduler, o.workers},
                            global, "flexure converge");
  if (code == kExitInputError) {  // refused before any part ran: leave nothing behind
    std::filesystem::remove(cases / "part.json");
    std::filesystem::remove(cases / "grid.json");
    throw CLI::RuntimeError(code);
  }
  if (code != 0) {
    std::cerr << "flexure converge: not every energy's part of the study ran (" << cases.string()
              << "/sweep.csv); no table was written; a rerun runs only the parts not done\n";
    throw CLI::RuntimeError(code);
  }
  const optimize::StudyResults results = joinConvergeParts(o, study, cases);
  const std::string summary = reports::writeStudyOutputs(
      study, results, optimize::summarizeStudy(study, results), o.outputDir);
  std::cout << summary;
  if (!global.quiet) {
    std::cerr << "flexure converge: joined " << study.energies.size()
              << " parts; wrote results.json, results.csv, summary.md and the plots to "
              << o.outputDir << '\n';
  }
}

void runConvergeCommand(const ConvergeCommandOptions& o, bool familiesGiven,
                        const GlobalOptions& global) {
  if (o.measure == "modes") {
    if (!o.scheduler.empty() || o.workers > 0)
      throw InputError("--scheduler and --workers apply to --measure c1c2");
    if (!o.meshFiles.empty())
      throw InputError("--measure modes runs on the generated square plates; --mesh is for C1/C2");
    const std::string summary = runSpectrumStudyInto(spectrumOptions(o, familiesGiven), o.outputDir,
                                                     global, "flexure converge");
    std::cout << summary;
    if (!global.quiet) {
      std::cerr << "flexure converge: wrote spectrum.md, spectrum.json, spectrum.csv and the "
                   "plots to "
                << o.outputDir << '\n';
    }
    return;
  }
  if (o.measure != "c1c2") throw InputError("--measure " + o.measure + ": expected c1c2 or modes");
  if (!o.scheduler.empty() || o.workers > 0) return runConvergeSweep(o, familiesGiven, global);
  const optimize::StudyOptions study = studyOptions(o, familiesGiven);
  const std::string summary = runStudyInto(study, o.outputDir, global, "flexure converge");
  std::cout << summary;
  if (!global.quiet) {
    std::cerr << "flexure converge: wrote results.json, results.csv, summary.md and the plots to "
              << o.outputDir << '\n';
  }
}

}  // namespace

void registerConvergeCommand(CLI::App& app, const GlobalOptions& global) {
  auto options = std::make_shared<ConvergeCommandOptions>();
  const auto takesPoisson = [](const curvature::EnergyEntry& e) {
    return e.poissonRule == curvature::PoissonRule::Koiter;
  };
  const auto meanCurvatureOnly = [](const curvature::EnergyEntry& e) {
    return e.poissonRule == curvature::PoissonRule::MeanCurvatureOnly;
  };
  CLI::App* sub = app.add_subcommand(
      "converge",
      "Convergence study: C1/C2 quadratic reproduction, nonlinear C2 and refinement against an "
      "exact plate solution, with tables and plots");
  sub->add_option("--energies", options->energies,
                  "Comma-separated: " + optimize::energyVariantSpecs(true, ", ") +
                      " (default: the spec's seven rows)")
      ->delimiter(',');
  CLI::Option* families =
      sub->add_option("--families", options->families,
                      "Comma-separated: patch48, stripe, criss, delaunay (default: all four, or "
                      "none when --mesh is given)")
          ->delimiter(',');
  sub->add_option("--seeds", options->seeds,
                  "delaunay: comma-separated seeds, one mesh sequence each")
      ->delimiter(',')
      ->capture_default_str()
      ->check(seedValue());
  auto files = CommandFiles::of(*sub);
  files->inputs("--mesh", options->meshFiles,
                "A flat mesh of yours (z = 0; repeat for several): C1, C2, nonlinear C2");
  sub->add_option("-n,--n", options->n, "Cells per side of the coarsest generated meshes")
      ->capture_default_str()
      ->check(inRange(2, 1024));
  sub->add_option("--levels", options->levels, "Refinement levels: n, 2n, …, 2^(K-1) n (1 to 8)")
      ->capture_default_str()
      ->check(inRange(1, 8));
  CLI::Option* quadratics =
      sub->add_option("--quadratics", options->quadratics,
                      "Quadratics a,b,c (p = a x² + b xy + c y²) separated by ';' (default "
                      "\"1,0,0;0,1,0;1,0,1;1,0,-1;0.3,-0.7,0.5\")");
  CLI::Option* amplitudes =
      sub->add_option("--amplitudes", options->amplitudes,
                      "Nonlinear C2 at eps = 2^-1 … 2^-K on the coarsest meshes (0: none)")
          ->capture_default_str()
          ->check(inRange(0, 30));
  CLI::Option* solution =
      sub->add_option("--solution", options->solution,
                      "Refinement data: a biharmonic polynomial:EXPR (none: no refinement)")
          ->capture_default_str();
  sub->add_option("--poisson", options->poisson,
                  "Poisson's ratio nu for " +
                      curvature::energyNamesWhere(takesPoisson, ", ", " and ") + " (default 0.3; " +
                      curvature::energyNamesWhere(meanCurvatureOnly, ", ", " and ") +
                      " are nu = 1 models)");
  CLI::Option* threads =
      sub->add_option("--threads", options->threads,
                      "Independent cases run on this many threads (with --scheduler or "
                      "--workers: in each part; default 1 there)")
          ->capture_default_str()
          ->check(inRange(1, maxThreads()));
  sub->add_option("--scheduler", options->scheduler,
                  "Run each energy's part of the study as a case of a Dask sweep on the "
                  "scheduler at this address, in DIR/cases (docs/sweeps.md); the tables equal "
                  "a local run's");
  sub->add_option("--workers", options->workers,
                  "The same on this many local Dask worker processes")
      ->check(CLI::PositiveNumber);
  addSolverArguments(*sub, options->solver);
  sub->add_option("--measure", options->measure,
                  "c1c2 (quadratic reproduction, nonlinear C2, refinement) | modes (the "
                  "vibration spectrum of the square plate against exact or tabulated λ over "
                  "the levels)")
      ->capture_default_str();
  CLI::Option* support =
      sub->add_option("--support", options->support,
                      "--measure modes: simply-supported (exact λ) | clamped (Leissa 1973)")
          ->capture_default_str();
  CLI::Option* count = sub->add_option("--count", options->count, "--measure modes: modes λ1 … λK")
                           ->capture_default_str()
                           ->check(inRange(1, 12));
  files
      ->output("-o,--output", options->outputDir,
               "Output directory (created if missing; a previous study's other files in it are "
               "removed)",
               OutputKind::Directory,
               [](const std::string& name) { return isStudyFile(name) || isSpectrumFile(name); })
      ->required();
  sub->footer(
      "Writes DIR/results.json (every run), DIR/results.csv (one row per solve), DIR/summary.md "
      "(the pass/fail table and the orders; also printed) and log-log plots DIR/*.png.\n"
      "With --measure modes: DIR/spectrum.md (orders and finest errors; also printed), "
      "DIR/spectrum.json, DIR/spectrum.csv and DIR/spectrum_<family>.png.\n"
      "Example: flexure converge --energies midedge,cotan,hinge --families patch48,delaunay "
      "--levels 3 -o study\n"
      "Example: flexure converge --measure modes --support clamped --levels 3 -o spectrum");
  files->onRun(global, [=, &global] {
    // An option of the other measurement is refused rather than ignored.
    const bool modes = options->measure == "modes";
    for (const CLI::Option* other :
         modes ? std::vector<const CLI::Option*>{quadratics, amplitudes, solution}
               : std::vector<const CLI::Option*>{support, count})
      if (other->count() > 0)
        throw InputError(other->get_name() + " applies to --measure " + (modes ? "c1c2" : "modes"));
    options->threadsGiven = threads->count() > 0;
    runConvergeCommand(*options, families->count() > 0, global);
  });
}

}  // namespace flexure::cli
