// flexure simulate: a plate or shell in time (optimize/dynamics/time_stepping.h) — a bending energy
// and a membrane, lumped masses, gravity, pins, damping — written as frame meshes, an energy
// history and a report.
#include <algorithm>
#include <cmath>
#include <cstdint>
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
#include "cli/plasticity_arguments.h"
#include "curvature/midedge_boundary.h"
#include "modeling/atomic_write.h"
#include "modeling/errors.h"
#include "modeling/mesh_io.h"
#include "modeling/rest_state.h"
#include "optimize/boundary_conditions.h"
#include "optimize/dynamics/simulation_spec.h"
#include "optimize/dynamics/time_stepping.h"
#include "optimize/inelastic/fracturing.h"
#include "optimize/inelastic/pin_release.h"
#include "optimize/inelastic/plastic_dynamics.h"
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
  std::vector<std::string> pin{"none"};  // SET[@MOTION] per group
  std::string integrator = "newmark", pinMotion;
  std::vector<std::string> damping;  // rayleigh:α,β and/or bend:c
  double beta = 0.25, gamma = 0.5, dt = 0.0, duration = 0.0, fps = 30.0, minDt = 0.0;
  double energyTolerance = optimize::DynamicsOptions().energyTolerance;
  std::string renderStyle = "shaded";  // "none": no frame images
  int renderSize = 480;
  double exaggerate = 1.0;  // frames drawn as rest + exaggerate (x − rest)
  std::string video;        // an MP4 of the frame images (ffmpeg); empty: none
  int checkpointEvery = 0;  // steps between checkpoints; 0: none
  std::string resumeDir;    // a checkpoint's output directory to continue from; empty: none
  std::string fingerprint;  // the options that decide the motion, as a checkpoint records them
  double fractureStrain = 0.0, thickness = 0.0;  // ε_f (0: no fracture) and h
  PlasticityArguments plasticity;                // yield values and hardening (no forming)
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
  return (name.rfind("frame-", 0) == 0 && (obj || png)) || (name.rfind("fragment-", 0) == 0 && obj);
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

// The integrator, the pins' motions and releases (their vertices come with the mesh,
// simulatedBody) and the damping, as the flags give them.
optimize::DynamicsOptions dynamicsOptions(const SimulateOptions& o) {
  optimize::DynamicsOptions dynamics;
  dynamics.integrator = optimize::parseIntegrator(o.integrator);
  dynamics.beta = o.beta;
  dynamics.gamma = o.gamma;
  checkPinSpecs(o.pin, o.pinMotion);
  if (!o.pinMotion.empty()) {
    if (o.pin == std::vector<std::string>{"none"})
      throw InputError("--pin-motion " + o.pinMotion +
                       ": moves the pinned vertices; give them with --pin");
    dynamics.pinMotion = parsePinMotion(o.pinMotion);
  }
  dynamics.pinGroups = pinGroupMotions(o.pin, dynamics.pinMotion);
  parseDamping(o.damping, dynamics);
  dynamics.energyTolerance = o.energyTolerance;
  return dynamics;
}

// How the frame images look (none with --render-style none), and the --video checks.
std::optional<render::RenderOptions> frameLook(const SimulateOptions& o) {
  namespace fs = std::filesystem;
  std::optional<render::RenderOptions> look;
  if (o.renderStyle == "plastic") {
    if (!o.plasticity.enabled())
      throw InputError(
          "--render-style plastic: colours the plastic strain; give --yield-curvature or "
          "--yield-strain");
    look.emplace();
    look->style = render::RenderStyle::Plastic;
    if (o.plasticity.yieldCurvature && o.plasticity.yieldStrain)
      look->plasticLabel = "plastic strain / yield value";
    else if (o.plasticity.yieldStrain)
      look->plasticLabel = "membrane plastic strain (Green)";
  } else if (o.renderStyle != "none") {
    look.emplace();
    look->style = render::parseRenderStyle(o.renderStyle);
    // Highlight lines alias into moiré at frame sizes on a gently curved sheet; error and
    // curvature need a surface or a field the frames do not have.
    if (look->style == render::RenderStyle::Error ||
        look->style == render::RenderStyle::Curvature ||
        look->style == render::RenderStyle::Highlight)
      throw InputError("--render-style " + o.renderStyle +
                       ": expected shaded, reflection, isophote, displacement, plastic or none");
  }
  if (look) {
    look->width = look->height = o.renderSize;
    if (look->style == render::RenderStyle::Displacement ||
        look->style == render::RenderStyle::Plastic)
      look->width += render::kLegendWidth;
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
// free, the load and the obstacles.
optimize::ProblemOptions bodyOptions(const SimulateOptions& o) {
  optimize::ProblemOptions p;
  p.bending = bendingOptions(o.bending);
  if (!o.membrane.model.empty()) p.membrane = membraneOptions(o.membrane);
  p.dof = optimize::DofMode::Xyz;
  p.fixedRings = 0;
  p.boundaryNormals = optimize::BoundaryNormals::Free;
  p.load = loadOptions(o.load);
  p.obstacles = obstacleList(o.load);
  return p;
}

// The flags mapped to the run's spec and the spec validated (optimize::SimulationSpec holds the
// rules; their messages name fields, which withFlagNames turns back into these flags).
optimize::SimulationSpec simulationSpec(const SimulateOptions& o) {
  if (!(o.fps > 0.0)) throw InputError("--fps: expected a value > 0");
  optimize::SimulationSpec spec;
  spec.body = bodyOptions(o);
  spec.dynamics = dynamicsOptions(o);
  spec.plasticity.yieldCurvature = o.plasticity.yieldCurvature;
  spec.plasticity.yieldStrain = o.plasticity.yieldStrain;
  spec.plasticity.hardening = o.plasticity.hardening;
  if (o.fractureStrain != 0.0) {
    spec.fracture.emplace();
    spec.fracture->fractureStrain = o.fractureStrain;
    spec.fracture->thickness = o.thickness;
  } else if (o.thickness != 0.0) {
    throw InputError("--thickness: the fibres of the fracture criterion; give --fracture-strain");
  }
  spec.steps.dt = o.dt;
  spec.steps.minDt = o.minDt;
  spec.steps.duration = o.duration;
  spec.checkpointed = o.checkpointEvery > 0 || !o.resumeDir.empty();
  spec.validate();
  return spec;
}

// The simulated body on the rest mesh: the pinned vertices (--pin) at their start positions
// (--init, or rest), and with two rings pinned midedge's boundary ξ held at rest (the clamp).
// `p` receives the held vertices and start positions (a cut mesh's problem is built from it),
// `dynamics` the pin groups that move or are let go.
optimize::Problem simulatedBody(const SimulateOptions& o, optimize::ProblemOptions& p,
                                optimize::DynamicsOptions& dynamics,
                                const modeling::Mesh& restMesh) {
  modeling::Stencils stencils = modeling::compileStencils(restMesh);
  modeling::RestState rest = modeling::precomputeRestState(stencils, restMesh.positions);
  PinnedGroups pinned = pinnedGroups(o.pin, stencils, rest.positions, dynamics.pinGroups);
  p.fixedVertex = std::move(pinned.held);
  p.boundaryPositions = startPositions(o, restMesh);
  if (curvature::energyEntry(p.bending.discretization).restEdgeUnknowns)
    p.fixedEdge = std::move(pinned.clampedEdges);
  return optimize::buildProblem(std::move(stencils), std::move(rest), p);
}

// What a run records: the energies after every step (as the CSV text and as rows for the plot),
// the frame meshes, and the smallest distance to an obstacle over the samples.
struct Recording {
  std::vector<std::string> termNames;
  bool contact = false;  // obstacles: a contact column
  bool plastic = false;  // plasticity: a plastic_dissipation column
  std::ostringstream csv;
  std::vector<std::vector<double>> history;  // per sample: time, kinetic, terms…, gravity,
                                             // (contact,) (plastic dissipation,) total
  std::vector<std::pair<std::string, modeling::Mesh>> frames;
  std::vector<double> frameTimes;              // s, one per frame
  std::vector<modeling::Positions> frameRest;  // each frame's rest positions (a cut changes them)
  std::vector<double> frameDissipation;        // the plastic dissipation at each frame
  std::vector<Eigen::VectorXd> framePlastic;   // with plasticity: each frame's vertex strains
  double smallestDistance = std::numeric_limits<double>::infinity();  // to an obstacle

  Recording(const std::vector<const curvature::EnergyTerm*>& terms, bool withContact,
            bool withPlasticity)
      : contact(withContact), plastic(withPlasticity) {
    for (const curvature::EnergyTerm* term : terms) termNames.push_back(term->name());
    csv << "time,kinetic";
    for (const std::string& name : termNames) csv << ',' << name;
    csv << ",gravity" << (contact ? ",contact" : "") << (plastic ? ",plastic_dissipation" : "")
        << ",total\n";
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
    if (plastic) row.push_back(stepper.balance().plastic);
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
    frameRest.push_back(restMesh.positions);
    frameDissipation.push_back(stepper.balance().plastic);
  }
};

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
  char text[160];
  std::snprintf(text, sizeof text, "at t = %.6g: a step of %.3g s failed (%s) and --min-dt %.3g",
                a.failedTime, a.failedStep, a.failure.failure.c_str(), minDt);
  run.failure = std::string(text) + " stops the halving";
  return false;
}

// FNV-1a (64 bits) of the rest mesh's OBJ text: a checkpoint is resumed on the same mesh only.
std::string meshChecksum(const modeling::Mesh& mesh) {
  std::uint64_t hash = 14695981039346656037ull;
  for (const unsigned char c : modeling::formatMesh(mesh, modeling::MeshFormat::Obj))
    hash = (hash ^ c) * 1099511628211ull;
  char text[20];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

nlohmann::json matrixJson(const Eigen::MatrixXd& m) {
  return std::vector<double>(m.data(), m.data() + m.size());
}

Eigen::MatrixXd matrixFrom(const nlohmann::json& j, Eigen::Index rows, Eigen::Index cols) {
  const std::vector<double> values = j.get<std::vector<double>>();
  if (static_cast<Eigen::Index>(values.size()) != rows * cols)
    throw InputError("expected " + std::to_string(rows * cols) + " numbers");
  return Eigen::Map<const Eigen::MatrixXd>(values.data(), rows, cols);
}

// DIR/checkpoint.json after step k, written at once (atomically, outside the run's output batch,
// so that it outlives a kill or a failure): the stepper's state (time_stepping.h State), the run's
// counts and the recording so far, with the options and the mesh it was made with. The stepper
// drops its kept factor, so that the run continues as a resumed one does.
void writeCheckpoint(const SimulateOptions& o, optimize::TimeStepper& stepper,
                     const Recording& recording, const Run& run, long k,
                     const std::string& checksum) {
  stepper.forgetFactor();
  const optimize::TimeStepper::State st = stepper.state();
  const optimize::EnergyBalance& b = st.balance;
  nlohmann::json frames = nlohmann::json::array();
  for (const auto& frame : recording.frames) frames.push_back(matrixJson(frame.second.positions));
  const nlohmann::json checkpoint = {
      {"flexure_checkpoint", 1},
      {"options", o.fingerprint},
      {"mesh", checksum},
      {"step", k},
      {"time", st.time},
      {"x", matrixJson(st.x)},
      {"v", matrixJson(st.v)},
      {"a", matrixJson(st.a)},
      {"xi", matrixJson(st.xi)},
      {"contact_stiffness", matrixJson(st.contactStiffness)},
      {"balance",
       {b.initial, b.dissipated, b.stiffening, b.peakKinetic, b.peakElastic, b.last, b.largestDrift,
        b.driftTime, static_cast<double>(b.driftStep), static_cast<double>(b.steps)}},
      {"run",
       {run.steps, run.newtonIterations, run.maxNewtonIterations, run.halvings, run.smallestStep}},
      {"csv", recording.csv.str()},
      {"history", recording.history},
      {"frames", frames},
      {"frame_times", recording.frameTimes},
      {"smallest_distance", std::isfinite(recording.smallestDistance)
                                ? nlohmann::json(recording.smallestDistance)
                                : nlohmann::json(nullptr)}};
  std::filesystem::create_directories(o.outputDir);
  modeling::writeFileNow((std::filesystem::path(o.outputDir) / "checkpoint.json").string(),
                         checkpoint.dump());
}

// Continues from --resume DIR's checkpoint: the stepper's state, the run's counts and the
// recording; the step it was written after. InputError (exit 2) when it is missing, unreadable,
// or made with other options or another mesh.
long resumeCheckpoint(const SimulateOptions& o, const std::string& checksum,
                      optimize::TimeStepper& stepper, Recording& recording, Run& run,
                      const modeling::Mesh& restMesh) {
  const std::string path = (std::filesystem::path(o.resumeDir) / "checkpoint.json").string();
  const std::string where = "--resume " + o.resumeDir + ": " + path;
  std::ifstream in(path);
  if (!in) throw InputError(where + ": no checkpoint (write one with --checkpoint N)");
  try {
    const nlohmann::json c = nlohmann::json::parse(in);
    if (c.at("flexure_checkpoint") != 1) throw InputError("not a checkpoint of this version");
    if (c.at("mesh") != checksum)
      throw InputError("was made with another rest mesh than " + o.restFile);
    if (c.at("options") != o.fingerprint)
      throw InputError("was made with other options: " + c.at("options").get<std::string>());
    const Eigen::Index n = restMesh.vertexCount();
    optimize::TimeStepper::State st;
    st.time = c.at("time");
    st.x = matrixFrom(c.at("x"), n, 3);
    st.v = matrixFrom(c.at("v"), n, 3);
    st.a = matrixFrom(c.at("a"), n, 3);
    st.xi = matrixFrom(c.at("xi"), c.at("xi").size(), 1);
    st.contactStiffness =
        matrixFrom(c.at("contact_stiffness"), c.at("contact_stiffness").size(), 1);
    const std::vector<double> b = c.at("balance").get<std::vector<double>>();
    if (b.size() != 10) throw InputError("expected 10 balance numbers");
    st.balance = {
        b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7], std::lround(b[8]), std::lround(b[9])};
    stepper.restore(st);
    const nlohmann::json& r = c.at("run");
    run.steps = r.at(0);
    run.newtonIterations = r.at(1);
    run.maxNewtonIterations = r.at(2);
    run.halvings = r.at(3);
    run.smallestStep = r.at(4);
    recording.csv.str(c.at("csv").get<std::string>());
    recording.csv.seekp(0, std::ios::end);
    recording.history = c.at("history").get<std::vector<std::vector<double>>>();
    recording.frames.clear();
    recording.frameRest.clear();
    for (const auto& frame : c.at("frames")) {
      char name[32];
      std::snprintf(name, sizeof name, "frame-%05zu.obj", recording.frames.size());
      modeling::Mesh m = restMesh;
      m.positions = matrixFrom(frame, n, 3);
      recording.frames.emplace_back(name, std::move(m));
      recording.frameRest.push_back(restMesh.positions);
    }
    recording.frameTimes = c.at("frame_times").get<std::vector<double>>();
    if (!c.at("smallest_distance").is_null())
      recording.smallestDistance = c.at("smallest_distance");
    return c.at("step");
  } catch (const nlohmann::json::exception& e) {
    throw InputError(where + ": not a readable checkpoint: " + e.what());
  } catch (const InputError& e) {
    throw InputError(where + ": " + e.what());
  }
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
      if (plastic != nullptr) recording.framePlastic.push_back(plastic->vertexPlasticMeasure());
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
    if (plastic != nullptr) recording.framePlastic.push_back(plastic->vertexPlasticMeasure());
  }
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - clock).count();
  return run;
}

// The run's energy balance (optimize::EnergyBalance): "balanced" when its largest drift is within
// the tolerance (or round-off), "gained" or "lost" beyond it, "driven" when moving pins do work
// (not checked).
std::string balanceVerdict(const optimize::TimeStepper& stepper, double tolerance) {
  const optimize::EnergyBalance& b = stepper.balance();
  if (!stepper.balanceChecked()) return "driven";
  if (b.balancedWithin(tolerance)) return "balanced";
  return b.largestDrift > 0.0 ? "gained" : "lost";
}

nlohmann::json energyBalanceReport(const optimize::TimeStepper& stepper, double tolerance) {
  const optimize::EnergyBalance& b = stepper.balance();
  return {{"largest_drift", b.largestDrift},
          {"relative_drift", b.relativeDrift()},
          {"time", b.driftTime},
          {"step", b.driftStep},
          {"scale", b.scale()},
          {"peak_kinetic", b.peakKinetic},
          {"initial_total", b.initial},
          {"dissipated", b.dissipated},
          {"contact_stiffening", b.stiffening},
          {"pin_work", b.pinWork},
          {"roundoff", b.roundoff},
          {"tolerance", tolerance},
          {"verdict", balanceVerdict(stepper, tolerance)}};
}

// One line on stderr: the balance's largest drift, and a warning when it is beyond the tolerance.
void printEnergyBalance(const optimize::TimeStepper& stepper, double tolerance, bool quiet) {
  const optimize::EnergyBalance& b = stepper.balance();
  const std::string verdict = balanceVerdict(stepper, tolerance);
  const bool warn = verdict == "gained" || verdict == "lost";
  if (quiet && !warn) return;
  const char* scale = b.scale() == b.peakKinetic ? "the peak kinetic energy" : "the energy scale";
  char tail[160] = "";
  if (verdict == "driven")
    std::snprintf(tail, sizeof tail, "; not checked: the moving pins do work");
  else if (b.relativeDrift() > tolerance && !warn)
    std::snprintf(tail, sizeof tail, "; round-off: below 1e-12 M (L/dt)^2 = %.3g", b.roundoff);
  else if (warn)
    std::snprintf(tail, sizeof tail,
                  "; beyond --energy-tolerance %g: a smaller --dt follows the motion more closely",
                  tolerance);
  std::fprintf(stderr,
               "flexure simulate: %senergy balance: the total (with the work done against "
               "damping) drifted by %.3g, %.3g %% of %s %.3g, at t = %.4g (step %ld)%s\n",
               warn ? "warning: " : "", b.largestDrift, 100.0 * b.relativeDrift(), scale, b.scale(),
               b.driftTime, b.driftStep, tail);
}

// The cracks (time, step, the face and strain they started from, the polyline in rest coordinates
// and where it was, the energy the cut released, the seconds of the cut and of the rebuild after
// it) and the fragments at the end.
nlohmann::json fractureReport(const SimulateOptions& o,
                              const optimize::FracturingDynamics& fracturing) {
  nlohmann::json cracks = nlohmann::json::array();
  double released = 0.0, rebuild = 0.0;
  for (const optimize::CrackEvent& c : fracturing.cracks()) {
    nlohmann::json rest = nlohmann::json::array(), current = nlohmann::json::array();
    for (Eigen::Index k = 0; k < c.rest.rows(); ++k) {
      rest.push_back({c.rest(k, 0), c.rest(k, 1), c.rest(k, 2)});
      current.push_back({c.current(k, 0), c.current(k, 1), c.current(k, 2)});
    }
    cracks.push_back({{"time", c.time},
                      {"step", c.step},
                      {"face", c.critical.face},
                      {"strain", c.critical.strain},
                      {"fibre", c.critical.fibre},
                      {"polyline_rest", rest},
                      {"polyline_current", current},
                      {"released_energy", c.released},
                      {"fragments", c.fragments},
                      {"cut_seconds", c.seconds.cut},
                      {"rebuild_seconds", c.seconds.rebuild()},
                      {"rebuild_parts_seconds",
                       {{"problem", c.seconds.problem},
                        {"stepper", c.seconds.stepper},
                        {"start", c.seconds.start},
                        {"criterion", c.seconds.criterion}}}});
    released += c.released;
    rebuild += c.seconds.rebuild();
  }
  return {{"fracture_strain", o.fractureStrain},
          {"thickness", o.thickness},
          {"cracks", cracks},
          {"released_energy", released},
          {"rebuild_seconds", rebuild},
          {"fragments", fracturing.fragments().size()},
          {"vertices", fracturing.restMesh().vertexCount()},
          {"faces", fracturing.restMesh().faceCount()}};
}

// The plastic state at the end: the yield values (null when not given), the bending elements (their
// kind null without a yield curvature) and membrane faces that carry a plastic strain (how many of
// how many, which), the largest plastic strain of each part (bending as a curvature, membrane as a
// Green strain), the dissipation at each frame.
nlohmann::json plasticityReport(const optimize::PlasticityOptions& options,
                                const optimize::PlasticDynamics& plastic,
                                const Recording& recording) {
  const auto valueOrNull = [](const std::optional<double>& v) {
    return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
  };
  const auto largest = [](const Eigen::VectorXd& v) { return v.size() > 0 ? v.maxCoeff() : 0.0; };
  const std::vector<int> yielded = plastic.yieldedElements();
  const std::vector<int> yieldedFaces = plastic.yieldedFaces();
  return {{"yield_curvature", valueOrNull(options.yieldCurvature)},
          {"yield_strain", valueOrNull(options.yieldStrain)},
          {"hardening", options.hardening},
          {"element", options.yieldCurvature ? nlohmann::json(plastic.elementKind())
                                             : nlohmann::json(nullptr)},
          {"elements", plastic.elementCount()},
          {"yielded_elements", yielded.size()},
          {"yielded", yielded},
          {"largest_plastic_curvature",
           largest(optimize::equivalentPlasticCurvatures(plastic.state()))},
          {"membrane_faces", plastic.membraneFaceCount()},
          {"yielded_membrane_faces", yieldedFaces.size()},
          {"yielded_faces", yieldedFaces},
          {"largest_plastic_strain", largest(optimize::equivalentPlasticStrains(plastic.state()))},
          {"plastic_dissipation", plastic.dissipation()},
          {"dissipation_history",
           {{"time", recording.frameTimes}, {"plastic_dissipation", recording.frameDissipation}}}};
}

// "plastic: B of N faces (or edges) yielded, M of F membrane faces yielded, dissipation D" on
// stderr, each part only when its yield value is given.
void printPlasticSummary(const optimize::PlasticityOptions& options,
                         const optimize::PlasticDynamics& plastic) {
  std::string parts;
  char text[120];
  if (options.yieldCurvature) {
    std::snprintf(text, sizeof text, "%zu of %d %ss yielded", plastic.yieldedElements().size(),
                  plastic.elementCount(), plastic.elementKind().c_str());
    parts += text;
  }
  if (options.yieldStrain) {
    std::snprintf(text, sizeof text, "%s%zu of %d membrane faces yielded",
                  parts.empty() ? "" : ", ", plastic.yieldedFaces().size(),
                  plastic.membraneFaceCount());
    parts += text;
  }
  std::fprintf(stderr, "flexure simulate: plastic: %s, dissipation %.6g\n", parts.c_str(),
               plastic.dissipation());
}

nlohmann::json simulationReport(const SimulateOptions& o, const std::string& energyName,
                                const optimize::DynamicsOptions& dynamics,
                                const optimize::FracturingDynamics& fracturing, const Run& run,
                                const Recording& recording, int vertexCount) {
  const optimize::Problem& body = fracturing.problem();
  const optimize::TimeStepper& stepper = fracturing.stepper();
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
      {"partial", !run.failure.empty()},
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
      {"pinned", o.pin.size() == 1 ? nlohmann::json(o.pin[0]) : nlohmann::json(o.pin)},
      {"pin_motion", o.pinMotion.empty() ? nlohmann::json(nullptr) : nlohmann::json(o.pinMotion)},
      {"gravity", {body.gravity.x(), body.gravity.y(), body.gravity.z()}},
      {"density", o.load.density},
      {"damping", o.damping},
      {"frames", recording.frames.size()},
      {"obstacles", o.load.obstacles},
      {"final_energies", {{"kinetic", last[1]}, {"total", last.back()}}},
      {"energy_balance", energyBalanceReport(stepper, dynamics.energyTolerance)}};
  if (recording.contact) {
    report["obstacle_layer"] = stepper.barrier().layer();
    report["smallest_obstacle_distance"] = recording.smallestDistance;
  }
  if (fracturing.fractures()) report["fracture"] = fractureReport(o, fracturing);
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
  if (recording.plastic) labels.push_back("plastic dissipation");
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
// displacement style, one colour scale (the largest displacement of the run), with `cracks` the
// lips each frame's cuts opened drawn over it, in DIR/frames/ (the earlier runs' images there that
// this one did not write go), and the video.
void writeFrameImages(const SimulateOptions& o, render::RenderOptions look,
                      render::OffscreenContext& context, const Recording& recording,
                      const std::vector<optimize::Obstacle>& obstacles, bool cracks,
                      const std::filesystem::path& dir) {
  const auto& frames = recording.frames;
  look.exaggeration = o.exaggerate;
  addObstacles(obstacles, look);
  Eigen::Index pointCount = 0;
  for (const modeling::Positions& rest : recording.frameRest) pointCount += rest.rows();
  look.framingPoints.resize(pointCount, 3);
  double largestDisplacement = 0.0;
  Eigen::Index first = 0;
  for (size_t f = 0; f < frames.size(); ++f) {
    const modeling::Positions& x = frames[f].second.positions;
    const modeling::Positions& rest = recording.frameRest[f];
    look.framingPoints.middleRows(first, rest.rows()) = rest + o.exaggerate * (x - rest);
    first += rest.rows();
    largestDisplacement = std::max(largestDisplacement, (x - rest).rowwise().norm().maxCoeff());
  }
  if (look.style == render::RenderStyle::Plastic) {
    double largest = 0.0;
    for (const Eigen::VectorXd& strain : recording.framePlastic)
      largest = std::max(largest, strain.maxCoeff());
    look.plasticMax = std::max(largest, 1e-12);
    look.rangeNote = "largest of the run";
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
    look.referencePositions = recording.frameRest[f];
    if (cracks) look.crackEdges = render::crackLipEdges(recording.frameRest[f], mesh.triangles);
    if (look.style == render::RenderStyle::Plastic) {
      const Eigen::VectorXd& strain = recording.framePlastic[f];
      look.vertexScalars.assign(strain.data(), strain.data() + strain.size());
    }
    names.push_back(name.substr(0, name.size() - 4) + ".png");
    pngs.push_back(render::encodePng(render::renderMesh(context, mesh, look)));
    modeling::writeFileAtomically((frameDir / names.back()).string(), pngs.back());
  }
  removeStaleFrames(frameDir, names);
  if (!o.video.empty()) writeVideo(o.video, pngs, o.fps);
}

// The frame meshes, their images (with `look`), energies.csv, energies.png and report.json in
// `dir`; the files of an earlier run there that this one did not write go at the commit.
void writeOutputs(const SimulateOptions& o, const std::optional<render::RenderOptions>& look,
                  render::OffscreenContext* context, const Recording& recording,
                  const std::string& title, const nlohmann::json& report,
                  const optimize::FracturingDynamics& dynamics, const std::filesystem::path& dir) {
  const render::LinePlot plot = energyPlot(recording, title);
  modeling::createOutputDirectory(dir.string());
  std::vector<std::string> written = {"energies.csv", "energies.png", "report.json"};
  for (const auto& [name, mesh] : recording.frames) {
    modeling::writeMesh((dir / name).string(), mesh);
    written.push_back(name);
  }
  if (dynamics.fractures()) {
    const std::vector<modeling::Mesh> fragments = dynamics.fragments();
    for (size_t k = 0; k < fragments.size(); ++k) {
      const std::string name = "fragment-" + std::to_string(k) + ".obj";
      modeling::writeMesh((dir / name).string(), fragments[k]);
      written.push_back(name);
    }
  }
  removeStaleFrames(dir, written);
  if (look)
    writeFrameImages(o, *look, *context, recording, dynamics.problem().obstacles.obstacles(),
                     dynamics.fractures(), dir);
  else
    removeStaleFrames(dir / "frames", {});
  modeling::writeFileAtomically((dir / "energies.csv").string(), recording.csv.str());
  render::writeLinePlot(plot, (dir / "energies.png").string());
  writeJsonFile((dir / "report.json").string(), report);
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
  if (plastic) recording.framePlastic.push_back(plastic->vertexPlasticMeasure());
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
  if (!run.failure.empty()) {
    // The frames computed before the failure are results: written and committed at once (each
    // file atomically), with the report saying the run is partial.
    modeling::OutputBatch partial;
    writeOutputs(o, look, context.get(), recording, title, report, fracturing, dir);
    partial.commit();
    throw NumericalError("the simulation could not proceed " + run.failure + "; the " +
                         std::to_string(recording.frames.size()) +
                         " frames to t = " + std::to_string(fracturing.stepper().time()) +
                         " are in " + dir.string() + "; see " + (dir / "report.json").string() +
                         " (try a smaller --dt or --min-dt)");
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
                  "the rest mesh) | plastic (coloured by the plastic strain; with "
                  "--yield-curvature or --yield-strain) | none")
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
  sub->add_option("--energy-tolerance", o.energyTolerance,
                  "A step after which the total energy (plus the work done against damping) has "
                  "grown by more than this fraction of the peak kinetic energy is halved; a run "
                  "whose balance drifts more is warned about")
      ->capture_default_str()
      ->check(positive());
  sub->add_option(
         "--fracture-strain", o.fractureStrain,
         "Fracture: after each step, a face whose largest principal fibre strain exceeds "
         "this cracks perpendicular to it (the mesh is cut; DIR/fragment-K.obj at the end)")
      ->check(positive());
  sub->add_option("--thickness", o.thickness,
                  "Fracture: the shell's thickness h, the fibres at +-h/2 (default 0: membrane "
                  "strain alone)");
  addYieldArguments(*sub, o.plasticity);
  sub->add_option("--checkpoint", o.checkpointEvery,
                  "Every N steps, DIR/checkpoint.json: the state and the run so far (--resume)")
      ->check(CLI::Range(1, 1 << 30));
  sub->add_option("--resume", o.resumeDir,
                  "Continue from DIR/checkpoint.json, made by a run with the same mesh and options "
                  "(--duration, --min-dt, the output and the frame images may differ)");
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
