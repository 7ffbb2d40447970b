// A simulation folder's extras on a viewer page (render/viewer_page.h): its obstacles, read from
// the folder's report.json; shared by `flexure view` and flexure.view.
#pragma once

#include <string>

#include "render/viewer_page.h"

namespace flexure::reports {

// The spheres and planes of DIR/report.json's "obstacles" (each "sphere:x,y,z,r" or
// "plane:nx,ny,nz,d", as optimize::parseObstacle reads them) added to `mesh`; nothing when the
// report or the list is missing. InputError naming the report for an obstacle it cannot read.
void addSimulationObstacles(render::ViewerMesh& mesh, const std::string& dir);

}  // namespace flexure::reports
