// flexure simulate's reports (internal to cli/): report.json (the run, the energy balance, the
// cracks, the plastic state) and the summaries on stderr.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "cli/simulation_arguments.h"
#include "cli/simulation_recording.h"
#include "optimize/dynamics/time_stepping.h"
#include "optimize/inelastic/fracturing.h"
#include "optimize/inelastic/plastic_dynamics.h"

namespace flexure::cli {

// One line on stderr: the balance's largest drift, and a warning when it is beyond the tolerance.
void printEnergyBalance(const optimize::TimeStepper& stepper, double tolerance, bool quiet);

// The plastic state at the end: the yield values (null when not given), the bending elements (their
// kind null without a yield curvature) and membrane faces that carry a plastic strain (how many of
// how many, which), the largest plastic strain of each part (bending as a curvature, membrane as a
// Green strain), the dissipation at each frame.
nlohmann::json plasticityReport(const optimize::PlasticityOptions& options,
                                const optimize::PlasticDynamics& plastic,
                                const Recording& recording);

// "plastic: B of N faces (or edges) yielded, M of F membrane faces yielded, dissipation D" on
// stderr, each part only when its yield value is given.
void printPlasticSummary(const optimize::PlasticityOptions& options,
                         const optimize::PlasticDynamics& plastic);

// report.json: the inputs, how the run went (steps, halvings, Newton iterations, time), the
// final energies and the energy balance, the obstacles' contact and the fracture.
nlohmann::json simulationReport(const SimulateOptions& o, const std::string& energyName,
                                const optimize::DynamicsOptions& dynamics,
                                const optimize::FracturingDynamics& fracturing, const Run& run,
                                const Recording& recording, int vertexCount);

}  // namespace flexure::cli
