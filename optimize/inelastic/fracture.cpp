#include "optimize/inelastic/fracture.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <unordered_map>

#include "curvature/bending_angle.h"
#include "curvature/face_frame.h"
#include "modeling/errors.h"

namespace flexure::optimize {

namespace {

using modeling::Mesh;
using modeling::Positions;

Eigen::Vector3d rowOf(const Eigen::Ref<const Positions>& x, int v) {
  return x.row(v).transpose();
}

// flapVertex[3 f + i]: the vertex across edge i of face f (the edge opposite corner i, running
// v_{i+1} → v_{i+2}), −1 on the boundary.
std::vector<int> flapVertices(const Mesh& mesh) {
  std::unordered_map<std::int64_t, int> cornerOfDirectedEdge;  // (a → b) ↦ 3 f + i
  const auto key = [&](int a, int b) {
    return static_cast<std::int64_t>(a) * mesh.vertexCount() + b;
  };
  for (int f = 0; f < mesh.faceCount(); ++f) {
    for (int i = 0; i < 3; ++i) {
      cornerOfDirectedEdge[key(mesh.triangles(f, (i + 1) % 3), mesh.triangles(f, (i + 2) % 3))] =
          3 * f + i;
    }
  }
  std::vector<int> flap(3 * mesh.faceCount(), -1);
  for (int f = 0; f < mesh.faceCount(); ++f) {
    for (int i = 0; i < 3; ++i) {
      const auto across = cornerOfDirectedEdge.find(
          key(mesh.triangles(f, (i + 2) % 3), mesh.triangles(f, (i + 1) % 3)));
      if (across == cornerOfDirectedEdge.end()) continue;
      flap[3 * f + i] = mesh.triangles(across->second / 3, across->second % 3);
    }
  }
  return flap;
}

curvature::Vec3<double> vectorOf(const Eigen::Ref<const Positions>& x, int v) {
  return {x(v, 0), x(v, 1), x(v, 2)};
}

// φ = 2 tan(θ/2) of the hinge over edge i of face f with flap vertex g.
double edgeAngleMeasure(const Eigen::Ref<const Positions>& x, const Mesh& mesh, int f, int i,
                        int g) {
  const double theta = curvature::bendingAngle(vectorOf(x, mesh.triangles(f, (i + 1) % 3)),
                                               vectorOf(x, mesh.triangles(f, (i + 2) % 3)),
                                               vectorOf(x, mesh.triangles(f, i)), vectorOf(x, g));
  return curvature::hingeAngleMeasure(theta, curvature::HingeAngle::Tan);
}

FaceStrains strainsOfFace(const Mesh& rest, const Eigen::Ref<const Positions>& current,
                          const std::vector<int>& flap, int f) {
  const Eigen::Vector3d restCorner[3] = {rowOf(rest.positions, rest.triangles(f, 0)),
                                         rowOf(rest.positions, rest.triangles(f, 1)),
                                         rowOf(rest.positions, rest.triangles(f, 2))};
  const curvature::FaceFrame frame =
      curvature::FaceFrame::of(restCorner[0], restCorner[1], restCorner[2]);
  Eigen::Matrix2d restEdges;  // columns x̄1 − x̄0, x̄2 − x̄0 in the frame
  restEdges << frame.components(restCorner[1] - restCorner[0]),
      frame.components(restCorner[2] - restCorner[0]);
  Eigen::Matrix<double, 3, 2> edges;
  edges << rowOf(current, rest.triangles(f, 1)) - rowOf(current, rest.triangles(f, 0)),
      rowOf(current, rest.triangles(f, 2)) - rowOf(current, rest.triangles(f, 0));
  const Eigen::Matrix<double, 3, 2> deformationGradient = edges * restEdges.inverse();
  FaceStrains strains;
  strains.membrane =
      0.5 * (deformationGradient.transpose() * deformationGradient - Eigen::Matrix2d::Identity());

  const double restArea = 0.5 * std::abs(restEdges.determinant());
  for (int i = 0; i < 3; ++i) {
    const int g = flap[3 * f + i];
    if (g < 0) continue;
    const Eigen::Vector2d edge =
        frame.components(restCorner[(i + 2) % 3] - restCorner[(i + 1) % 3]);
    const Eigen::Vector2d normal = Eigen::Vector2d(edge.y(), -edge.x()).normalized();
    const double change =
        edgeAngleMeasure(current, rest, f, i, g) - edgeAngleMeasure(rest.positions, rest, f, i, g);
    strains.bending += change * edge.norm() / (2.0 * restArea) * normal * normal.transpose();
  }
  return strains;
}

void requireMatchingRows(const Mesh& rest, const Eigen::Ref<const Positions>& current) {
  if (current.rows() != rest.vertexCount()) {
    throw InputError("fracture criterion: the configuration has " + std::to_string(current.rows()) +
                     " vertices, the rest mesh " + std::to_string(rest.vertexCount()));
  }
}

}  // namespace

void FractureOptions::validate() const {
  if (!std::isfinite(fractureStrain) || fractureStrain <= 0.0) {
    throw InputError("FractureOptions.fractureStrain must be a positive number, got " +
                     std::to_string(fractureStrain));
  }
  if (!std::isfinite(thickness) || thickness < 0.0) {
    throw InputError("FractureOptions.thickness must be a finite number ≥ 0, got " +
                     std::to_string(thickness));
  }
}

std::vector<FaceStrains> faceStrains(const Mesh& rest, const Eigen::Ref<const Positions>& current) {
  requireMatchingRows(rest, current);
  const std::vector<int> flap = flapVertices(rest);
  std::vector<FaceStrains> strains(rest.faceCount());
  for (int f = 0; f < rest.faceCount(); ++f) strains[f] = strainsOfFace(rest, current, flap, f);
  return strains;
}

std::vector<FacePrincipalStrain> facePrincipalStrains(const Mesh& rest,
                                                      const Eigen::Ref<const Positions>& current,
                                                      double thickness) {
  const std::vector<FaceStrains> strains = faceStrains(rest, current);
  std::vector<FacePrincipalStrain> principal(rest.faceCount());
  for (int f = 0; f < rest.faceCount(); ++f) {
    const curvature::FaceFrame frame = curvature::FaceFrame::of(
        rowOf(rest.positions, rest.triangles(f, 0)), rowOf(rest.positions, rest.triangles(f, 1)),
        rowOf(rest.positions, rest.triangles(f, 2)));
    FacePrincipalStrain& result = principal[f];
    result.face = f;
    result.strain = -std::numeric_limits<double>::infinity();
    for (const int fibre : {+1, -1}) {
      const Eigen::Matrix2d fibreStrain =
          strains[f].membrane + fibre * 0.5 * thickness * strains[f].bending;
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(fibreStrain);
      // Eigenvalues ascending: the last is the largest.
      if (eigen.eigenvalues()(1) <= result.strain) continue;
      const Eigen::Vector2d vector = eigen.eigenvectors().col(1);
      result.strain = eigen.eigenvalues()(1);
      result.strainDirection = (vector.x() * frame.u + vector.y() * frame.v).normalized();
      result.crackDirection = frame.normal.cross(result.strainDirection);
      result.fibre = fibre;
    }
  }
  return principal;
}

std::optional<FacePrincipalStrain> criticalFace(const Mesh& rest,
                                                const Eigen::Ref<const Positions>& current,
                                                const FractureOptions& options) {
  options.validate();
  std::optional<FacePrincipalStrain> critical;
  for (const FacePrincipalStrain& face : facePrincipalStrains(rest, current, options.thickness)) {
    if (face.strain > options.fractureStrain && (!critical || face.strain > critical->strain)) {
      critical = face;
    }
  }
  return critical;
}

std::optional<FracturedShell> fractureShell(const Mesh& rest, const Positions& x,
                                            const Positions& v, const std::vector<bool>& heldVertex,
                                            const FractureOptions& options) {
  if (v.rows() != rest.vertexCount() ||
      (!heldVertex.empty() && static_cast<int>(heldVertex.size()) != rest.vertexCount())) {
    throw InputError("fracture: the velocities or held vertices do not match the rest mesh's " +
                     std::to_string(rest.vertexCount()) + " vertices");
  }
  const std::optional<FacePrincipalStrain> critical = criticalFace(rest, x, options);
  if (!critical) return std::nullopt;
  const std::vector<FacePrincipalStrain> strains = facePrincipalStrains(rest, x, options.thickness);
  std::vector<bool> cracking(rest.faceCount());
  for (int f = 0; f < rest.faceCount(); ++f) {
    cracking[f] = strains[f].strain > options.fractureStrain;
  }
  FracturedShell shell;
  shell.critical = *critical;
  shell.cut =
      modeling::cutAlongCrack(rest, x, {critical->face, critical->crackDirection}, cracking);
  shell.rest = shell.cut.rest;
  shell.positions = shell.cut.current;
  const int vertexCount = shell.rest.vertexCount();
  shell.velocities.resize(vertexCount, 3);
  if (!heldVertex.empty()) shell.heldVertex.resize(vertexCount);
  for (int i = 0; i < vertexCount; ++i) {
    const modeling::VertexSource& s = shell.cut.sources[i];
    shell.velocities.row(i) = (1.0 - s.t) * v.row(s.a) + s.t * v.row(s.b);
    if (!heldVertex.empty()) shell.heldVertex[i] = heldVertex[s.a] && heldVertex[s.b];
  }
  return shell;
}

std::vector<Mesh> meshFragments(const Mesh& mesh) {
  std::vector<int> parent(mesh.vertexCount());
  for (int i = 0; i < mesh.vertexCount(); ++i) parent[i] = i;
  const auto root = [&](int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (int f = 0; f < mesh.faceCount(); ++f) {
    parent[root(mesh.triangles(f, 0))] = root(mesh.triangles(f, 1));
    parent[root(mesh.triangles(f, 1))] = root(mesh.triangles(f, 2));
  }
  std::unordered_map<int, int> fragmentOfRoot;
  std::vector<int> fragmentOf(mesh.vertexCount()), indexIn(mesh.vertexCount());
  std::vector<std::vector<int>> vertices;
  for (int i = 0; i < mesh.vertexCount(); ++i) {
    const auto [entry, added] =
        fragmentOfRoot.try_emplace(root(i), static_cast<int>(vertices.size()));
    if (added) vertices.emplace_back();
    fragmentOf[i] = entry->second;
    indexIn[i] = static_cast<int>(vertices[entry->second].size());
    vertices[entry->second].push_back(i);
  }
  std::vector<Mesh> fragments(vertices.size());
  std::vector<std::vector<int>> faces(vertices.size());
  for (int f = 0; f < mesh.faceCount(); ++f) faces[fragmentOf[mesh.triangles(f, 0)]].push_back(f);
  for (std::size_t k = 0; k < fragments.size(); ++k) {
    fragments[k].positions.resize(static_cast<int>(vertices[k].size()), 3);
    for (std::size_t i = 0; i < vertices[k].size(); ++i) {
      fragments[k].positions.row(static_cast<int>(i)) = mesh.positions.row(vertices[k][i]);
    }
    fragments[k].triangles.resize(static_cast<int>(faces[k].size()), 3);
    for (std::size_t j = 0; j < faces[k].size(); ++j) {
      for (int c = 0; c < 3; ++c) {
        fragments[k].triangles(static_cast<int>(j), c) = indexIn[mesh.triangles(faces[k][j], c)];
      }
    }
  }
  return fragments;
}

}  // namespace flexure::optimize
