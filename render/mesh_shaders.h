// The GLSL 4.50 sources of the mesh renderer (internal to render/): the vertex stage and the
// fragment stage with the styles' environments and lights (mesh_shaders.cpp states the math).
#pragma once

namespace flexure::render {

// Frame coordinates in, clip coordinates out, with each corner's barycentric coordinate.
extern const char* const kVertexShader;
// The stripes' colours, darkStripe(s) and the reflection, isophote and shaded styles' colours
// (reflectionLines, isophotes, shaded): the one definition of the renderer and of the viewer page
// (viewer_page.cpp), GLSL 4.50 and GLSL ES 1.0 alike, reading the uniforms stripeWidth,
// stripeCount, stripeAcross and lightDirection. Both fragment stages hold it where they say
// "@STRIPE_FUNCTIONS@".
extern const char* const kStripeFunctions;
// The styles' colours: reflection, isophote and highlight stripes, shading, the scalar colour
// map, obstacles, marked faces, the edge overlay and (with CRACKS defined) the crack band.
extern const char* const kFragmentShader;

}  // namespace flexure::render
