#include "reports/viewer_fields.h"

#include <algorithm>
#include <string>
#include <vector>

#include "modeling/errors.h"
#include "modeling/mesh_info.h"
#include "modeling/surface_distance.h"
#include "reports/viewer_simulation.h"

namespace flexure::reports {

namespace {

struct NamedStyle {
  const char* name;
  ViewStyle style;
};

const std::vector<NamedStyle>& namedStyles() {
  using render::ViewerStyle;
  static const std::vector<NamedStyle> styles = {
      {"reflection", {ViewerStyle::Reflection, ViewerField::None}},
      {"isophote", {ViewerStyle::Isophote, ViewerField::None}},
      {"shaded", {ViewerStyle::Shaded, ViewerField::None}},
      {"curvature", {ViewerStyle::Field, ViewerField::Curvature}},
      {"displacement", {ViewerStyle::Field, ViewerField::Displacement}},
      {"plastic", {ViewerStyle::Field, ViewerField::Plastic}},
      {"angle", {ViewerStyle::Field, ViewerField::Angle}},
      {"error", {ViewerStyle::Field, ViewerField::Error}},
  };
  return styles;
}

}  // namespace

ViewStyle parseViewStyle(const std::string& name) {
  for (const NamedStyle& s : namedStyles())
    if (name == s.name) return s.style;
  throw InputError("ViewerPageSpec.style '" + name + "': expected " + viewStyleNames());
}

std::string viewStyleNames() {
  std::string names;
  for (const NamedStyle& s : namedStyles())
    names += (names.empty() ? "" : " | ") + std::string(s.name);
  return names;
}

void addFields(render::ViewerPageSpec& page, ViewerField field, const ViewerFieldSources& sources) {
  switch (field) {
    case ViewerField::None:
      return;
    case ViewerField::Curvature:
      return addMeanCurvatureFields(page, sources.curvatureEnergy
                                              ? *sources.curvatureEnergy
                                              : curvature::defaultMeanCurvatureEnergy());
    case ViewerField::Displacement:
      return addDisplacementFields(page, sources.rest, sources.restName);
    case ViewerField::Plastic:
      return addPlasticFields(page, sources.folders);
    case ViewerField::Angle:
      return addSmallestAngleFields(page);
    case ViewerField::Error:
      return addReferenceDistanceFields(page, sources.reference, sources.referenceName);
  }
}

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

void addSmallestAngleFields(render::ViewerPageSpec& page) {
  page.style = render::ViewerStyle::Field;
  page.fieldTitle = "smallest angle (°)";
  page.diverging = false;
  page.fieldOnFaces = true;
  page.fieldRange = std::make_pair(0.0, 60.0);
  for (render::ViewerMesh& m : page.meshes) {
    if (!m.modes.empty())
      throw InputError(m.name +
                       ": the angle style colours faces, and a mode's view colours "
                       "vertices");
    for (std::size_t f = 0; f < m.frames.size(); ++f) {
      const modeling::Triangles& t = m.trianglesAt(f);
      Eigen::VectorXd angles(t.rows());
      for (Eigen::Index j = 0; j < t.rows(); ++j)
        angles[j] = modeling::smallestAngleDegrees(m.frames[f], t(j, 0), t(j, 1), t(j, 2));
      m.fields.push_back(std::move(angles));
    }
  }
}

void addReferenceDistanceFields(render::ViewerPageSpec& page, const modeling::Mesh& reference,
                                const std::string& referenceName) {
  if (reference.faceCount() == 0) throw InputError(referenceName + ": no faces");
  page.style = render::ViewerStyle::Field;
  page.fieldTitle = "error: distance to " + referenceName;
  page.diverging = false;
  const modeling::SurfaceDistance distance(reference);
  double largest = 0.0;
  for (render::ViewerMesh& m : page.meshes)
    for (const modeling::Positions& x : m.frames) {
      Eigen::VectorXd field(x.rows());
      for (Eigen::Index v = 0; v < x.rows(); ++v) field[v] = distance(x.row(v).transpose());
      largest = std::max(largest, field.maxCoeff());
      m.fields.push_back(std::move(field));
    }
  if (largest > 0.0) page.fieldRange = std::make_pair(0.0, largest);
}

}  // namespace flexure::reports
