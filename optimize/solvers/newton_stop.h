// Why a Newton loop (newton_loop.h) stopped: a value that callers test, and the words reports
// print for users.
#pragma once

#include <functional>

namespace flexure::optimize {

enum class NewtonStop {
  Running,              // not stopped (yet)
  Converged,            // the loop's stop rule holds
  MaxIterations,        // the iteration limit was reached first
  NonFinite,            // the energy, its gradient or a step is not finite (overflow, degenerate)
  NotPositiveDefinite,  // no shift made the Hessian factorable
  NotDescent,           // the Newton step does not descend
  LineSearchFailed,     // no step length decreased the objective
  Infeasible,           // the fixed unknowns put a vertex inside an obstacle
  SolverFailure,        // another solver's failure (Ceres' own, its report says which)
  Stopped               // its IterationObserver asked it to stop (never converged)
};

// Where an iterative solve is, for an observer: the steps accepted so far, the objective and the
// max-norm of its gradient over the free unknowns (Ceres: its 2-norm) at the current iterate.
struct IterationProgress {
  int iteration = 0;
  double energy = 0.0;
  double gradientNorm = 0.0;
};

// Called at every iteration of a solve (a progress display; a request to stop from outside the
// library, such as an interrupt): returning true stops the solve there, reported as
// NewtonStop::Stopped and not converged. Empty: not called.
using IterationObserver = std::function<bool(const IterationProgress&)>;

// A short description for reports ("the line search found no decrease").
const char* newtonStopMessage(NewtonStop stop);

}  // namespace flexure::optimize
