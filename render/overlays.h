// What is drawn over a render with Cairo (internal to render/): the caption and the outline
// segments.
#pragma once

#include "render/image.h"
#include "render/mesh_renderer.h"
#include "render/scene.h"

namespace flexure::render {

// `text` at the top left of `image`, in black or white against the background.
Image withCaption(const Image& image, const RenderOptions& o);

// The outline segments of `o` drawn over `meshImage` (the part of the render the mesh is framed
// in): each end x maps to the frame, p = (x − c) · worldToFrame, to clip coordinates
// q = frameToClip (p, 1), and to the pixel ((q_x / q_w + 1) w / 2, (1 − q_y / q_w) h / 2), image
// rows top to bottom as GL's viewport maps them, flipped.
Image withOutline(const Image& meshImage, const Scene& scene, const RenderOptions& o);

}  // namespace flexure::render
