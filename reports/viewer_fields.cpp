#include "reports/viewer_fields.h"

#include "modeling/errors.h"

namespace flexure::reports {

void addMeanCurvatureFields(render::ViewerPageSpec& page, const curvature::EnergyEntry& energy) {
  page.style = render::ViewerStyle::Field;
  page.fieldTitle = "mean curvature H (" + energy.name + ")";
  page.diverging = true;
  for (render::ViewerMesh& m : page.meshes)
    for (std::size_t f = 0; f < m.frames.size(); ++f) {
      const std::vector<double> h =
          energy.meanCurvatureField(modeling::Mesh{m.frames[f], m.trianglesAt(f)});
      m.fields.push_back(Eigen::Map<const Eigen::VectorXd>(h.data(), Eigen::Index(h.size())));
    }
}

void addDisplacementFields(render::ViewerPageSpec& page, const modeling::Positions& rest,
                           const std::string& restName) {
  page.style = render::ViewerStyle::Field;
  page.fieldTitle = "displacement |x - x_rest|";
  page.diverging = false;
  for (render::ViewerMesh& m : page.meshes) {
    if (m.frames.empty()) throw InputError(m.name + ": no frames");
    if (!m.faceChanges.empty())
      throw InputError(m.name + ": its faces change at frame " +
                       std::to_string(m.faceChanges.front().frame) +
                       " (a cut adds vertices that have no place in the rest positions); "
                       "the displacement style needs one vertex set");
    const modeling::Positions& from = rest.rows() > 0 ? rest : m.frames.front();
    if (from.rows() != m.frames.front().rows())
      throw InputError(restName + ": " + std::to_string(from.rows()) + " vertices, but " + m.name +
                       " has " + std::to_string(m.frames.front().rows()));
    for (const modeling::Positions& x : m.frames) m.fields.push_back((x - from).rowwise().norm());
  }
}

}  // namespace flexure::reports
