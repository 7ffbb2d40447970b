// The fields a viewer page (render/viewer_page.h) colours its meshes by, computed at every frame
// of every mesh — shared by `flexure view` and flexure.view, so that both draw the same numbers.
#pragma once

#include <string>

#include "curvature/energy_registry.h"
#include "render/viewer_page.h"

namespace flexure::reports {

// The mean curvature H of `energy`'s kernel (as the renderer's curvature style) at every vertex
// of every frame, on the diverging map; sets the page's field style and legend title.
void addMeanCurvatureFields(render::ViewerPageSpec& page, const curvature::EnergyEntry& energy);

// |x − x_rest| at every vertex of every frame, on the sequential map; `rest` (#V by 3, the same
// for every mesh) named `restName` in messages, or empty: each mesh's first frame. InputError
// when `rest` has another vertex count than a mesh.
void addDisplacementFields(render::ViewerPageSpec& page, const modeling::Positions& rest,
                           const std::string& restName);

}  // namespace flexure::reports
