// Why a Newton loop (newton_loop.h) stopped: a value that callers test, and the words reports
// print for users.
#pragma once

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
  SolverFailure         // another solver's failure (Ceres' own, its report says which)
};

// A short description for reports ("the line search found no decrease").
const char* newtonStopMessage(NewtonStop stop);

}  // namespace flexure::optimize
