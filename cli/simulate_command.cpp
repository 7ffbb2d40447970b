// flexure simulate: a plate or shell in time (optimize/dynamics/time_stepping.h) — a bending energy
// and a membrane, lumped masses, gravity, pins, damping — written as frame meshes, an energy
// history and a report.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "cli/bending_arguments.h"
#include "cli/command_files.h"
#include "cli/commands.h"
#include "cli/dynamics_arguments.h"
#include "cli/load_arguments.h"
#include "cli/membrane_arguments.h"
#include "cli/mesh_json.h"
#include "curvature/midedge_boundary.h"
#include "modeling/atomic_write.h"
#include "modeling/errors.h"
#include "modeling/mesh_io.h"
#include "modeling/rest_state.h"
#include "optimize/boundary_conditions.h"
#include "optimize/dynamics/time_stepping.h"
#include "render/mesh_renderer.h"
#include "render/offscreen_context.h"
#include "render/plot.h"

namespace flexure::cli {
namespace {

struct SimulateOptions {
  std::string restFile, initFile, outputDir;
  BendingArguments bending;
  MembraneArguments membrane;
  LoadArguments load;
  std::string pin = "none", integrator = "newmark", pinMotion;
  std::vector<std::string> damping;  // rayleigh:α,β and/or bend:c
  double beta = 0.25, gamma = 0.5, dt = 0.0, duration = 0.0, fps = 30.0, minDt = 0.0;
  std::string renderStyle = "shaded";  // "none": no frame images
  int renderSize = 480;
  double exaggerate = 1.0;  // frames drawn as rest + exaggerate (x − rest)
  std::string video;        // an MP4 of the frame images (ffmpeg); empty: none
};

// Whether ffmpeg can be run (it is looked up on PATH, as a shell would).
bool ffmpegAvailable() {
  return std::system("command -v ffmpeg >/dev/null 2>&1") == 0;
}

std::string readBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

// The frame images as an H.264 MP4 at `fps` frames per second, encoded by ffmpeg in a private
// temporary folder (single-threaded, bit-exact flags and no metadata: the same frames give the
// same bytes) and staged to `video` like every other output. InputError with ffmpeg's own message
// when it fails.
void writeVideo(const std::string& video, const std::vector<std::string>& pngs, double fps) {
  namespace fs = std::filesystem;
  std::string pattern = (fs::temp_directory_path() / "flexure-video.XXXXXX").string();
  if (mkdtemp(pattern.data()) == nullptr)
    throw InputError("--video " + video + ": cannot make a temporary folder for ffmpeg");
  const fs::path scratch(pattern);
  struct Cleanup {
    fs::path path;
    ~Cleanup() {
      std::error_code ec;
      fs::remove_all(path, ec);
    }
  } cleanup{scratch};
  for (size_t k = 0; k < pngs.size(); ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "frame-%05zu.png", k);
    std::ofstream((scratch / name).string(), std::ios::binary) << pngs[k];
  }
  char rate[32];
  std::snprintf(rate, sizeof rate, "%.17g", fps);
  const std::string command =
      "ffmpeg -nostdin -v error -y -framerate " + std::string(rate) + " -i '" +
      (scratch / "frame-%05d.png").string() +
      "' -vf 'pad=ceil(iw/2)*2:ceil(ih/2)*2' -c:v libx264 -pix_fmt yuv420p -threads 1 "
      "-map_metadata -1 -fflags +bitexact -flags:v +bitexact '" +
      (scratch / "video.mp4").string() + "' 2>'" + (scratch / "ffmpeg.log").string() + "'";
  const int status = std::system(command.c_str());
  if (status != 0 || !fs::exists(scratch / "video.mp4"))
    throw InputError("--video " + video + ": ffmpeg failed: " + readBytes(scratch / "ffmpeg.log"));
  modeling::writeFileAtomically(video, readBytes(scratch / "video.mp4"));
}

bool isSimulationFile(const std::string& name) {
  if (name == "energies.csv" || name == "energies.png" || name == "report.json") return true;
  const bool obj = name.size() > 4 && name.compare(name.size() - 4, 4, ".obj") == 0;
  const bool png = name.size() > 4 && name.compare(name.size() - 4, 4, ".png") == 0;
  return name.rfind("frame-", 0) == 0 && (obj || png);
}

// Schedules the removal (at the commit) of the frame images in `frameDir` this run did not write.
void removeStaleFrames(const std::filesystem::path& frameDir,
                       const std::vector<std::string>& kept) {
  std::error_code ec;
  if (!std::filesystem::is_directory(frameDir, ec)) return;
  for (const auto& entry : std::filesystem::directory_iterator(frameDir, ec)) {
    const std::string name = entry.path().filename().string();
    if (!entry.is_regular_file(ec) || !isSimulationFile(name) ||
        std::find(kept.begin(), kept.end(), name) != kept.end())
      continue;
    modeling::removeWhenCommitted(entry.path().string());
  }
}

struct Run {
  int steps = 0, newtonIterations = 0, maxNewtonIterations = 0, halvings = 0;
  double smallestStep = 0.0;
  double seconds = 0.0;  // wall time of the stepping
  std::string failure;   // where a step failed even at the smallest step; empty: completed

  double newtonIterationsPerStep() const { return steps ? double(newtonIterations) / steps : 0.0; }
};

// The time options checked; the smallest step a failing step is halved to.
double checkedMinDt(const SimulateOptions& o) {
  if (!(o.dt > 0.0)) throw InputError("--dt: expected a time step > 0");
  if (!(o.duration >= o.dt)) throw InputError("--duration: expected at least one --dt");
  if (o.duration / o.dt > 1e7) throw InputError("--duration / --dt: more than 10^7 steps");
  if (!(o.fps > 0.0)) throw InputError("--fps: expected a value > 0");
  const double minDt = o.minDt > 0.0 ? o.minDt : o.dt / 64.0;
  if (minDt > o.dt) throw InputError("--min-dt: expected at most --dt");
  return minDt;
}

// --damping rayleigh:α,β and/or bend:c, each at most once.
void parseDamping(const std::vector<std::string>& specs, optimize::DynamicsOptions& dynamics) {
  bool rayleigh = false, bend = false;
  for (const std::string& damping : specs) {
    if (damping.rfind("rayleigh:", 0) == 0 && !rayleigh) {
      const std::vector<double> ab = parseNumbers("--damping", damping.substr(9), 2);
      dynamics.rayleighMass = ab[0];
      dynamics.rayleighStiffness = ab[1];
      rayleigh = true;
    } else if (damping.rfind("bend:", 0) == 0 && !bend) {
      dynamics.bendingDamping = parseNumbers("--damping", damping.substr(5), 1)[0];
      bend = true;
    } else {
      throw InputError("--damping " + damping +
                       ": expected rayleigh:alpha,beta or bend:c (each at most once)");
    }
  }
}

// The integrator, pin motion and damping (the load and obstacles belong to the problem).
optimize::DynamicsOptions dynamicsOptions(const SimulateOptions& o) {
  optimize::DynamicsOptions dynamics;
  dynamics.integrator = parseIntegrator(o.integrator);
  dynamics.beta = o.beta;
  dynamics.gamma = o.gamma;
  if (!o.pinMotion.empty()) {
    if (o.pin == "none")
      throw InputError("--pin-motion " + o.pinMotion +
                       ": moves the pinned vertices; give them with --pin");
    dynamics.pinMotion = parsePinMotion(o.pinMotion);
  }
  parseDamping(o.damping, dynamics);
  dynamics.validate();
  return dynamics;
}

// How the frame images look (none with --render-style none), and the --video checks.
std::optional<render::RenderOptions> frameLook(const SimulateOptions& o) {
  namespace fs = std::filesystem;
  std::optional<render::RenderOptions> look;
  if (o.renderStyle != "none") {
    look.emplace();
    look->style = render::parseRenderStyle(o.renderStyle);
    // Highlight lines alias into moiré at frame sizes on a gently curved sheet; error and
    // curvature need a surface or a field the frames do not have.
    if (look->style == render::RenderStyle::Error ||
        look->style == render::RenderStyle::Curvature ||
        look->style == render::RenderStyle::Highlight)
      throw InputError("--render-style " + o.renderStyle +
                       ": expected shaded, reflection, isophote, displacement or none");
    look->width = look->height = o.renderSize;
    if (look->style == render::RenderStyle::Displacement) look->width += render::kLegendWidth;
    look->azimuthDegrees = 25.0;
    look->elevationDegrees = 30.0;
  }
  if (!o.video.empty()) {
    if (!look)
      throw InputError("--video " + o.video +
                       ": the video is made of the frame images; not with --render-style none");
    const fs::path ext = fs::path(o.video).extension();
    if (ext != ".mp4") throw InputError("--video " + o.video + ": expected a .mp4 file name");
    if (!ffmpegAvailable())
      throw InputError(
          "--video " + o.video +
          ": ffmpeg is not installed (Debian package ffmpeg, which scripts/install-deps "
          "installs); run without --video, or install it");
  }
  return look;
}

modeling::Positions startPositions(const SimulateOptions& o, const modeling::Mesh& restMesh) {
  if (o.initFile.empty()) return restMesh.positions;
  const modeling::Mesh init = modeling::readMesh(o.initFile);
  if (init.vertexCount() != restMesh.vertexCount() || init.triangles != restMesh.triangles)
    throw InputError(o.initFile + ": does not share the connectivity of " + o.restFile +
                     ": --init must be the rest mesh in other positions");
  return init.positions;
}

// What is simulated, before the mesh is read: the bending energy and membrane, every coordinate
// free, the load and the obstacles (each checked here, before any work).
optimize::ProblemOptions bodyOptions(const SimulateOptions& o, const curvature::BendingOptions& b) {
  optimize::ProblemOptions p;
  p.bending = b;
  p.membrane = membraneOptions(o.membrane);
  p.dof = optimize::DofMode::Xyz;
  p.fixedRings = 0;
  p.boundaryNormals = optimize::BoundaryNormals::Free;
  p.load = loadOptions(o.load);
  p.obstacles = obstacleList(o.load);
  p.validate();
  return p;
}

// The simulated body on the rest mesh: the pinned vertices (--pin) at their start positions
// (--init, or rest), and with two rings pinned midedge's boundary ξ held at rest (the clamp).
optimize::Problem simulatedBody(const SimulateOptions& o, optimize::ProblemOptions p,
                                const modeling::Mesh& restMesh) {
  modeling::Stencils stencils = modeling::compileStencils(restMesh);
  modeling::RestState rest = modeling::precomputeRestState(stencils, restMesh.positions);
  p.fixedVertex = o.pin == "none"
                      ? std::vector<bool>(restMesh.vertexCount(), false)
                      : optimize::parseFixedSet("--pin", o.pin, stencils, rest.positions);
  p.boundaryPositions = startPositions(o, restMesh);
  if (curvature::energyEntry(p.bending.discretization).restEdgeUnknowns)
    p.fixedEdge = optimize::clampedBoundaryEdges(o.pin, stencils);
  return optimize::buildProblem(std::move(stencils), std::move(rest), p);
}

// What a run records: the energies after every step (as the CSV text and as rows for the plot),
// the frame meshes, and the smallest distance to an obstacle over the samples.
struct Recording {
  std::vector<std::string> termNames;
  bool contact = false;  // obstacles: a contact column
  std::ostringstream csv;
  std::vector<std::vector<double>> history;  // per sample: time, kinetic, terms…, gravity,
                                             // (contact,) total
  std::vector<std::pair<std::string, modeling::Mesh>> frames;
  std::vector<double> frameTimes;                                     // s, one per frame
  double smallestDistance = std::numeric_limits<double>::infinity();  // to an obstacle

  Recording(const std::vector<const curvature::EnergyTerm*>& terms, bool withContact)
      : contact(withContact) {
    for (const curvature::EnergyTerm* term : terms) termNames.push_back(term->name());
    csv << "time,kinetic";
    for (const std::string& name : termNames) csv << ',' << name;
    csv << ",gravity" << (contact ? ",contact" : "") << ",total\n";
  }

  void sample(const optimize::TimeStepper& stepper) {
    const optimize::EnergySample e = stepper.energies();
    std::vector<double> row = {e.time, e.kinetic};
    row.insert(row.end(), e.terms.begin(), e.terms.end());
    row.push_back(e.gravity);
    if (contact) {
      row.push_back(e.contact);
      smallestDistance =
          std::min(smallestDistance, stepper.barrier().smallestDistance(stepper.positions()));
    }
    row.push_back(e.total());
    char text[40];
    for (size_t k = 0; k < row.size(); ++k) {
      std::snprintf(text, sizeof text, "%.17g", row[k]);
      csv << (k ? "," : "") << text;
    }
    csv << '\n';
    history.push_back(std::move(row));
  }

  void frame(const optimize::TimeStepper& stepper, const modeling::Mesh& restMesh) {
    char name[32];
    std::snprintf(name, sizeof name, "frame-%05zu.obj", frames.size());
    modeling::Mesh m = restMesh;
    m.positions = stepper.positions();
    frames.emplace_back(name, std::move(m));
    frameTimes.push_back(stepper.time());
  }
};

// One step of h, halved (recursively, down to minDt) while Newton fails, counted into `run`;
// false (and run.failure says where) when it fails even at minDt.
bool advance(optimize::TimeStepper& stepper, double h, double minDt, Run& run) {
  const optimize::TimeStepper::Advance a = stepper.advance(h, minDt);
  run.steps += a.steps;
  run.newtonIterations += a.newtonIterations;
  run.maxNewtonIterations = std::max(run.maxNewtonIterations, a.maxNewtonIterations);
  run.halvings += a.halvings;
  run.smallestStep = std::min(run.smallestStep, a.smallestStep);
  if (a.completed) return true;
  char text[160];
  std::snprintf(text, sizeof text, "at t = %.6g: a step of %.3g s failed (%s) and --min-dt %.3g",
                a.failedTime, a.failedStep, a.failure.failure.c_str(), minDt);
  run.failure = std::string(text) + " stops the halving";
  return false;
}

// Steps of --dt to --duration: the energies after every step, a frame every 1/fps of simulated
// time and at the last step, progress on stderr unless quiet.
Run simulate(const SimulateOptions& o, double minDt, bool quiet, optimize::TimeStepper& stepper,
             const modeling::Mesh& restMesh, Recording& recording) {
  Run run;
  run.smallestStep = o.dt;
  const auto clock = std::chrono::steady_clock::now();
  const long steps = std::lround(o.duration / o.dt);
  const double frameInterval = 1.0 / o.fps;
  double nextFrame = frameInterval;
  for (long k = 1; k <= steps && run.failure.empty(); ++k) {
    if (!advance(stepper, o.dt, minDt, run)) break;
    recording.sample(stepper);
    if (stepper.time() >= nextFrame - 1e-9 * o.dt || k == steps) {
      recording.frame(stepper, restMesh);
      while (nextFrame <= stepper.time() + 1e-9 * o.dt) nextFrame += frameInterval;
    }
    if (!quiet && (k % std::max(1L, steps / 20) == 0 || k == steps)) {
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - clock).count();
      std::fprintf(stderr, "flexure simulate: t = %.4g / %.4g s, %.1f steps/s\n", stepper.time(),
                   o.duration, run.steps / std::max(seconds, 1e-9));
    }
  }
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - clock).count();
  return run;
}

nlohmann::json simulationReport(const SimulateOptions& o, const std::string& energyName,
                                const optimize::DynamicsOptions& dynamics,
                                const optimize::Problem& body, const optimize::TimeStepper& stepper,
                                const Run& run, const Recording& recording, int vertexCount) {
  const std::vector<double>& last = recording.history.back();
  nlohmann::json report = {
      {"rest", o.restFile},
      {"energy_name", energyName},
      {"membrane", o.membrane.model},
      {"integrator", optimize::integratorName(dynamics.integrator)},
      {"dt", o.dt},
      {"duration", o.duration},
      {"reached_time", stepper.time()},
      {"completed", run.failure.empty()},
      {"failure", run.failure.empty() ? nlohmann::json(nullptr) : nlohmann::json(run.failure)},
      {"steps", run.steps},
      {"step_halvings", run.halvings},
      {"smallest_step", run.smallestStep},
      {"newton_iterations",
       {{"total", run.newtonIterations},
        {"per_step", run.newtonIterationsPerStep()},
        {"max", run.maxNewtonIterations}}},
      {"seconds", run.seconds},
      {"steps_per_second", run.steps / std::max(run.seconds, 1e-9)},
      {"vertices", vertexCount},
      {"pinned", o.pin},
      {"pin_motion", o.pinMotion.empty() ? nlohmann::json(nullptr) : nlohmann::json(o.pinMotion)},
      {"gravity", {body.gravity.x(), body.gravity.y(), body.gravity.z()}},
      {"density", o.load.density},
      {"damping", o.damping},
      {"frames", recording.frames.size()},
      {"obstacles", o.load.obstacles},
      {"final_energies", {{"kinetic", last[1]}, {"total", last.back()}}}};
  if (recording.contact) {
    report["obstacle_layer"] = stepper.barrier().layer();
    report["smallest_obstacle_distance"] = recording.smallestDistance;
  }
  return report;
}

// The energy history as a plot: each energy against time.
render::LinePlot energyPlot(const Recording& recording, const std::string& title) {
  render::LinePlot plot;
  plot.title = title;
  plot.xLabel = "time";
  plot.yLabel = "energy";
  std::vector<std::string> labels = {"kinetic"};
  labels.insert(labels.end(), recording.termNames.begin(), recording.termNames.end());
  labels.push_back("gravity");
  if (recording.contact) labels.push_back("contact");
  labels.push_back("total");
  for (size_t c = 0; c < labels.size(); ++c) {
    render::PlotSeries series{labels[c], {}, {}};
    for (const auto& row : recording.history) {
      series.x.push_back(row[0]);
      series.y.push_back(row[c + 1]);
    }
    plot.series.push_back(std::move(series));
  }
  return plot;
}

// The obstacles as the renderer draws them.
void addObstacles(const std::vector<optimize::Obstacle>& obstacles, render::RenderOptions& look) {
  for (const optimize::Obstacle& obstacle : obstacles) {
    if (obstacle.kind == optimize::Obstacle::Kind::Sphere)
      look.spheres.push_back({obstacle.vector, obstacle.scalar});
    else if (obstacle.kind == optimize::Obstacle::Kind::Plane)
      look.planes.push_back({obstacle.vector, obstacle.scalar});
  }
}

// The frames rendered with one camera for the whole run, framed on every frame's drawn vertices
// (rest + exaggerate (x − rest)) and the obstacles, with the frame's time and, for the
// displacement style, one colour scale (the largest displacement of the run), in DIR/frames/ (the
// earlier runs' images there that this one did not write go), and the video.
void writeFrameImages(const SimulateOptions& o, render::RenderOptions look,
                      render::OffscreenContext& context, const Recording& recording,
                      const modeling::Mesh& restMesh,
                      const std::vector<optimize::Obstacle>& obstacles,
                      const std::filesystem::path& dir) {
  const auto& frames = recording.frames;
  const modeling::Positions& rest = restMesh.positions;
  const Eigen::Index vertexCount = rest.rows();
  look.referencePositions = rest;
  look.exaggeration = o.exaggerate;
  addObstacles(obstacles, look);
  look.framingPoints.resize(static_cast<Eigen::Index>(frames.size()) * vertexCount, 3);
  double largestDisplacement = 0.0;
  for (size_t f = 0; f < frames.size(); ++f) {
    const modeling::Positions& x = frames[f].second.positions;
    look.framingPoints.middleRows(f * vertexCount, vertexCount) = rest + o.exaggerate * (x - rest);
    largestDisplacement = std::max(largestDisplacement, (x - rest).rowwise().norm().maxCoeff());
  }
  if (look.style == render::RenderStyle::Displacement) {
    look.displacementMax = std::max(largestDisplacement, 1e-12);
    look.rangeNote = "largest of the run";
  }
  const std::filesystem::path frameDir = dir / "frames";
  modeling::createOutputDirectory(frameDir.string());
  std::vector<std::string> pngs, names;
  for (size_t f = 0; f < frames.size(); ++f) {
    const auto& [name, mesh] = frames[f];
    char caption[80];
    if (o.exaggerate != 1.0)
      std::snprintf(caption, sizeof caption, "t = %.3f s, displacement ×%g",
                    recording.frameTimes[f], o.exaggerate);
    else
      std::snprintf(caption, sizeof caption, "t = %.3f s", recording.frameTimes[f]);
    look.caption = caption;
    names.push_back(name.substr(0, name.size() - 4) + ".png");
    pngs.push_back(render::encodePng(render::renderMesh(context, mesh, look)));
    modeling::writeFileAtomically((frameDir / names.back()).string(), pngs.back());
  }
  removeStaleFrames(frameDir, names);
  if (!o.video.empty()) writeVideo(o.video, pngs, o.fps);
}

void runSimulate(const SimulateOptions& o, const GlobalOptions& global) {
  namespace fs = std::filesystem;
  // Every option first, then the inputs; nothing is written before the run ends well.
  const double minDt = checkedMinDt(o);
  if (o.membrane.model.empty())
    throw InputError(
        "simulate moves every coordinate: give a membrane (--membrane stvk|springs|"
        "conformal); bending alone has no stiffness against stretching");
  const optimize::DynamicsOptions dynamics = dynamicsOptions(o);
  const curvature::BendingOptions b = bendingOptions(o.bending);
  const optimize::ProblemOptions bodyBase = bodyOptions(o, b);
  const std::optional<render::RenderOptions> look = frameLook(o);
  // A missing OSMesa fails here, before the simulation.
  std::unique_ptr<render::OffscreenContext> context;
  if (look) context = std::make_unique<render::OffscreenContext>();

  const modeling::Mesh restMesh = modeling::readMesh(o.restFile);
  const optimize::Problem body = simulatedBody(o, bodyBase, restMesh);
  optimize::TimeStepper stepper(body, dynamics);
  const int vertexCount = restMesh.vertexCount();
  stepper.start(body.boundary.start, modeling::Positions::Zero(vertexCount, 3), Eigen::VectorXd());

  Recording recording(body.termPointers(), !body.obstacles.empty());
  recording.sample(stepper);
  recording.frame(stepper, restMesh);
  const Run run = simulate(o, minDt, global.quiet, stepper, restMesh, recording);
  const std::string energyName(curvature::discretizationName(b.discretization));
  const nlohmann::json report =
      simulationReport(o, energyName, dynamics, body, stepper, run, recording, vertexCount);
  const fs::path dir(o.outputDir);
  if (!run.failure.empty()) {
    fs::create_directories(dir);  // the report outlives the failure; the frames do not exist
    writeFailureReport((dir / "report.json").string(), report);
    throw NumericalError("the simulation could not proceed " + run.failure + "; see " +
                         (dir / "report.json").string() + " (try a smaller --dt or --min-dt)");
  }

  const render::LinePlot plot =
      energyPlot(recording, "Energies: " + energyName + " + " + o.membrane.model + ", " +
                                optimize::integratorName(dynamics.integrator));
  modeling::createOutputDirectory(dir.string());
  for (const auto& [name, mesh] : recording.frames)
    modeling::writeMesh((dir / name).string(), mesh);
  if (look)
    writeFrameImages(o, *look, *context, recording, restMesh, body.obstacles.obstacles(), dir);
  else
    removeStaleFrames(dir / "frames", {});
  modeling::writeFileAtomically((dir / "energies.csv").string(), recording.csv.str());
  render::writeLinePlot(plot, (dir / "energies.png").string());
  writeJsonFile((dir / "report.json").string(), report);
  if (!global.quiet) {
    std::fprintf(stderr,
                 "flexure simulate: wrote %zu frames, energies.csv, energies.png and report.json "
                 "to %s (%d steps, %.2f Newton iterations per step, %d halvings, %.1f s)\n",
                 recording.frames.size(), dir.string().c_str(), run.steps,
                 run.newtonIterationsPerStep(), run.halvings, run.seconds);
  }
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
  sub->add_option("--pin", o.pin,
                  "Vertices held in place: none | rings:K (2 clamps) | vertices:FILE")
      ->capture_default_str();
  sub->add_option("--pin-motion", o.pinMotion,
                  "The pinned vertices follow a rigid motion: rotate:ax,ay,az,px,py,pz,omega "
                  "(axis, a point on it, rad/s) | translate:vx,vy,vz (velocity)");
  addLoadArguments(*sub, o.load);
  sub->add_option("--integrator", o.integrator,
                  "newmark (average acceleration: conserves energy) | backward-euler "
                  "(dissipates) | central-difference (explicit)")
      ->capture_default_str();
  sub->add_option("--beta", o.beta, "newmark: β")->capture_default_str();
  sub->add_option("--gamma", o.gamma, "newmark: γ")->capture_default_str();
  sub->add_option("--damping", o.damping,
                  "rayleigh:alpha,beta (C = alpha M + beta K, K the Hessian at rest) and/or "
                  "bend:c (force -c K_bend(x) v: the rate of bending only; repeatable)");
  sub->add_option("--dt", o.dt, "Time step (s)")->required()->check(positive());
  sub->add_option("--duration", o.duration, "Simulated time (s)")->required()->check(positive());
  sub->add_option("--fps", o.fps, "Frames per simulated second")
      ->capture_default_str()
      ->check(positive());
  sub->add_option("--render-style", o.renderStyle,
                  "Each frame also as frames/frame-NNNNN.png, with the obstacles and the time: "
                  "shaded | reflection | isophote | displacement (coloured by the distance from "
                  "the rest mesh) | none")
      ->capture_default_str();
  sub->add_option("--exaggerate", o.exaggerate,
                  "Frame images draw rest + K (x - rest): small motions made visible (the frame "
                  "meshes keep the true positions)")
      ->capture_default_str()
      ->check(positive());
  sub->add_option("--render-size", o.renderSize, "Frame image size in pixels (square)")
      ->capture_default_str()
      ->check(inRange(32, 4096));
  files->output("--video", o.video,
                "An H.264 MP4 of the frame images at --fps (needs ffmpeg, Debian package ffmpeg)");
  sub->add_option("--min-dt", o.minDt,
                  "Smallest step a failing step is halved to (default --dt / 64)")
      ->check(positive());
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
      "DIR/report.json. Exit 3 when a step fails even at --min-dt (the report says where).\n"
      "Example: flexure simulate --rest plate.obj --energy midedge --membrane stvk --pin rings:2 "
      "--gravity 0,0,-9.81 --damping rayleigh:5,0 --dt 0.005 --duration 2 -o droop");
  files->onRun(global, [options, &global] { runSimulate(*options, global); });
}

}  // namespace flexure::cli
