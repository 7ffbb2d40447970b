// flexure simulate: a plate or shell in time (optimize/dynamics/time_stepping.h) — a bending energy
// and a membrane, lumped masses, gravity, pins, damping — written as frame meshes, an energy
// history and a report.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "cli/command_files.h"
#include "cli/commands.h"
#include "cli/simulation_arguments.h"
#include "cli/simulation_checkpoints.h"
#include "cli/simulation_outputs.h"
#include "cli/simulation_recording.h"
#include "cli/simulation_reports.h"
#include "modeling/atomic_write.h"
#include "modeling/errors.h"
#include "modeling/mesh_io.h"
#include "optimize/dynamics/time_stepping.h"
#include "optimize/inelastic/fracturing.h"
#include "optimize/inelastic/pin_release.h"
#include "optimize/inelastic/plastic_dynamics.h"
#include "optimize/inelastic/simulation_spec.h"
#include "render/mesh_renderer.h"
#include "render/offscreen_context.h"

namespace flexure::cli {
namespace {

// One step of h, halved (recursively, down to minDt) while Newton fails or to find a fracture
// event, with the fracture checks, split where a pin group is let go, each part followed by the
// plastic update (optimize::advanceReleasingPins), counted into `run`; false (and run.failure says
// where) when it fails even at minDt.
bool advance(optimize::FracturingDynamics& dynamics, optimize::PlasticDynamics* plastic, double h,
             double minDt, Run& run) {
  const optimize::TimeStepper::Advance a =
      optimize::advanceReleasingPins(dynamics, plastic, h, minDt, run.steps);
  run.steps += a.steps;
  run.newtonIterations += a.newtonIterations;
  run.maxNewtonIterations = std::max(run.maxNewtonIterations, a.maxNewtonIterations);
  run.halvings += a.halvings;
  run.smallestStep = std::min(run.smallestStep, a.smallestStep);
  if (a.completed) return true;
  char time[80], step[40];
  std::snprintf(time, sizeof time, "at t = %.6g: a step of %.3g s failed (", a.failedTime,
                a.failedStep);
  std::snprintf(step, sizeof step, ") and --min-dt %.3g", minDt);
  run.failure = time + a.failure.failure + step + " stops the halving";
  return false;
}

// Steps of --dt to --duration: the fracture check and the plastic update after every step, the
// energies after every step, a frame (of the mesh as cut so far) every 1/fps of simulated time and
// at the last step, progress on stderr unless quiet.
Run simulate(const SimulateOptions& o, const optimize::TimeSteps& timeSteps, bool quiet,
             optimize::FracturingDynamics& dynamics, optimize::PlasticDynamics* plastic,
             Recording& recording, Run run, long firstStep, const std::string& meshChecksum) {
  const auto clock = std::chrono::steady_clock::now();
  const long steps = timeSteps.stepCount();
  const double minDt = timeSteps.smallestStep();
  const double frameInterval = 1.0 / o.fps;
  double nextFrame = frameInterval;  // the first frame time after the state's, as the loop has it
  while (nextFrame <= dynamics.stepper().time() + 1e-9 * o.dt) nextFrame += frameInterval;
  for (long k = firstStep + 1; k <= steps && run.failure.empty(); ++k) {
    if (!advance(dynamics, plastic, o.dt, minDt, run)) break;
    optimize::TimeStepper& stepper = dynamics.stepper();
    recording.sample(stepper);
    if (stepper.time() >= nextFrame - 1e-9 * o.dt || k == steps) {
      recording.frame(stepper, dynamics.restMesh());
      if (plastic != nullptr) recording.framePlasticity(*plastic);
      while (nextFrame <= stepper.time() + 1e-9 * o.dt) nextFrame += frameInterval;
    }
    if (o.checkpointEvery > 0 && k % o.checkpointEvery == 0)
      writeCheckpoint(o, stepper, recording, run, k, meshChecksum);
    if (!quiet && (k % std::max(1L, steps / 20) == 0 || k == steps)) {
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - clock).count();
      std::fprintf(stderr, "flexure simulate: t = %.4g / %.4g s, %.1f steps/s\n", stepper.time(),
                   o.duration, run.steps / std::max(seconds, 1e-9));
    }
  }
  // A failure may come after some halves of a step converged: the state reached is kept too.
  const optimize::TimeStepper& stepper = dynamics.stepper();
  if (!run.failure.empty() && stepper.time() > recording.history.back()[0]) {
    recording.sample(stepper);
    recording.frame(stepper, dynamics.restMesh());
    if (plastic != nullptr) recording.framePlasticity(*plastic);
  }
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - clock).count();
  return run;
}

// The option values alone, as runSimulate checks them first (for flexure run's check of every
// step before the first runs: the inputs may not exist yet).
void checkOptionValues(const SimulateOptions& o) {
  simulationSpec(o);
  frameLook(o);
}

void runSimulate(const SimulateOptions& o, const GlobalOptions& global) {
  namespace fs = std::filesystem;
  // Every option first, then the inputs; nothing is written before the run ends well.
  optimize::SimulationSpec spec = simulationSpec(o);
  optimize::DynamicsOptions& dynamics = spec.dynamics;
  optimize::ProblemOptions& bodyBase = spec.body;
  const optimize::PlasticityOptions& plasticity = spec.plasticity;
  const std::optional<render::RenderOptions> look = frameLook(o);
  // A missing OSMesa fails here, before the simulation.
  std::unique_ptr<render::OffscreenContext> context;
  if (look) context = std::make_unique<render::OffscreenContext>();

  const modeling::Mesh restMesh = modeling::readMesh(o.restFile);
  optimize::Problem body = simulatedBody(o, bodyBase, dynamics, restMesh);
  const modeling::Positions startPositions = body.boundary.start;
  optimize::FracturingDynamics fracturing(restMesh, std::move(body), bodyBase, dynamics,
                                          spec.fracture);
  optimize::TimeStepper& stepper = fracturing.stepper();
  const int vertexCount = restMesh.vertexCount();
  fracturing.start(startPositions, modeling::Positions::Zero(vertexCount, 3));
  std::optional<optimize::PlasticDynamics> plastic;
  if (plasticity.enabled()) plastic.emplace(fracturing.problem(), stepper, plasticity);

  Recording recording(fracturing.problem().termPointers(), !fracturing.problem().obstacles.empty(),
                      plastic.has_value());
  recording.sample(stepper);
  recording.frame(stepper, restMesh);
  if (plastic) recording.framePlasticity(*plastic);
  const std::string checksum = meshChecksum(restMesh);
  Run start;
  start.smallestStep = o.dt;
  const long firstStep =
      o.resumeDir.empty() ? 0 : resumeCheckpoint(o, checksum, stepper, recording, start, restMesh);
  const Run run = simulate(o, spec.steps, global.quiet, fracturing, plastic ? &*plastic : nullptr,
                           recording, start, firstStep, checksum);
  const std::string energyName(curvature::discretizationName(bodyBase.bending.discretization));
  nlohmann::json report =
      simulationReport(o, energyName, dynamics, fracturing, run, recording, vertexCount);
  if (plastic) {
    report["plasticity"] = plasticityReport(plasticity, *plastic, recording);
    report["energy_balance"]["plastic_dissipation"] = plastic->dissipation();
  }
  printEnergyBalance(fracturing.stepper(), dynamics.energyTolerance, global.quiet);
  if (plastic && !global.quiet) printPlasticSummary(plasticity, *plastic);
  const fs::path dir(o.outputDir);
  const std::string title = "Energies: " + energyName + " + " + o.membrane.model + ", " +
                            optimize::integratorName(dynamics.integrator);
  const std::string balanceFailure = fracturing.stepper().balanceFailure();
  if (!run.failure.empty() || !balanceFailure.empty()) {
    // The frames computed before the failure are results: written and committed at once (each
    // file atomically), with the report saying the run is partial or its balance's verdict.
    modeling::OutputBatch partial;
    writeOutputs(o, look, context.get(), recording, title, report, fracturing, dir);
    partial.commit();
    const std::string where = "the " + std::to_string(recording.frames.size()) +
                              " frames to t = " + std::to_string(fracturing.stepper().time()) +
                              " are in " + dir.string() + "; see " + (dir / "report.json").string();
    if (!run.failure.empty())
      throw NumericalError("the simulation could not proceed " + run.failure + "; " + where +
                           " (try a smaller --dt or --min-dt)");
    throw NumericalError(balanceFailure + "; " + where + " (try a smaller --dt)");
  }
  writeOutputs(o, look, context.get(), recording, title, report, fracturing, dir);
  if (!global.quiet) {
    std::fprintf(stderr,
                 "flexure simulate: wrote %zu frames, energies.csv, energies.png and report.json "
                 "to %s (%d steps, %.2f Newton iterations per step, %d halvings, %.1f s)\n",
                 recording.frames.size(), dir.string().c_str(), run.steps,
                 run.newtonIterationsPerStep(), run.halvings, run.seconds);
  }
}

// The options that decide the motion, one "name=value" a line as CLI11 writes a configuration:
// every option but the output, the duration, the frame images, --min-dt (it only rescues a
// failing step), --checkpoint and --resume themselves.
std::string motionOptions(const CLI::App& sub) {
  static const std::vector<std::string> free = {
      "output",     "duration",   "min-dt", "render-style", "render-size", "video",
      "exaggerate", "checkpoint", "resume", "quiet",        "verbose",     "force"};
  std::istringstream lines(sub.config_to_str(true, false));
  std::string line, kept;
  while (std::getline(lines, line)) {
    const std::string name = line.substr(0, line.find('='));
    if (std::find(free.begin(), free.end(), name) == free.end()) kept += line + "\n";
  }
  return kept;
}

// Self-contact and friction.
void addContactArguments(CLI::App& sub, SimulateOptions& o) {
  sub.add_option("--self-contact", o.selfContact,
                 "on: every vertex-face and edge-edge pair of the shell closer than "
                 "--contact-offset repels (a log barrier), and no step lets two parts pass "
                 "through each other (continuous collision detection); off: the shell may pass "
                 "through itself")
      ->capture_default_str()
      ->check(CLI::IsMember({"on", "off"}));
  sub.add_option("--contact-offset", o.contactOffset,
                 "Self-contact: the distance below which two parts of the shell repel (default: "
                 "a quarter of the mean rest edge length)");
  sub.add_option(
         "--friction", o.friction,
         "Coulomb friction coefficient mu >= 0 at every contact: the obstacles and the "
         "shell's own (smoothed and lagged per step as in incremental potential contact; 0: "
         "frictionless)")
      ->capture_default_str();
}

// The integrator, its damping and steps, and the step's Newton stop.
void addTimeSteppingArguments(CLI::App& sub, SimulateOptions& o) {
  sub.add_option("--integrator", o.integrator,
                 "newmark (average acceleration: conserves energy) | backward-euler "
                 "(dissipates) | central-difference (explicit)")
      ->capture_default_str();
  sub.add_option("--beta", o.beta, "newmark: β")->capture_default_str();
  sub.add_option("--gamma", o.gamma, "newmark: γ")->capture_default_str();
  sub.add_option("--damping", o.damping,
                 "rayleigh:alpha,beta (C = alpha M + beta K, K the Hessian at rest) and/or "
                 "bend:c (force -c K_bend(x) v: the rate of bending only; repeatable)");
  sub.add_option("--dt", o.dt, "Time step (s)")->required()->check(positive());
  sub.add_option("--duration", o.duration, "Simulated time (s)")->required()->check(positive());
  sub.add_option("--energy-tolerance", o.energyTolerance,
                 "A step after which the total energy (plus the work done against damping) has "
                 "grown by more than this fraction of the peak kinetic energy is halved; a run "
                 "whose balance drifts more exits 3")
      ->capture_default_str()
      ->check(positive());
  sub.add_option("--step-tolerance", o.stepTolerance,
                 "A step's Newton iterations stop when the largest remaining velocity "
                 "correction |dx|max / dt is below this times the rest mesh's bounding-box "
                 "diagonal per second (1e-9: the strict reference)")
      ->capture_default_str();
  sub.add_option(
         "--quasi-newton-pairs", o.quasiNewtonPairs,
         "m > 0: between factorizations a step's iterations are L-BFGS steps on the "
         "kept factor with the last m iterate pairs (0: chord steps on the factor, the strict "
         "reference's)")
      ->capture_default_str();
  sub.add_option("--min-dt", o.minDt,
                 "Smallest step a failing step is halved to (default --dt / 64)")
      ->check(positive());
}

// The frames: their rate, their images and the video.
void addFrameArguments(CLI::App& sub, CommandFiles& files, SimulateOptions& o) {
  sub.add_option("--fps", o.fps, "Frames per simulated second")
      ->capture_default_str()
      ->check(positive());
  sub.add_option("--render-style", o.renderStyle,
                 "Each frame also as frames/frame-NNNNN.png, with the obstacles and the time: "
                 "shaded | reflection | isophote | displacement (coloured by the distance from "
                 "the rest mesh) | plastic (coloured by the plastic strain; with "
                 "--yield-curvature or --yield-strain) | none")
      ->capture_default_str();
  sub.add_option("--exaggerate", o.exaggerate,
                 "Frame images draw rest + K (x - rest): small motions made visible (the frame "
                 "meshes keep the true positions)")
      ->capture_default_str()
      ->check(positive());
  sub.add_option("--render-size", o.renderSize, "Frame image size in pixels (square)")
      ->capture_default_str()
      ->check(inRange(32, 4096));
  files.output("--video", o.video,
               "An H.264 MP4 of the frame images at --fps (needs ffmpeg, Debian package ffmpeg)");
}

// Fracture: the strain a face cracks at and the shell's thickness.
void addFractureArguments(CLI::App& sub, SimulateOptions& o) {
  sub.add_option("--fracture-strain", o.fractureStrain,
                 "Fracture: after each step, a face whose largest principal fibre strain exceeds "
                 "this cracks perpendicular to it (the mesh is cut; DIR/fragment-K.obj at the end)")
      ->check(positive());
  sub.add_option("--thickness", o.thickness,
                 "Fracture: the shell's thickness h, the fibres at +-h/2 (default 0: membrane "
                 "strain alone)");
}

}  // namespace

void registerSimulateCommand(CLI::App& app, const GlobalOptions& global) {
  auto options = std::make_shared<SimulateOptions>();
  SimulateOptions& o = *options;
  CLI::App* sub = app.add_subcommand(
      "simulate", "A plate or shell in time: Newmark, backward Euler or central differences");
  auto files = CommandFiles::of(*sub);
  files->input("--rest", o.restFile, "Rest mesh (a flat plate or a curved shell)")->required();
  files->input("--init", o.initFile,
               "Start positions (the rest mesh's connectivity; default rest)");
  addBendingArguments(*sub, o.bending);
  addMembraneArguments(*sub, o.membrane, "stvk | springs | conformal (required)");
  sub->add_option(
         "--pin", o.pin,
         "Held vertices, repeatable, each group SET or SET@MOTION (MOTION as --pin-motion's, "
         "for that group alone): none | rings:K (2 clamps) | vertices:FILE | "
         "box:X0,X1,Y0,Y1,Z0,Z1")
      ->default_str("none");
  sub->add_option("--pin-motion", o.pinMotion,
                  "The pinned vertices follow a rigid motion: rotate:ax,ay,az,px,py,pz,omega "
                  "(axis, a point on it, rad/s) | translate:vx,vy,vz (velocity)");
  addLoadArguments(*sub, o.load);
  addContactArguments(*sub, o);
  addTimeSteppingArguments(*sub, o);
  addFrameArguments(*sub, *files, o);
  addFractureArguments(*sub, o);
  addYieldArguments(*sub, o.plasticity);
  sub->add_option("--checkpoint", o.checkpointEvery,
                  "Every N steps, DIR/checkpoint.json: the state and the run so far (--resume)")
      ->check(CLI::Range(1, 1 << 30));
  sub->add_option("--resume", o.resumeDir,
                  "Continue from DIR/checkpoint.json, made by a run with the same mesh and options "
                  "(--duration, --min-dt, the output and the frame images may differ)");
  files
      ->output("-o,--output", o.outputDir,
               "Output directory (created if missing; a previous simulation's files in it are "
               "removed)",
               OutputKind::Directory, isSimulationFile)
      ->required();
  sub->footer(
      "Writes DIR/frame-NNNNN.obj (every 1/fps of simulated time) and DIR/frames/frame-NNNNN.png "
      "(rendered with one camera for the whole run; with --video also an MP4 of them), "
      "DIR/energies.csv and "
      "DIR/energies.png (kinetic, each energy term, gravity, total against time) and "
      "DIR/report.json. Exit 3 when a step fails even at --min-dt, or gains more energy than "
      "--energy-tolerance (the report says where; the frames computed before are kept).\n"
      "Example: flexure simulate --rest plate.obj --energy midedge --membrane stvk --pin rings:2 "
      "--gravity 0,0,-9.81 --damping rayleigh:5,0 --dt 0.005 --duration 2 -o droop");
  sub->parse_complete_callback([options, &global] {
    if (global.checkOnly) checkOptionValues(*options);
  });
  files->onRun(global, [options, sub, &global] {
    options->fingerprint = motionOptions(*sub);
    runSimulate(*options, global);
  });
}

}  // namespace flexure::cli
