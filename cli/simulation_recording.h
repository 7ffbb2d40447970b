// What a run of flexure simulate records (internal to cli/): the stepping's counts, the energies
// after every step (CSV text and plot rows) and the frames.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cstdio>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "curvature/energy_term.h"
#include "modeling/mesh.h"
#include "optimize/dynamics/time_stepping.h"
#include "optimize/inelastic/plastic_dynamics.h"

namespace flexure::cli {

struct Run {
  int steps = 0, newtonIterations = 0, maxNewtonIterations = 0, halvings = 0;
  double smallestStep = 0.0;
  double seconds = 0.0;  // wall time of the stepping
  std::string failure;   // where a step failed even at the smallest step; empty: completed

  double newtonIterationsPerStep() const { return steps ? double(newtonIterations) / steps : 0.0; }
};

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
  // With plasticity, each frame's plastic measure (PlasticDynamics): per vertex, and per face.
  std::vector<Eigen::VectorXd> framePlastic, frameFacePlastic;
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

  // The plastic measure of the frame just recorded.
  void framePlasticity(const optimize::PlasticDynamics& plasticity) {
    framePlastic.push_back(plasticity.vertexPlasticMeasure());
    frameFacePlastic.push_back(plasticity.facePlasticMeasure());
  }
};

}  // namespace flexure::cli
