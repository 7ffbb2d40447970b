// The peak memory of a convergence study, estimated before any mesh is made: per case a base plus
// the registry's bytes per vertex of its energy, the `threads` largest cases at once.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "curvature/energy_registry.h"
#include "optimize/studies/convergence_study.h"

namespace flexure::optimize {

double studyBytesPerVertex(curvature::Discretization discretization) {
  return curvature::energyEntry(discretization).studyBytesPerVertex;
}

StudyMemoryEstimate estimateStudyMemory(const StudyOptions& options) {
  options.validate();
  struct Case {
    double bytes, vertices;
    std::string name;
  };
  std::vector<Case> cases;
  for (const EnergyVariant& v : options.energies) {
    const double perVertex = studyBytesPerVertex(v.bending.discretization);
    const auto add = [&](double vertices, const std::string& mesh) {
      cases.push_back(
          {kStudyCaseBaseBytes + perVertex * vertices, vertices, v.label + " on " + mesh});
    };
    for (const modeling::MeshFamily family : options.families) {
      const double delaunay = family == modeling::MeshFamily::Delaunay ? 1.25 : 1.0;
      const int seeds =
          family == modeling::MeshFamily::Delaunay ? static_cast<int>(options.seeds.size()) : 1;
      for (int level = 0; level < options.levels; ++level) {
        const double n = std::ldexp(static_cast<double>(options.baseN), level);
        for (int s = 0; s < seeds; ++s) {
          char name[96];
          std::snprintf(name, sizeof name, "%s n=%.0f",
                        std::string(modeling::meshFamilyName(family)).c_str(), n);
          add(delaunay * (n + 1.0) * (n + 1.0), name);
        }
      }
    }
    for (const UserMesh& user : options.userMeshes) add(user.mesh.vertexCount(), user.name);
  }
  std::sort(cases.begin(), cases.end(),
            [](const Case& a, const Case& b) { return a.bytes > b.bytes; });
  StudyMemoryEstimate estimate;
  estimate.concurrent = std::max(1, std::min(options.threads, static_cast<int>(cases.size())));
  for (int k = 0; k < estimate.concurrent; ++k) estimate.peakBytes += cases[k].bytes;
  estimate.largestCaseBytes = cases.front().bytes;
  estimate.largestCaseVertices = cases.front().vertices;
  estimate.largestCase = cases.front().name;
  return estimate;
}

}  // namespace flexure::optimize
