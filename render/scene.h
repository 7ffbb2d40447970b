// What a render draws (internal to render/): the mesh at its drawn positions (exaggerated about a
// reference), the obstacles (spheres, planes) as one triangle mesh, and the points the camera
// frames.
#pragma once

#include "modeling/mesh.h"
#include "render/mesh_renderer.h"

namespace flexure::render {

// What is drawn: the mesh at its drawn positions (x̄ + k (x − x̄) when exaggerated), the obstacles
// as one triangle mesh, and the points the camera frames.
struct Scene {
  modeling::Mesh mesh;
  modeling::Mesh obstacles;
  modeling::Positions framingPoints;
};

// The drawn mesh, the obstacles and the framed points: the given framing points (or the drawn
// mesh's), every sphere, and every plane's square, sized and centred by those points' bounding box.
Scene buildScene(const modeling::Mesh& mesh, const RenderOptions& o);

}  // namespace flexure::render
