#include "optimize/inelastic/fracture.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <unordered_map>

#include "curvature/face_frame.h"
#include "curvature/rest_element_data.h"
#include "curvature/triangle_averaged.h"
#include "modeling/errors.h"
#include "modeling/rest_state.h"
#include "modeling/stencils.h"

namespace flexure::optimize {

namespace {

using modeling::Mesh;
using modeling::Positions;

Eigen::Vector3d rowOf(const Eigen::Ref<const Positions>& x, int v) {
  return x.row(v).transpose();
}

// The point across edge i of face f mirrored from its corner i, in the face's plane: a flat hinge
// (θ = 0) standing in for the missing flap of a boundary edge, whose edge tensor is zero.
Eigen::Vector3d mirroredCorner(const Eigen::Ref<const Positions>& x, const Mesh& mesh, int f,
                               int i) {
  const Eigen::Vector3d corner = rowOf(x, mesh.triangles(f, i));
  const Eigen::Vector3d a = rowOf(x, mesh.triangles(f, (i + 1) % 3));
  const Eigen::Vector3d along = (rowOf(x, mesh.triangles(f, (i + 2) % 3)) - a).normalized();
  const Eigen::Vector3d foot = a + (corner - a).dot(along) * along;
  return 2.0 * foot - corner;
}

// S_T of face f at configuration x: TriangleAveragedResidual::shapeOperator with the rest edge
// tensors of the face's interior edges (a boundary edge's tensor is zero).
Eigen::Matrix2d shapeOperatorOf(const curvature::TriangleAveragedResidual& face,
                                const Eigen::Ref<const Positions>& x, const Mesh& mesh, int f) {
  std::array<Eigen::Vector3d, 6> points;
  std::array<const double*, 6> blocks;
  for (int k = 0; k < 6; ++k) {
    const int v = face.vertices[k];
    points[k] = v >= 0 ? rowOf(x, v) : mirroredCorner(x, mesh, f, k - 3);
    blocks[k] = points[k].data();
  }
  const curvature::Sym2<double> s = face.shapeOperator(blocks.data());
  Eigen::Matrix2d m;
  m << s.a, s.b, s.b, s.c;
  return m;
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
                     numberText(fractureStrain));
  }
  if (!std::isfinite(thickness) || thickness < 0.0) {
    throw InputError("FractureOptions.thickness must be a finite number ≥ 0, got " +
                     numberText(thickness));
  }
}

FractureCriterion::FractureCriterion(const Mesh& rest)
    : rest_(rest), stencils_(modeling::compileStencils(rest)) {
  const modeling::RestState restState = modeling::precomputeRestState(stencils_, rest.positions);
  faces_.resize(rest.faceCount());
  for (int f = 0; f < rest.faceCount(); ++f) {
    const Eigen::Vector3d restCorner[3] = {rowOf(rest.positions, rest.triangles(f, 0)),
                                           rowOf(rest.positions, rest.triangles(f, 1)),
                                           rowOf(rest.positions, rest.triangles(f, 2))};
    RestFace& face = faces_[f];
    face.frame = curvature::FaceFrame::of(restCorner[0], restCorner[1], restCorner[2]);
    Eigen::Matrix2d restEdges;  // columns x̄1 − x̄0, x̄2 − x̄0 in the frame
    restEdges << face.frame.components(restCorner[1] - restCorner[0]),
        face.frame.components(restCorner[2] - restCorner[0]);
    face.inverseRestEdges = restEdges.inverse();
    // curvature::edgeTensor's frame (current_metric.h's at the rest corners) is FaceFrame's.
    const double area = restState.faceAreas[f];
    for (int i = 0; i < 3; ++i) {
      face.shapeOperator.vertices[i] = stencils_.faces(f, i);
      face.shapeOperator.vertices[3 + i] = stencils_.faceFlaps(f, i);
      const double scale =
          stencils_.faceFlaps(f, i) < 0 ? 0.0 : restState.faceEdgeLengths(f, i) / (2.0 * area);
      face.shapeOperator.edgeTensors[i] = curvature::edgeTensor(stencils_, restState, f, i, scale);
    }
    face.restShapeOperator = shapeOperatorOf(face.shapeOperator, rest.positions, rest, f);
  }
}

std::vector<FaceStrains> FractureCriterion::strains(
    const Eigen::Ref<const Positions>& current) const {
  requireMatchingRows(rest_, current);
  std::vector<FaceStrains> strains(rest_.faceCount());
  for (int f = 0; f < rest_.faceCount(); ++f) {
    const RestFace& face = faces_[f];
    Eigen::Matrix<double, 3, 2> edges;
    edges << rowOf(current, rest_.triangles(f, 1)) - rowOf(current, rest_.triangles(f, 0)),
        rowOf(current, rest_.triangles(f, 2)) - rowOf(current, rest_.triangles(f, 0));
    const Eigen::Matrix<double, 3, 2> deformationGradient = edges * face.inverseRestEdges;
    strains[f].membrane =
        0.5 * (deformationGradient.transpose() * deformationGradient - Eigen::Matrix2d::Identity());
    strains[f].bending =
        shapeOperatorOf(face.shapeOperator, current, rest_, f) - face.restShapeOperator;
  }
  return strains;
}

std::vector<FacePrincipalStrain> FractureCriterion::principalStrains(
    const std::vector<FaceStrains>& strains, double thickness) const {
  std::vector<FacePrincipalStrain> principal(rest_.faceCount());
  for (int f = 0; f < rest_.faceCount(); ++f) {
    const curvature::FaceFrame& frame = faces_[f].frame;
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

std::vector<FaceStrains> faceStrains(const Mesh& rest, const Eigen::Ref<const Positions>& current) {
  requireMatchingRows(rest, current);
  return FractureCriterion(rest).strains(current);
}

std::vector<FacePrincipalStrain> facePrincipalStrains(const Mesh& rest,
                                                      const Eigen::Ref<const Positions>& current,
                                                      double thickness) {
  requireMatchingRows(rest, current);
  const FractureCriterion criterion(rest);
  return criterion.principalStrains(criterion.strains(current), thickness);
}

namespace {

// The face with the largest strain when it exceeds ε_f.
std::optional<FacePrincipalStrain> strongestOver(const std::vector<FacePrincipalStrain>& strains,
                                                 double fractureStrain) {
  std::optional<FacePrincipalStrain> critical;
  for (const FacePrincipalStrain& face : strains) {
    if (face.strain > fractureStrain && (!critical || face.strain > critical->strain)) {
      critical = face;
    }
  }
  return critical;
}

}  // namespace

std::optional<FacePrincipalStrain> criticalFace(const Mesh& rest,
                                                const Eigen::Ref<const Positions>& current,
                                                const FractureOptions& options) {
  options.validate();
  return strongestOver(facePrincipalStrains(rest, current, options.thickness),
                       options.fractureStrain);
}

namespace {

// The vertices of `rest` at the rest point p.
std::vector<int> verticesAt(const Mesh& rest, const Eigen::Vector3d& p) {
  std::vector<int> found;
  for (int i = 0; i < rest.vertexCount(); ++i)
    if (rest.positions.row(i).transpose() == p) found.push_back(i);
  return found;
}

// The crack direction at tip vertex v: n̄_f × the principal direction of the area-weighted mean
// of the fibre strains (fibre `fibre`) of the faces around v, as 3-D tensors U E Uᵀ (U = [u v] of
// each rest frame) projected into face f's rest plane. The mean smooths the tip's singular field,
// whose single faces lean off the load.
Eigen::Vector3d tipCrackDirection(const Mesh& rest, const std::vector<FaceStrains>& strains,
                                  double thickness, int tip, int f, int fibre) {
  Eigen::Matrix3d mean = Eigen::Matrix3d::Zero();
  for (int g = 0; g < rest.faceCount(); ++g) {
    if ((rest.triangles.row(g).array() != tip).all()) continue;
    const Eigen::Vector3d x0 = rowOf(rest.positions, rest.triangles(g, 0));
    const Eigen::Vector3d x1 = rowOf(rest.positions, rest.triangles(g, 1));
    const Eigen::Vector3d x2 = rowOf(rest.positions, rest.triangles(g, 2));
    const curvature::FaceFrame frame = curvature::FaceFrame::of(x0, x1, x2);
    Eigen::Matrix<double, 3, 2> u;
    u << frame.u, frame.v;
    const Eigen::Matrix2d e = strains[g].membrane + fibre * 0.5 * thickness * strains[g].bending;
    mean += 0.5 * (x1 - x0).cross(x2 - x0).norm() * u * e * u.transpose();
  }
  const curvature::FaceFrame frame = curvature::FaceFrame::of(
      rowOf(rest.positions, rest.triangles(f, 0)), rowOf(rest.positions, rest.triangles(f, 1)),
      rowOf(rest.positions, rest.triangles(f, 2)));
  Eigen::Matrix<double, 3, 2> u;
  u << frame.u, frame.v;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(u.transpose() * mean * u);
  const Eigen::Vector2d largest = eigen.eigenvectors().col(1);
  return frame.normal.cross(largest.x() * frame.u + largest.y() * frame.v).normalized();
}

// From the crack to its tip vertex: the tip minus the mean of its neighbours along boundary edges
// (the crack's lips: edges with one face).
Eigen::Vector3d awayFromCrack(const Mesh& rest, int tip) {
  std::map<int, int> facesOfEdgeTo;
  for (int g = 0; g < rest.faceCount(); ++g) {
    for (int k = 0; k < 3; ++k) {
      if (rest.triangles(g, k) != tip) continue;
      ++facesOfEdgeTo[rest.triangles(g, (k + 1) % 3)];
      ++facesOfEdgeTo[rest.triangles(g, (k + 2) % 3)];
    }
  }
  Eigen::Vector3d lips = Eigen::Vector3d::Zero();
  int count = 0;
  for (const auto& [w, faces] : facesOfEdgeTo) {
    if (faces != 1) continue;
    lips += rowOf(rest.positions, w);
    ++count;
  }
  const Eigen::Vector3d x = rowOf(rest.positions, tip);
  return count > 0 ? Eigen::Vector3d(x - lips / count) : Eigen::Vector3d::Zero();
}

}  // namespace

std::vector<Eigen::Vector3d> openCrackTips(const Mesh& rest,
                                           const std::vector<Eigen::Vector3d>& candidates) {
  std::vector<Eigen::Vector3d> open;
  for (const Eigen::Vector3d& p : candidates) {
    if (verticesAt(rest, p).size() != 1) continue;
    if (std::find(open.begin(), open.end(), p) == open.end()) open.push_back(p);
  }
  return open;
}

std::optional<FracturedShell> fractureShell(const Mesh& rest, const Positions& x,
                                            const Positions& v, const std::vector<bool>& heldVertex,
                                            const FractureOptions& options,
                                            const std::vector<Eigen::Vector3d>& openTips) {
  requireMatchingRows(rest, x);
  return fractureShell(FractureCriterion(rest), x, v, heldVertex, options, openTips);
}

namespace {

// The faces with a vertex on an earlier crack's lips (a rest point where two or more vertices are).
std::vector<bool> lipFaces(const Mesh& rest) {
  std::map<std::array<double, 3>, int> copiesAt;
  for (int i = 0; i < rest.vertexCount(); ++i)
    ++copiesAt[{rest.positions(i, 0), rest.positions(i, 1), rest.positions(i, 2)}];
  std::vector<bool> lip(rest.faceCount(), false);
  for (int f = 0; f < rest.faceCount(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int i = rest.triangles(f, k);
      if (copiesAt[{rest.positions(i, 0), rest.positions(i, 1), rest.positions(i, 2)}] > 1)
        lip[f] = true;
    }
  }
  return lip;
}

}  // namespace

std::vector<bool> fractureEventFaces(const Mesh& rest,
                                     const std::vector<Eigen::Vector3d>& openTips) {
  std::vector<bool> event = lipFaces(rest);
  event.flip();
  for (const Eigen::Vector3d& point : openTips) {
    const std::vector<int> at = verticesAt(rest, point);
    if (at.size() != 1) continue;
    for (int f = 0; f < rest.faceCount(); ++f)
      if ((rest.triangles.row(f).array() == at[0]).any()) event[f] = true;
  }
  return event;
}

namespace {

// Where a fracture check on (criterion.rest(), x) starts a crack: the seed, the strain at its face
// (its crackDirection the seed's direction) and the faces over ε_f the crack may run through.
// Empty when the check does not cut.
struct CrackStart {
  modeling::CrackSeed seed;
  FacePrincipalStrain strain;
  std::vector<bool> cracking;  // #F
};

std::optional<CrackStart> crackStart(const FractureCriterion& criterion, const Positions& x,
                                     const FractureOptions& options,
                                     const std::vector<Eigen::Vector3d>& openTips) {
  const Mesh& rest = criterion.rest();
  options.validate();
  const std::vector<FaceStrains> faceStrain = criterion.strains(x);
  const std::vector<FacePrincipalStrain> strains =
      criterion.principalStrains(faceStrain, options.thickness);
  const std::optional<FacePrincipalStrain> critical =
      strongestOver(strains, options.fractureStrain);
  if (!critical) return std::nullopt;
  std::vector<bool> cracking(rest.faceCount());
  for (int f = 0; f < rest.faceCount(); ++f) {
    cracking[f] = strains[f].strain > options.fractureStrain;
  }
  // A new crack starts at the strongest face off the lips of earlier cracks (vertices split in
  // two): those faces unload as the lips open, and crack again only from a tip.
  const std::vector<bool> onLip = lipFaces(rest);
  std::optional<FacePrincipalStrain> initiating;
  for (int f = 0; f < rest.faceCount(); ++f) {
    if (cracking[f] && !onLip[f] && (!initiating || strains[f].strain > initiating->strain))
      initiating = strains[f];
  }
  modeling::CrackSeed seed{initiating ? initiating->face : critical->face,
                           initiating ? initiating->crackDirection : critical->crackDirection};
  FacePrincipalStrain start = initiating ? *initiating : *critical;
  for (const Eigen::Vector3d& point : openTips) {
    const std::vector<int> at = verticesAt(rest, point);
    if (at.size() != 1) continue;
    for (int f = 0; f < rest.faceCount(); ++f) {
      if (!cracking[f] || (rest.triangles.row(f).array() != at[0]).all()) continue;
      if (seed.tipVertex >= 0 && strains[f].strain <= start.strain) continue;
      start = strains[f];
      seed = {f, Eigen::Vector3d::Zero(), at[0]};
    }
  }
  if (seed.tipVertex < 0 && !initiating) return std::nullopt;
  if (seed.tipVertex < 0 && !openTips.empty()) {
    // One crack front per piece: a piece with an open tip cracks only from it.
    const std::vector<int> component = modeling::vertexComponents(criterion.stencils());
    const int piece = component[rest.triangles(seed.face, 0)];
    for (const Eigen::Vector3d& point : openTips) {
      const std::vector<int> at = verticesAt(rest, point);
      if (at.size() == 1 && component[at[0]] == piece) return std::nullopt;
    }
  }
  if (seed.tipVertex >= 0) {
    seed.direction = tipCrackDirection(rest, faceStrain, options.thickness, seed.tipVertex,
                                       seed.face, start.fibre);
    if (seed.direction.dot(awayFromCrack(rest, seed.tipVertex)) < 0.0) seed.direction *= -1.0;
    start.crackDirection = seed.direction;
  }
  return CrackStart{seed, start, std::move(cracking)};
}

}  // namespace

std::optional<FracturedShell> fractureShell(const FractureCriterion& criterion, const Positions& x,
                                            const Positions& v, const std::vector<bool>& heldVertex,
                                            const FractureOptions& options,
                                            const std::vector<Eigen::Vector3d>& openTips) {
  const Mesh& rest = criterion.rest();
  if (v.rows() != rest.vertexCount() ||
      (!heldVertex.empty() && static_cast<int>(heldVertex.size()) != rest.vertexCount())) {
    throw InputError("fracture: the velocities or held vertices do not match the rest mesh's " +
                     std::to_string(rest.vertexCount()) + " vertices");
  }
  const std::optional<CrackStart> begin = crackStart(criterion, x, options, openTips);
  if (!begin) return std::nullopt;
  FracturedShell shell;
  shell.critical = begin->strain;
  shell.cut = modeling::cutAlongCrack(rest, x, begin->seed, begin->cracking);
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
  std::vector<Eigen::Vector3d> candidates = openTips;
  const Eigen::Index ends = shell.cut.crackRest.rows();
  if (ends > 0) {
    candidates.push_back(shell.cut.crackRest.row(0).transpose());
    candidates.push_back(shell.cut.crackRest.row(ends - 1).transpose());
  }
  shell.openTips = openCrackTips(shell.rest, candidates);
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

namespace {

// Moves each vertex of `twins` (free ones: `held` empty or false) by `gap` towards the mean of its
// faces' centroids in `x` (the same faces in every configuration).
int moveIntoFans(const std::vector<int>& twins, const modeling::Triangles& faces,
                 const std::vector<std::vector<int>>& fans, const std::vector<bool>& held,
                 double gap, modeling::Positions& x) {
  int moved = 0;
  std::vector<Eigen::RowVector3d> to;
  for (const int v : twins) {
    Eigen::RowVector3d centre = Eigen::RowVector3d::Zero();
    for (const int f : fans[v])
      centre += (x.row(faces(f, 0)) + x.row(faces(f, 1)) + x.row(faces(f, 2))) / 3.0;
    const Eigen::RowVector3d inward = centre / std::max<double>(1.0, fans[v].size()) - x.row(v);
    const bool moves = !fans[v].empty() && (held.empty() || !held[v]) && inward.norm() > 0.0;
    to.push_back(moves ? Eigen::RowVector3d(x.row(v) + gap * inward.normalized()) : x.row(v));
    moved += moves;
  }
  for (std::size_t k = 0; k < twins.size(); ++k) x.row(twins[k]) = to[k];
  return moved;
}

}  // namespace

int openLips(FracturedShell& shell, const modeling::Positions& carriedRest, double gap) {
  const modeling::Positions& cutRest = shell.rest.positions;  // lips coincide
  if (carriedRest.rows() != cutRest.rows() || carriedRest.cols() != 3)
    throw InputError("openLips: the carried rest positions have " +
                     std::to_string(carriedRest.rows()) + " rows, the cut mesh " +
                     std::to_string(cutRest.rows()) + " vertices");
  const modeling::Triangles& faces = shell.rest.triangles;
  std::vector<std::vector<int>> fans(cutRest.rows());
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) fans[faces(f, k)].push_back(static_cast<int>(f));
  // The vertices at each point of the cut rest mesh, and among them the fresh twins: those that
  // also share their position (a cut's copies; a lip of an earlier cut is where the run took it,
  // and a crack through it makes twins of one of its sides only).
  using Point = std::array<double, 3>;
  const auto point = [](const modeling::Positions& x, int v) {
    return Point{x(v, 0), x(v, 1), x(v, 2)};
  };
  std::map<std::pair<Point, Point>, std::vector<int>> twinsAt;
  for (Eigen::Index v = 0; v < cutRest.rows(); ++v) {
    const int i = static_cast<int>(v);
    twinsAt[{point(cutRest, i), point(shell.positions, i)}].push_back(i);
  }
  modeling::Positions opened = carriedRest;
  int moved = 0;
  for (const auto& [where, twins] : twinsAt) {
    if (twins.size() < 2) continue;
    moved += moveIntoFans(twins, faces, fans, shell.heldVertex, gap, shell.positions);
    moveIntoFans(twins, faces, fans, shell.heldVertex, gap, opened);
  }
  shell.rest.positions = std::move(opened);
  return moved;
}

}  // namespace flexure::optimize
