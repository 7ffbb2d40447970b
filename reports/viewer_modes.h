// Vibration modes on a viewer page (render/viewer_page.h): each mode's displacement φ and its nodal
// lines — the zero set of the normal displacement (optimize::nodalEdgeSegments), computed once
// here as points on mesh edges — from a `flexure modes` folder or from shapes in memory; shared
// by `flexure view` and flexure.view.
#pragma once

#include <string>
#include <vector>

#include "modeling/mesh.h"
#include "modeling/rest_state.h"
#include "modeling/stencils.h"
#include "render/viewer_page.h"

namespace flexure::reports {

// A mode of the page: `shape` φ (#V by 3, the rest vertices' displacement at full swing), its
// label, and its nodal lines on the rest mesh's edges.
render::ViewerMode viewerMode(const modeling::Stencils& stencils, const modeling::RestState& rest,
                              const modeling::Positions& shape, const std::string& label);

// Whether `dir` is a `flexure modes` folder (it holds modes.json).
bool isModesFolder(const std::string& dir);

// The meshes of a `flexure modes` folder, one per energy of DIR/modes.json: the rest mesh
// (rest.obj) with its flexible modes, φ_k = mode-<energy>-<k>.obj − rest (the largest
// displacement the scale × L the shapes were written with), each labelled "mode k: λ = …, ω = …".
// InputError naming the file at fault: modes.json unreadable, no rest.obj or shapes (the folder was
// written without its mode shapes), a shape with another vertex count or other faces than the rest;
// and naming the folder for a page `style` that cannot show modes (a field: the modes are drawn in
// the reflection, isophote or shaded style).
std::vector<render::ViewerMesh> readModesFolder(const std::string& dir, render::ViewerStyle style);

}  // namespace flexure::reports
