// A fairing result on a viewer page (render/viewer_page.h): the input, CGAL's fair and flexure's
// side by side (one linked camera), each with the faired region's outline
// (modeling::regionOutlineEdges), read from the JSON report `flexure fair` writes; shared by
// `flexure view` and flexure.view.
#pragma once

#include <string>
#include <vector>

#include "modeling/mesh.h"
#include "render/viewer_page.h"

namespace flexure::reports {

// The outline of `region` (a flag per vertex of `mesh`) as page segments along mesh edges.
render::ViewerSegments regionOutlineSegments(const modeling::Mesh& mesh,
                                             const std::vector<bool>& region);

// Whether `path` is a fairing report: a JSON object with "measures", "region" and "input".
bool isFairingReport(const std::string& path);

// The meshes of a fairing report added to `page`: "input" (for a hole fill, the mesh with its
// holes: no outline, other vertices), "cgal_output" when written, and "output", each path as
// written in the report — relative to the working directory, else to the report's folder. The
// outline is of the report's region "indices", on each mesh with the result's vertices; the page
// is framed as flexure fair's figure: the region and modeling::kHeldRings +
// modeling::kContextRings rings around it on those meshes, seen along the region's mean normal on
// the result. InputError naming the report or the file: not a fairing report, no region indices,
// an output not written (an unconverged fair), a mesh missing or with another vertex count.
void addFairingReport(render::ViewerPageSpec& page, const std::string& path);

}  // namespace flexure::reports
