// The meshes of a convergence study: the refinement sequences of the generated families (n, 2n,
// … cells per side; delaunay once per seed) and the user's meshes with their mean edge length.
#include "optimize/studies/study_meshes.h"

#include "modeling/generators.h"
#include "modeling/mesh_info.h"

namespace flexure::optimize {

std::vector<StudyMesh> studyMeshes(const StudyOptions& options) {
  std::vector<StudyMesh> meshes;
  for (const modeling::MeshFamily family : options.families) {
    std::vector<std::optional<std::uint64_t>> seeds = {std::nullopt};
    if (family == modeling::MeshFamily::Delaunay)
      seeds.assign(options.seeds.begin(), options.seeds.end());
    for (const auto& seed : seeds) {
      const std::vector<modeling::Mesh> sequence = modeling::refinementSequence(
          {family, options.baseN, seed.value_or(1), {}}, options.levels);
      for (int level = 0; level < options.levels; ++level) {
        StudyMesh m;
        m.family = std::string(modeling::meshFamilyName(family));
        m.seed = seed;
        m.n = options.baseN << level;
        m.level = level;
        m.h = 1.0 / *m.n;
        m.mesh = sequence[level];
        meshes.push_back(std::move(m));
      }
    }
  }
  for (const UserMesh& user : options.userMeshes) {
    StudyMesh m;
    m.family = user.name;
    m.h = modeling::describeMesh(user.mesh).meanEdgeLength;
    m.mesh = user.mesh;
    meshes.push_back(std::move(m));
  }
  return meshes;
}

}  // namespace flexure::optimize
