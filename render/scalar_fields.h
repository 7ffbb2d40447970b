// The per-vertex scalar fields the legend styles colour (internal to render/): the values, the
// colour map and its range, and the legend's title and range words.
#pragma once

#include <string>
#include <vector>

#include "modeling/mesh.h"
#include "render/colour_map.h"
#include "render/mesh_renderer.h"

namespace flexure::render {

// What a legend style colours: the per-vertex values, the colour map's range (decimal logarithms
// on a log scale), the map, and the legend's title and range words.
struct ScalarField {
  std::vector<double> values;
  double minimum = 0.0, maximum = 1.0;
  const ColourMap* map = nullptr;
  std::string title, range;
  bool logarithmic = false;
};

// The field of the style of `o` (error, curvature, displacement or plastic) on `mesh`; InputError
// when the values given do not match the mesh or are not finite.
ScalarField legendField(const modeling::Mesh& mesh, const RenderOptions& o);

}  // namespace flexure::render
