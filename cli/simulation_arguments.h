// flexure simulate's options (internal to cli/): the flags' values, and what they map to — the
// run's spec (optimize::SimulationSpec), the look of the frame images, the simulated body.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cli/bending_arguments.h"
#include "cli/load_arguments.h"
#include "cli/membrane_arguments.h"
#include "cli/plasticity_arguments.h"
#include "modeling/mesh.h"
#include "optimize/dynamics/time_stepping.h"
#include "optimize/inelastic/simulation_spec.h"
#include "render/mesh_renderer.h"

namespace flexure::cli {

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
  double stepTolerance = optimize::DynamicsOptions().stepTolerance;     // ε_v
  int quasiNewtonPairs = optimize::DynamicsOptions().quasiNewtonPairs;  // m; 0: chord steps
  std::string renderStyle = "shaded";                                   // "none": no frame images
  int renderSize = 480;
  double exaggerate = 1.0;  // frames drawn as rest + exaggerate (x − rest)
  std::string video;        // an MP4 of the frame images (ffmpeg); empty: none
  int checkpointEvery = 0;  // steps between checkpoints; 0: none
  std::string resumeDir;    // a checkpoint's output directory to continue from; empty: none
  std::string fingerprint;  // the options that decide the motion, as a checkpoint records them
  double fractureStrain = 0.0, thickness = 0.0;  // ε_f (0: no fracture) and h
  PlasticityArguments plasticity;                // yield values and hardening (no forming)
  std::string selfContact = "on";                // on | off
  double contactOffset = 0.0;                    // d̂; 0: the rule's
  double friction = 0.0;                         // μ on the obstacles; 0: frictionless
};

// How the frame images look (none with --render-style none), and the --video checks.
std::optional<render::RenderOptions> frameLook(const SimulateOptions& o);

// The flags mapped to the run's spec and the spec validated (optimize::SimulationSpec holds the
// rules; their messages name fields, which withFlagNames turns back into these flags).
optimize::SimulationSpec simulationSpec(const SimulateOptions& o);

// The simulated body on the rest mesh: the pinned vertices (--pin) at their start positions
// (--init, or rest), and with two rings pinned midedge's boundary ξ held at rest (the clamp).
// `p` receives the held vertices and start positions (a cut mesh's problem is built from it),
// `dynamics` the pin groups that move or are let go.
optimize::Problem simulatedBody(const SimulateOptions& o, optimize::ProblemOptions& p,
                                optimize::DynamicsOptions& dynamics,
                                const modeling::Mesh& restMesh);

}  // namespace flexure::cli
