#include "optimize/boundary_conditions.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>

#include "curvature/midedge_boundary.h"
#include "modeling/boundary_rings.h"
#include "modeling/errors.h"
#include "modeling/vertex_sets.h"

namespace flexure::optimize {

DofMode parseDofMode(std::string_view name, std::string_view field) {
  if (name == "height") return DofMode::Height;
  if (name == "xyz") return DofMode::Xyz;
  throw InputError(std::string(field) + " " + std::string(name) + ": expected height or xyz");
}

BoundaryNormals parseBoundaryNormals(std::string_view name) {
  if (name == "clamped") return BoundaryNormals::Clamped;
  if (name == "free") return BoundaryNormals::Free;
  throw InputError("ProblemOptions.boundaryNormals " + std::string(name) +
                   ": expected clamped or free");
}

BoundaryConditions withHeldValues(BoundaryConditions bc, const Positions& held,
                                  const std::optional<Eigen::VectorXd>& heldXi) {
  if (held.rows() != bc.start.rows())
    throw InputError("held values: " + std::to_string(held.rows()) + " rows for a mesh of " +
                     std::to_string(bc.start.rows()) + " vertices");
  const bool holdsXi =
      std::find(bc.fixedEdge.begin(), bc.fixedEdge.end(), true) != bc.fixedEdge.end();
  bool moved = false;
  for (Eigen::Index v = 0; v < held.rows() && !moved; ++v)
    moved = bc.fixedVertex[v] && bc.start.row(v) != held.row(v);
  if (holdsXi && moved && !heldXi)
    throw InputError(
        "held ξ: the problem holds ξ on its boundary edges (the clamp of its boundary), and the "
        "held vertices given are not its own; give the ξ that clamp them (e.g. those of a problem "
        "with their boundary surface), or the old clamp would stay");
  if (heldXi && heldXi->size() != bc.xi.size())
    throw InputError("held ξ: " + std::to_string(heldXi->size()) + " values for " +
                     std::to_string(bc.xi.size()) + " edge unknowns");
  bc.start = held;
  if (heldXi) bc.xi = *heldXi;
  return bc;
}

std::vector<bool> freeUnknownMask(const std::vector<bool>& heldVertex,
                                  const std::vector<bool>& heldEdge, DofMode dof) {
  const size_t vertexCount = heldVertex.size();
  std::vector<bool> free(3 * vertexCount + heldEdge.size(), false);
  for (size_t v = 0; v < vertexCount; ++v)
    for (int c = dof == DofMode::Height ? 2 : 0; c < 3 && !heldVertex[v]; ++c)
      free[3 * v + c] = true;
  for (size_t e = 0; e < heldEdge.size(); ++e) free[3 * vertexCount + e] = !heldEdge[e];
  return free;
}

std::vector<bool> fixedRings(const modeling::Stencils& stencils, int ringCount) {
  const Eigen::VectorXi rings = modeling::vertexRings(stencils);
  std::vector<bool> fixed(stencils.vertexCount(), false);
  for (int v = 0; v < stencils.vertexCount(); ++v) fixed[v] = rings[v] >= 0 && rings[v] < ringCount;
  return fixed;
}

std::vector<bool> parseFixedSet(const std::string& option, const std::string& spec,
                                const modeling::Stencils& stencils, const Positions& rest) {
  const auto colon = spec.find(':');
  const std::string kind = spec.substr(0, colon),
                    value = colon == std::string::npos ? "" : spec.substr(colon + 1);
  const std::string expected = ": expected rings:K, vertices:FILE or box:X0,X1,Y0,Y1,Z0,Z1";
  if (kind == "rings") {
    int rings = -1;
    const auto [end, error] = std::from_chars(value.data(), value.data() + value.size(), rings);
    if (error != std::errc() || end != value.data() + value.size() || rings < 1) {
      throw InputError(option + " " + spec + ": expected rings:K with K >= 1");
    }
    return fixedRings(stencils, rings);
  }
  if (kind == "vertices" && !value.empty()) {
    std::vector<bool> listed =
        modeling::readVertexSet(value, stencils.vertexCount(), "fixed-vertex list");
    // As an empty box: a set that holds nothing is a mistake, not a request to hold nothing
    // (that is "none").
    if (std::find(listed.begin(), listed.end(), true) == listed.end())
      throw InputError(option + " " + spec + ": " + value + " lists no vertex");
    return listed;
  }
  if (kind == "box") {
    // The rest vertices inside an axis-aligned box (bounds inclusive).
    double bounds[6];
    const char* cursor = value.c_str();
    for (int k = 0; k < 6; ++k) {
      char* end = nullptr;
      bounds[k] = std::strtod(cursor, &end);
      if (end == cursor || (k < 5 && *end != ',') || (k == 5 && *end != '\0'))
        throw InputError(option + " " + spec + expected);
      cursor = end + 1;
    }
    std::vector<bool> inside(rest.rows(), false);
    int count = 0;
    for (int v = 0; v < rest.rows(); ++v) {
      bool in = true;
      for (int c = 0; c < 3; ++c)
        in = in && rest(v, c) >= bounds[2 * c] && rest(v, c) <= bounds[2 * c + 1];
      inside[v] = in;
      count += in;
    }
    if (count == 0) throw InputError(option + " " + spec + ": the box holds no vertex of the mesh");
    return inside;
  }
  throw InputError(option + " " + spec + expected);
}

std::vector<bool> clampedBoundaryEdges(const std::string& spec,
                                       const modeling::Stencils& stencils) {
  const std::string prefix = "rings:";
  if (spec.rfind(prefix, 0) != 0) return {};
  int rings = 0;
  const auto [end, error] =
      std::from_chars(spec.data() + prefix.size(), spec.data() + spec.size(), rings);
  if (error != std::errc() || end != spec.data() + spec.size() || rings < 2) return {};
  return curvature::boundaryEdges(stencils);
}

Positions boundaryFromSurface(const Positions& rest, const std::vector<bool>& fixedVertex,
                              const modeling::PolynomialSurface& surface) {
  Positions start = rest;
  for (int v = 0; v < rest.rows(); ++v)
    if (fixedVertex[v]) start(v, 2) = surface.height(rest(v, 0), rest(v, 1));
  return start;
}

BoundaryConditions surfaceBoundary(const modeling::Stencils& stencils, const Positions& rest,
                                   const Eigen::VectorXd& restXi,
                                   const std::vector<bool>& fixedVertex,
                                   const modeling::PolynomialSurface& surface,
                                   BoundaryNormals normals, bool linearized) {
  BoundaryConditions bc;
  bc.fixedVertex = fixedVertex;
  bc.start = boundaryFromSurface(rest, fixedVertex, surface);
  bc.xi = restXi;
  bc.fixedEdge.assign(restXi.size(), false);
  if (restXi.size() == 0 || normals == BoundaryNormals::Free) return bc;
  const std::vector<bool> onBoundary = curvature::boundaryEdges(stencils);
  const Eigen::VectorXd clamped = linearized
                                      ? restXi + curvature::linearizedClampedBoundaryXi(
                                                     stencils, rest, bc.start - rest, surface)
                                      : curvature::clampedBoundaryXi(stencils, bc.start, surface);
  for (int e = 0; e < stencils.edgeCount(); ++e) {
    if (!onBoundary[e]) continue;
    bc.fixedEdge[e] = true;
    bc.xi[e] = clamped[e];
  }
  return bc;
}

double reproductionError(const Positions& rest, const Positions& result,
                         const std::vector<bool>& fixedVertex,
                         const modeling::PolynomialSurface& surface) {
  double error = 0.0, scale = 0.0;
  for (int v = 0; v < rest.rows(); ++v) {
    const double p = surface.height(rest(v, 0), rest(v, 1));
    scale = std::max(scale, std::abs(p));
    if (!fixedVertex[v]) error = std::max(error, std::abs(result(v, 2) - p));
  }
  return scale > 0.0 ? error / scale : error;
}

}  // namespace flexure::optimize
