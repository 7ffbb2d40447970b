// The render's camera (internal to render/): the camera-aligned object frame and the orthographic
// or perspective projection that frames a set of points (mesh_renderer.h states the conventions).
#pragma once

#include <Eigen/Core>

#include "modeling/mesh.h"
#include "render/mesh_renderer.h"

namespace flexure::render {

// What the shaders see. The "frame" is the camera-aligned object frame: origin at the mesh's
// bounding-box centre, axes (image right, image up, toward the viewer), unit = bounding radius.
struct Camera {
  Eigen::Matrix3d rotation;      // rows: image right, image up, toward the viewer (e)
  Eigen::Matrix3d worldToFrame;  // rotation / R
  Eigen::Vector3d centre;
  Eigen::Matrix4d frameToClip;
  bool perspective = false;
  Eigen::Vector3d eye{0.0, 0.0, 0.0};  // perspective only, in the frame
};

// The camera looking at `points` as the options ask (azimuth, elevation, projection), framing them
// in a width × height image; InputError when the points have no extent or are not finite.
Camera frameCamera(const modeling::Positions& points, const RenderOptions& o, int width,
                   int height);

}  // namespace flexure::render
