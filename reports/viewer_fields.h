// The fields a viewer page (render/viewer_page.h) colours its meshes by, computed at every frame
// of every mesh, and the page's styles by name — shared by `flexure view` and flexure.view, so
// that both take the same names and draw the same numbers.
#pragma once

#include <string>
#include <vector>

#include "curvature/energy_registry.h"
#include "modeling/mesh.h"
#include "render/viewer_page.h"

namespace flexure::reports {

// What a field style colours: None for the drawing styles (reflection, isophote, shaded).
enum class ViewerField { None, Curvature, Displacement, Plastic, Angle, Error };

struct ViewStyle {
  render::ViewerStyle drawing = render::ViewerStyle::Reflection;
  ViewerField field = ViewerField::None;
};

// "reflection", "isophote", "shaded", or a field style: "curvature", "displacement", "plastic"
// (addPlasticFields, viewer_simulation.h), "angle" or "error". InputError naming
// ViewerPageSpec.style and the choices.
ViewStyle parseViewStyle(const std::string& name);
// The names parseViewStyle takes, "reflection | isophote | …".
std::string viewStyleNames();

// What the field styles read besides the meshes: each its own, unused by the others.
struct ViewerFieldSources {
  const curvature::EnergyEntry* curvatureEnergy = nullptr;  // curvature (null: the default)
  modeling::Positions rest;          // displacement (empty: each mesh's first frame)
  std::string restName;              // in displacement's messages
  modeling::Mesh reference;          // error
  std::string referenceName;         // error's legend
  std::vector<std::string> folders;  // plastic: each mesh's simulation folder
};

// The field of `field` at every frame of the page's meshes (the functions below; nothing for
// None), as `flexure view` and flexure.view both draw it.
void addFields(render::ViewerPageSpec& page, ViewerField field, const ViewerFieldSources& sources);

// The mean curvature H of `energy`'s kernel (as the renderer's curvature style) at every vertex
// of every frame, on the diverging map; sets the page's field style and legend title.
void addMeanCurvatureFields(render::ViewerPageSpec& page, const curvature::EnergyEntry& energy);

// |x − x_rest| at every vertex of every frame, on the sequential map; `rest` (#V by 3, the same
// for every mesh) named `restName` in messages, or empty: each mesh's first frame. InputError
// when `rest` has another vertex count than a mesh.
void addDisplacementFields(render::ViewerPageSpec& page, const modeling::Positions& rest,
                           const std::string& restName);

// The smallest interior angle of every face at every frame (modeling::smallestAngleDegrees), in
// degrees, per face on the sequential map over [0°, 60°] (60° only for an equilateral face):
// slivers dark. Not for meshes with modes (InputError naming the mesh).
void addSmallestAngleFields(render::ViewerPageSpec& page);

// The error against a reference surface: at every vertex of every frame its distance to the
// closest point of `reference`'s faces (modeling::SurfaceDistance; any mesh, its vertices
// unrelated to the page's), on the sequential map over [0, max]; `referenceName` (its file's
// name) titles the legend.
void addReferenceDistanceFields(render::ViewerPageSpec& page, const modeling::Mesh& reference,
                                const std::string& referenceName);

}  // namespace flexure::reports
