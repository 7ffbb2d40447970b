// The legend of the scalar styles (internal to render/): a colour bar with ticks beside the mesh
// image, titled and with the words on how its range was chosen.
#pragma once

#include <string>

#include "render/colour_map.h"
#include "render/image.h"
#include "render/mesh_renderer.h"

namespace flexure::render {

// The mesh image on the left, and on the right a vertical colour bar of `map` from `minimum`
// (bottom) to `maximum` (top) with ticks at legendTicks, and above it `title` and `range` (how
// the range was chosen), each fitted to the legend's width.
// On a log scale `minimum` and `maximum` are decimal logarithms, the ticks whole decades labelled
// "1e-5".
Image withLegend(const Image& meshImage, const RenderOptions& o, double minimum, double maximum,
                 const ColourMap& map, const std::string& title, const std::string& range,
                 bool logarithmic = false);

}  // namespace flexure::render
