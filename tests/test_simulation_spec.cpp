// SimulationSpec::validate: every rule of a simulation before its mesh is read, both sides of the
// table (a good spec passes, each bad one is refused naming its fields); TimeSteps' step count and
// default smallest step; renameFields, which the front ends use to name the fields in their words.
#include <gtest/gtest.h>

#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "curvature/energy_registry.h"
#include "modeling/field_names.h"
#include "optimize/inelastic/simulation_spec.h"
#include "support/input_error.h"

namespace flexure {
namespace {

using optimize::SimulationSpec;
using testing::inputErrorOf;

// A hinge + stvk body, Newmark, dt 0.01 for 0.5 s: a spec every rule accepts.
SimulationSpec goodSpec() {
  SimulationSpec s;
  s.body.bending.discretization = curvature::parseDiscretization("hinge");
  s.body.membrane.emplace();
  s.body.dof = optimize::DofMode::Xyz;
  s.body.fixedRings = 0;
  s.body.boundaryNormals = optimize::BoundaryNormals::Free;
  s.steps.dt = 0.01;
  s.steps.duration = 0.5;
  return s;
}

TEST(SimulationSpec, AGoodSpecPasses) {
  EXPECT_EQ(inputErrorOf([] { goodSpec().validate(); }), "(no InputError)");
  SimulationSpec open = goodSpec();
  open.steps = {};  // steps given as the run goes
  EXPECT_EQ(inputErrorOf([&] { open.validate(); }), "(no InputError)");
  SimulationSpec plastic = goodSpec();
  plastic.plasticity.yieldCurvature = 0.1;
  plastic.plasticity.yieldStrain = 0.01;
  plastic.plasticity.hardening = 0.5;
  EXPECT_EQ(inputErrorOf([&] { plastic.validate(); }), "(no InputError)");
  SimulationSpec cracking = goodSpec();
  cracking.fracture.emplace();
  cracking.fracture->fractureStrain = 0.01;
  cracking.dynamics.pinGroups.push_back({{}, {}, 0.5});  // let go at the last step
  EXPECT_EQ(inputErrorOf([&] { cracking.validate(); }), "(no InputError)");
  SimulationSpec both = cracking;  // a cut carries the plastic strains (plastic_dynamics.h)
  both.plasticity = plastic.plasticity;
  EXPECT_EQ(inputErrorOf([&] { both.validate(); }), "(no InputError)");
  SimulationSpec midedge = cracking;  // its ξ re-solved on each cut mesh (fracturing.h)
  midedge.body.bending.discretization = curvature::parseDiscretization("midedge");
  EXPECT_EQ(inputErrorOf([&] { midedge.validate(); }), "(no InputError)");
}

struct BadCase {
  const char* what;
  std::function<void(SimulationSpec&)> change;
  std::vector<std::string> said;  // the message holds each
};

TEST(SimulationSpec, EachBadSpecIsRefusedNamingItsFields) {
  const auto plastic = [](SimulationSpec& s) { s.plasticity.yieldCurvature = 0.1; };
  const auto cracking = [](SimulationSpec& s) {
    s.fracture.emplace();
    s.fracture->fractureStrain = 0.01;
  };
  const std::vector<BadCase> cases = {
      {"no membrane",
       [](SimulationSpec& s) { s.body.membrane.reset(); },
       {"ProblemOptions.membrane", "give a membrane"}},
      {"height mode",
       [](SimulationSpec& s) { s.body.dof = optimize::DofMode::Height; },
       {"ProblemOptions.dof"}},
      {"Newmark beta",
       [](SimulationSpec& s) { s.dynamics.beta = 0.9; },
       {"DynamicsOptions.beta 0.9"}},
      {"hardening alone",
       [](SimulationSpec& s) { s.plasticity.hardening = 0.5; },
       {"PlasticityOptions.hardening", "needs a yield value"}},
      {"cotan yields",
       [&](SimulationSpec& s) {
         plastic(s);
         s.body.bending.discretization = curvature::parseDiscretization("cotan");
       },
       {"PlasticityOptions.yieldCurvature", "cotan", "hinge, triavg, midedge or quadfit"}},
      {"membrane yield without stvk",
       [](SimulationSpec& s) {
         s.plasticity.yieldStrain = 0.01;
         s.body.membrane->model = curvature::MembraneModel::Conformal;
       },
       {"PlasticityOptions.yieldStrain", "ProblemOptions.membrane stvk"}},
      {"plasticity with checkpoints",
       [&](SimulationSpec& s) {
         plastic(s);
         s.checkpointed = true;
       },
       {"not with SimulationSpec.checkpointed"}},
      {"negative thickness",
       [&](SimulationSpec& s) {
         cracking(s);
         s.fracture->thickness = -0.01;
       },
       {"FractureOptions.thickness", "got -0.01"}},
      {"a release after the end",
       [](SimulationSpec& s) {
         s.dynamics.pinGroups.push_back({{}, {}, 5.0});
       },
       {"PinGroup.releaseTime 5: after the run's end (TimeSteps.duration 0.5)"}},
      {"a release with checkpoints",
       [](SimulationSpec& s) {
         s.dynamics.pinGroups.push_back({{}, {}, 0.2});
         s.checkpointed = true;
       },
       {"PinGroup.releaseTime: not with SimulationSpec.checkpointed"}},
      {"a release at 0",
       [](SimulationSpec& s) {
         s.dynamics.pinGroups.push_back({{}, {}, 0.0});
       },
       {"PinGroup.releaseTime 0: expected a time > 0"}},
      {"no step", [](SimulationSpec& s) { s.steps.dt = 0.0; }, {"TimeSteps.dt"}},
      {"a duration between steps",
       [](SimulationSpec& s) { s.steps.duration = 0.015; },
       {"TimeSteps.duration 0.015: not a whole number of steps of 0.01 (1.5); give 0.01 or 0.02"}},
      {"a duration under one step",
       [](SimulationSpec& s) { s.steps.duration = 0.004; },
       {"TimeSteps.duration 0.004", "give 0.01"}},
      {"too many steps", [](SimulationSpec& s) { s.steps.duration = 1e6; }, {"10^7 steps"}},
      {"a smallest step above the step",
       [](SimulationSpec& s) { s.steps.minDt = 0.02; },
       {"TimeSteps.minDt"}},
  };
  for (const BadCase& c : cases) {
    SimulationSpec s = goodSpec();
    c.change(s);
    const std::string message = inputErrorOf([&] { s.validate(); });
    for (const std::string& part : c.said)
      EXPECT_NE(message.find(part), std::string::npos) << c.what << ": " << message;
  }
}

TEST(TimeSteps, CountsStepsAndHalvesTo64th) {
  optimize::TimeSteps steps;
  steps.dt = 0.005;
  steps.duration = 2.0;
  steps.validate();
  EXPECT_EQ(steps.stepCount(), 400);
  EXPECT_DOUBLE_EQ(steps.smallestStep(), 0.005 / 64.0);
  steps.minDt = 0.001;
  EXPECT_DOUBLE_EQ(steps.smallestStep(), 0.001);
  steps.duration = 0.0;  // open-ended
  EXPECT_EQ(steps.stepCount(), 0);
  // 0.3 / 0.1 is 2.9999999999999996 in doubles: still three whole steps.
  steps.dt = 0.1;
  steps.duration = 0.3;
  EXPECT_EQ(inputErrorOf([&] { steps.validate(); }), "(no InputError)");
  EXPECT_EQ(steps.stepCount(), 3);
}

TEST(FieldNames, RenamesWholeFieldsOnly) {
  const std::vector<modeling::FieldName> table = {{"SpectrumStudyOptions.count", "--count"},
                                                  {"StudyOptions.count", "count_of_study"},
                                                  {"TimeSteps.dt", "dt"}};
  EXPECT_EQ(modeling::renameFields("TimeSteps.dt: expected > 0; TimeSteps.dt again", table),
            "dt: expected > 0; dt again");
  EXPECT_EQ(modeling::renameFields("SpectrumStudyOptions.count 13", table), "--count 13");
  EXPECT_EQ(modeling::renameFields("StudyOptions.count 0", table), "count_of_study 0");
  // A longer field that holds a known one is not renamed in part.
  EXPECT_EQ(modeling::renameFields("TimeSteps.dtMax", table), "TimeSteps.dtMax");
  EXPECT_EQ(modeling::renameFields("MyTimeSteps.dt", table), "MyTimeSteps.dt");
}

}  // namespace
}  // namespace flexure
