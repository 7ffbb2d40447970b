// The mesh drawn with OpenGL into an image (internal to render/): the corner soup, the shader
// program, the multisampled framebuffer, the uniforms, the draw and the readback.
#pragma once

#include <vector>

#include "render/colour_map.h"
#include "render/image.h"
#include "render/mesh_renderer.h"
#include "render/scene.h"

namespace flexure::render {

class OffscreenContext;

// Draws the mesh with GL into an image of `width` × `height` (the whole image, or the part left
// of the legend).
Image rasterize(OffscreenContext& context, const Scene& scene, const RenderOptions& o, int width,
                int height, const std::vector<double>& scalars, double scalarMin, double scalarMax,
                const ColourMap& map, RenderTimings* timings = nullptr);

}  // namespace flexure::render
