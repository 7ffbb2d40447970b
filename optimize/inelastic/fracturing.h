// Shell dynamics with fracture (issue #29; Gingold, Secord, Han, Grinspun & Zorin 2004, seed 002):
// after each accepted time step the fracture criterion (fracture.h) is checked on the current state
// and, when a face exceeds ε_f, the shell is cut once (fractureShell) and the motion continues on
// the cut mesh: a Problem built for it with the same ProblemOptions (its held vertices and start
// positions those the cut carries over), and a TimeStepper restarted on it with the time,
// positions, velocities and accelerations carried per vertex (modeling::VertexSource) and the
// energy balance kept. The pin groups still held are carried as the held vertices are (a vertex a
// cut adds on an edge is in a group when both ends of the edge are, a copy when its original is),
// so they stay the same material points and a later release (releasePins) lets go of those.
//
// Energy balance across a cut: the cut keeps each split face's strain (the pieces' rest and
// current positions are interpolated along the same edges, so a constant-strain face stays one),
// and the elastic energy the crack frees turns into motion over the next steps as the sides
// separate, which the integrator conserves. What changes at the cut itself, at a fixed
// configuration, is small: the bending terms of the new edges and hinges, and the lumped masses
// (kinetic and gravity energy) of the vertices near the crack, redistributed with their rest areas.
// That change ΔE = E_before − E_after of the total E = K + Σ E_terms + E_gravity + B is taken out
// of the balance's reference (EnergyBalance::initial and last −= ΔE, reported per crack), so that
// E_b = E + D − S is measured against the energy the cuts left and its drift measures the time
// stepping alone. It is not added to the damping work D: D also budgets the contact stiffening
// (time_stepping.cpp), and a cut's ΔE there let the barrier's raises grow to match it (a sphere
// dropped on a plane and shattering: S = 0.23, the balance −12 % of the peak kinetic energy).
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "modeling/crack_cut.h"
#include "modeling/mesh.h"
#include "optimize/dynamics/time_stepping.h"
#include "optimize/inelastic/fracture.h"
#include "optimize/problem.h"

namespace flexure::optimize {

// One cut: when, where it started and the crack's polyline.
struct CrackEvent {
  double time = 0.0;
  long step = 0;                 // the accepted steps before it
  FacePrincipalStrain critical;  // on the mesh before the cut
  modeling::Positions rest;      // the crack's points in rest coordinates (k by 3)
  modeling::Positions current;   // and where they were at the cut
  double released = 0.0;         // ΔE counted as dissipated
  int fragments = 0;             // connected pieces after the cut
  // Wall-clock seconds of the cut (fractureShell on the criterion's kept rest data) and of what
  // checkFracture rebuilds after it: the Problem for the cut mesh, the TimeStepper (its Hessian
  // pattern, fill-reducing order and CHOLMOD symbolic analysis), its start and the two restores
  // that carry the state and balance over, and the cut mesh's criterion and event faces. The first
  // numerical factorization on the new pattern is made by the next step.
  struct Seconds {
    double cut = 0.0, problem = 0.0, stepper = 0.0, start = 0.0, criterion = 0.0;
    double rebuild() const { return problem + stepper + start + criterion; }
  } seconds;
};

class FracturingDynamics {
 public:
  // `problem` built by buildProblem(rest, options) (its held vertices options.fixedVertex);
  // `fracture` empty: the run never cracks, and the stepper is the one TimeStepper(problem,
  // dynamics) makes. InputError for invalid fracture options, or fracture with a separate membrane
  // rest shape. Midedge's ξ (massless) are re-solved on each cut mesh at the carried positions.
  FracturingDynamics(modeling::Mesh rest, Problem problem, ProblemOptions options,
                     DynamicsOptions dynamics, std::optional<FractureOptions> fracture);

  // As TimeStepper::start; the positions are also the pins' time-0 positions kept across cuts.
  void start(const modeling::Positions& x, const modeling::Positions& v);

  // Advances by h as TimeStepper::advance(h, minStep) does, with the fracture check after each
  // accepted step, searching in time for the fracture event (seed 002, "Resolving fracture
  // events"): a step after which some event face (fractureEventFaces) exceeds ε_f by more than the
  // fraction kFractureOvershoot is discarded and made as two of half its length, at most
  // kFractureSearchLevels halvings deep. So a crack is cut when the strain first reaches ε_f, in
  // the faces that reach it then, and the faces near it relax with respect to the new boundary
  // before any more are checked; overstepping the event instead leaves many faces over ε_f at once,
  // each later step cutting a new crack through them (a strip pulled apart shattered). A face on
  // an earlier crack's lips away from a tip is no event (no crack starts there), so it does not
  // shorten the step. A step that starts over the band (the check after the last step left an
  // event face there: one cut per check) is not tried at all but split at once down to the
  // shortest level, where it is taken: every longer one would end over the band and be discarded
  // (a thin sphere dropped on a floor tried and discarded 4 042 such steps in 100, and now 11,
  // with the same 84 cracks and 10 fragments). Two cheaper
  // rules were tried and are not used: ignoring the faces already over ε_f at the step's start, and
  // resolving only the face the check cuts from; with either, the strip torn under gravity grew
  // its crack in larger cuts and its falling piece cracked again, and with the second a thin
  // sphere dropped on a floor broke into 28 fragments instead of 10 and its balance lost 8 %.
  // `step` counts the accepted steps before this call (CrackEvent::step).
  TimeStepper::Advance advance(double h, double minStep, long step);
  static constexpr int kFractureSearchLevels = 10;  // 1/1024 of the step, seed 002's resolution
  static constexpr double kFractureOvershoot = 0.02;

  // Called at each cut with the cut mesh's problem, its stepper built and not yet started, and the
  // cut (its faceOrigin: the face of the old mesh each new face lies in), before the energies the
  // balance compares across the cut are taken: a state carried per face (the plastic strains,
  // PlasticDynamics::carryAcrossCut) moves the cut problem's rest state there, so that the energy
  // the cut releases is measured with it. Empty: none.
  using CutListener = std::function<void(Problem& cut, const modeling::CrackCut& crack)>;
  void onCut(CutListener listener) { onCut_ = std::move(listener); }

  // The fracture check after an accepted step: at most one cut. True when the shell was cut (the
  // stepper, problem and rest mesh are then the cut ones). A crack along edges already separated
  // (no face split, no vertex added or duplicated) is not a cut.
  bool checkFracture(long step);

  // Lets go of the pin groups whose release time is at most `time` (releasePinGroups; the state's
  // time may differ from theirs by round-off): the problem no longer holds their vertices and a
  // stepper built without them continues the state (TimeStepper::continueAfterRelease). True when
  // a group was released.
  bool releasePins(double time);
  // The earliest release time of the pin groups still held (+∞: none).
  double nextRelease() const { return dynamics_.nextRelease(); }

  TimeStepper& stepper() { return *stepper_; }
  const TimeStepper& stepper() const { return *stepper_; }
  const Problem& problem() const { return *problem_; }
  // Mutable for a plastic update, which moves its terms' rest curvature (plastic_dynamics.h).
  Problem& problem() { return *problem_; }
  const modeling::Mesh& restMesh() const { return rest_; }
  bool fractures() const { return fracture_.has_value(); }
  // The dynamics options the stepper runs with (the pin groups still held, on the current mesh).
  const DynamicsOptions& dynamics() const { return dynamics_; }
  const std::vector<CrackEvent>& cracks() const { return cracks_; }
  // The connected pieces of the current rest mesh, each with its current positions.
  std::vector<modeling::Mesh> fragments() const;

 private:
  // The largest principal fibre strain of each face now (#F).
  std::vector<double> strainNow() const;
  // Some event face's strain over ε_f (1 + kFractureOvershoot).
  bool overBand(const std::vector<double>& strain) const;
  // The check on the strains of the current state.
  bool checkFracture(long step, const std::vector<double>& strain);

  modeling::Mesh rest_;
  ProblemOptions options_;
  DynamicsOptions dynamics_;
  std::optional<FractureOptions> fracture_;
  std::unique_ptr<Problem> problem_;
  std::unique_ptr<TimeStepper> stepper_;
  std::unique_ptr<FractureCriterion> criterion_;  // for rest_, when fracture_
  modeling::Positions pinStart_;                  // the positions at time 0, carried across cuts
  std::vector<CrackEvent> cracks_;
  std::vector<Eigen::Vector3d> openTips_;  // rest points where cracks stop inside the shell
  std::vector<bool> eventFaces_;           // of rest_ and openTips_ (fractureEventFaces)
  CutListener onCut_;
};

}  // namespace flexure::optimize
