// A `flexure simulate` folder on a viewer page (render/viewer_page.h): its frames and their times,
// the faces a cut changed, the cracks' lips and the obstacles; shared by `flexure view` and
// flexure.view.
#pragma once

#include <string>
#include <vector>

#include "render/viewer_page.h"

namespace flexure::reports {

// Whether `dir` is a folder (a simulation's, when it holds frame-NNNNN.obj files).
bool isSimulationFolder(const std::string& dir);

// DIR's frame-NNNNN.obj files in order as one mesh named after the folder: the times of
// report.json's "frame_times" (none, and the page numbers the frames, when it has not one per
// frame); where a frame's faces differ from the one before (a cut: fracture), a face change; the
// lips of cracks.json (written by a simulation that fractured); the spheres and planes of
// report.json's "obstacles" (as optimize::parseObstacle reads them). InputError naming the folder
// when it holds no frame; the file of a frame that cannot be read, that changes the vertex count
// without changing the faces, or that changes the faces in a folder without cracks.json;
// cracks.json when it does not match the frames; the report when an obstacle cannot be read.
render::ViewerMesh readSimulationFolder(const std::string& dir);

// The plastic measure of each face at each frame, DIR/plastic.json's "faces" (written by a
// simulation with plasticity), as the per-face field of `page.meshes[first + k]`, read from
// folders[k], on the sequential map titled by the measure's name. InputError naming a
// folders[k] that is no folder or has no plastic.json, and plastic.json when it does not match the
// frames or the folders measure different things.
void addPlasticFields(render::ViewerPageSpec& page, const std::vector<std::string>& folders,
                      std::size_t first = 0);

}  // namespace flexure::reports
