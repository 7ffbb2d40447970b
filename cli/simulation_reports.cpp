// flexure simulate's reports: the energy balance's verdict and numbers, the cracks and fragments,
// the plastic state, the run as a whole in report.json, and their one-line summaries on stderr.
#include "cli/simulation_reports.h"

#include <algorithm>
#include <cstdio>
#include <optional>
#include <vector>

namespace flexure::cli {
namespace {

// Each mesh obstacle: its spec, its size, the file of its rest mesh and its motion.
nlohmann::json meshObstacleReport(const std::vector<optimize::MeshObstacle>& obstacles) {
  nlohmann::json list = nlohmann::json::array();
  for (size_t k = 0; k < obstacles.size(); ++k) {
    const optimize::PinMotion& m = obstacles[k].motion;
    nlohmann::json motion = {{"kind", m.kind == optimize::PinMotion::Kind::Rotate      ? "rotate"
                                      : m.kind == optimize::PinMotion::Kind::Translate ? "translate"
                                                                                       : "none"}};
    if (m.kind == optimize::PinMotion::Kind::Translate)
      motion["velocity"] = {m.velocity.x(), m.velocity.y(), m.velocity.z()};
    if (m.kind == optimize::PinMotion::Kind::Rotate) {
      motion["axis"] = {m.axis.x(), m.axis.y(), m.axis.z()};
      motion["point"] = {m.point.x(), m.point.y(), m.point.z()};
      motion["omega"] = m.omega;
    }
    list.push_back({{"label", obstacles[k].label},
                    {"mesh", "obstacle-" + std::to_string(k) + ".obj"},
                    {"vertices", obstacles[k].mesh.vertexCount()},
                    {"faces", obstacles[k].mesh.faceCount()},
                    {"motion", motion}});
  }
  return list;
}

// The run's energy balance (optimize::TimeStepper::balanceVerdict): balanced, gained, lost or
// driven.
std::string balanceVerdict(const optimize::TimeStepper& stepper) {
  return optimize::balanceVerdictName(stepper.balanceVerdict());
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
          {"verdict", balanceVerdict(stepper)}};
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

}  // namespace

void printEnergyBalance(const optimize::TimeStepper& stepper, double tolerance, bool quiet) {
  const optimize::EnergyBalance& b = stepper.balance();
  const std::string verdict = balanceVerdict(stepper);
  const bool warn = verdict == "gained" || verdict == "lost";
  if (quiet && !warn) return;
  const char* scale = b.scale() == b.peakKinetic ? "the peak kinetic energy" : "the energy scale";
  char tail[160] = "";
  if (verdict == "driven")
    std::snprintf(tail, sizeof tail, "; not checked: the moving pins or mesh obstacles do work");
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

// The self-contact over the run (optimize::TimeStepper::ContactStatistics): its offset, the
// smallest distance between repelling primitives at a step's end (null: none came within the
// offset), the pairs within it per step, and the share of the run's time in collision detection;
// with mesh obstacles their pairs with the shell count too (self_contact: whether the shell's own
// pairs do).
nlohmann::json contactReport(const optimize::TimeStepper& stepper, double seconds) {
  if (stepper.selfContact().empty()) return {{"self_contact", false}};
  const optimize::TimeStepper::ContactStatistics& c = stepper.contactStatistics();
  return {
      {"self_contact", stepper.selfContact().shellPairs()},
      {"offset", stepper.selfContact().layer()},
      {"smallest_distance", std::isfinite(c.smallestDistance) ? nlohmann::json(c.smallestDistance)
                                                              : nlohmann::json(nullptr)},
      {"pairs_per_step",
       {{"mean", c.steps > 0 ? c.pairs / static_cast<double>(c.steps) : 0.0},
        {"peak", c.peakPairs}}},
      {"detection_seconds", c.detectionSeconds},
      {"detection_share", c.detectionSeconds / std::max(seconds, 1e-9)},
      {"pattern_growths", c.patternGrowths}};
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
      {"frame_times", recording.frameTimes},
      {"obstacles", o.load.obstacles},
      {"friction", dynamics.friction},
      {"final_energies", {{"kinetic", last[1]}, {"total", last.back()}}},
      {"energy_balance", energyBalanceReport(stepper, dynamics.energyTolerance)}};
  if (recording.contact) {
    report["obstacle_layer"] = stepper.barrier().layer();
    report["smallest_obstacle_distance"] = recording.smallestDistance;
  }
  report["contact"] = contactReport(stepper, run.seconds);
  if (!stepper.selfContact().meshObstacles().empty())
    report["mesh_obstacles"] = meshObstacleReport(stepper.selfContact().meshObstacles());
  if (fracturing.fractures()) report["fracture"] = fractureReport(o, fracturing);
  const std::string balanceFailure = stepper.balanceFailure();
  if (run.failure.empty() && !balanceFailure.empty()) report["failure"] = balanceFailure;
  return report;
}

}  // namespace flexure::cli
