#include "modeling/rest_state.h"

#include <Eigen/Geometry>
#include <cmath>
#include <string>

#include "modeling/errors.h"
#include "modeling/mixed_area.h"

namespace flexure::modeling {

RestState precomputeRestState(const Stencils& s, const Positions& rest) {
  const int nf = s.faceCount();
  RestState r;
  r.positions = rest;
  r.faceAreas.resize(nf);
  r.faceNormals.resize(nf, 3);
  r.faceEdgeLengths.resize(nf, 3);
  r.faceEdgeNormals.resize(nf, 9);
  r.faceCotangents.resize(nf, 3);
  r.vertexVoronoiAreas.setZero(s.vertexCount());
  r.vertexBarycentricAreas.setZero(s.vertexCount());

  for (int f = 0; f < nf; ++f) {
    Eigen::Vector3d x[3];
    for (int i = 0; i < 3; ++i) x[i] = rest.row(s.faces(f, i));
    const Eigen::Vector3d areaVector = (x[1] - x[0]).cross(x[2] - x[0]);
    const double twiceArea = areaVector.norm();
    if (!(twiceArea > 0.0)) {
      throw InputError("rest face " + std::to_string(f) + " (vertices " +
                       std::to_string(s.faces(f, 0)) + ", " + std::to_string(s.faces(f, 1)) + ", " +
                       std::to_string(s.faces(f, 2)) +
                       ") has zero area; no bending energy is defined on it");
    }
    const double area = 0.5 * twiceArea;
    const Eigen::Vector3d normal = areaVector / twiceArea;
    r.faceAreas[f] = area;
    r.faceNormals.row(f) = normal;

    // Edge i runs x_{i+1} → x_{i+2}; cot of the angle at vertex i is (e_{i+1} · −e_{i+2}) / 2A
    // with e_i the edge vectors, i.e. the dot of the two edges leaving vertex i.
    double cot[3], lengthSquared[3];
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d edge = x[(i + 2) % 3] - x[(i + 1) % 3];
      lengthSquared[i] = edge.squaredNorm();
      r.faceEdgeLengths(f, i) = std::sqrt(lengthSquared[i]);
      r.faceEdgeNormals.block<1, 3>(f, 3 * i) = edge.cross(normal) / r.faceEdgeLengths(f, i);
      cot[i] = (x[(i + 1) % 3] - x[i]).dot(x[(i + 2) % 3] - x[i]) / twiceArea;
      r.faceCotangents(f, i) = cot[i];
    }
    for (int i = 0; i < 3; ++i) {
      const int v = s.faces(f, i);
      r.vertexBarycentricAreas[v] += area / 3.0;
      r.vertexVoronoiAreas[v] += mixedVoronoiShare(twiceArea, cot, lengthSquared, i);
    }
  }

  r.edgeLengths.resize(s.edgeCount());
  for (int e = 0; e < s.edgeCount(); ++e)
    r.edgeLengths[e] = (rest.row(s.edges(e, 1)) - rest.row(s.edges(e, 0))).norm();
  return r;
}

}  // namespace flexure::modeling
