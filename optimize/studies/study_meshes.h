// The meshes of a convergence study (internal to optimize/studies/): each level of each generated
// family (and seed), then the user's meshes.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "modeling/mesh.h"
#include "optimize/studies/convergence_study.h"

namespace flexure::optimize {

// One mesh of a study: a level of a generated family (and seed) or a user mesh.
struct StudyMesh {
  std::string family;
  std::optional<std::uint64_t> seed;
  std::optional<int> n;
  int level = 0;
  double h = 0.0;
  modeling::Mesh mesh;

  std::string describe() const {
    std::string s = family;
    if (seed) s += " seed " + std::to_string(*seed);
    if (n) s += " n=" + std::to_string(*n);
    return s;
  }
};

std::vector<StudyMesh> studyMeshes(const StudyOptions& options);

}  // namespace flexure::optimize
