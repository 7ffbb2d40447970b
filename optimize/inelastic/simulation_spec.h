// What a simulation is, said once for the command and for Python: the body (what is simulated),
// how it moves, the inelastic models and the run's time steps. Plain data; validate() holds every
// rule on one field and between fields, each message naming the fields ("TimeSteps.duration"), so
// that the front ends map their words to fields, and the fields of a message back to their words,
// and hold no rule of their own.
#pragma once

#include <optional>

#include "optimize/dynamics/time_stepping.h"
#include "optimize/inelastic/fracture.h"
#include "optimize/inelastic/plasticity.h"
#include "optimize/problem.h"

namespace flexure::optimize {

// The steps of a run: h, the smallest step a failing one is halved to, and how long it runs.
struct TimeSteps {
  // A failing step is halved at most this many times by default: minDt = dt / kDefaultHalving.
  static constexpr double kDefaultHalving = 64.0;
  // The most steps a run of a given duration may take.
  static constexpr double kMaxSteps = 1e7;

  double dt = 0.0;        // h (s), > 0
  double minDt = 0.0;     // the smallest step (s), in (0, dt]; 0: dt / kDefaultHalving
  double duration = 0.0;  // the simulated time (s), a whole number of steps; 0: open-ended

  // InputError naming the field: dt not positive and finite, minDt negative or above dt, a
  // duration that is not a whole number of steps (within 1e-9 of one) or more than kMaxSteps.
  void validate() const;
  double smallestStep() const { return minDt > 0.0 ? minDt : dt / kDefaultHalving; }
  // duration / dt, rounded (0 for an open-ended run).
  long stepCount() const;
};

struct SimulationSpec {
  // The bending energy, membrane, load and obstacles; every coordinate free (DofMode::Xyz). The
  // held vertices and their clamp come from the pins, on the mesh.
  ProblemOptions body;
  DynamicsOptions dynamics;      // pin groups: their motions and releases (vertices on the mesh)
  PlasticityOptions plasticity;  // no yield value: elastic
  std::optional<FractureOptions> fracture;  // empty: the shell never cracks
  // dt = 0: the steps are given as the run goes (each validated on its own then).
  TimeSteps steps;
  // The run writes or resumes checkpoints, which keep one mesh, its pins and no plastic state.
  bool checkpointed = false;

  // Every rule of a simulation before its mesh is read (InputError naming the fields): the body
  // (a membrane, xyz), the dynamics, the inelastic models' values, plasticity that the energy and
  // membrane can carry (with fracture too: a cut carries it, plastic_dynamics.h), fracture not
  // with an energy that owns edge unknowns, neither with checkpoints, releases within the
  // duration and not with checkpoints.
  void validate() const;
};

}  // namespace flexure::optimize
