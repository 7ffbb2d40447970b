#include "optimize/biharmonic.h"

#include <Eigen/CholmodSupport>

#include "modeling/errors.h"

namespace flexure::optimize {

SparseMatrix cotanLaplacian(const modeling::Stencils& s, const modeling::RestState& rest) {
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(12 * s.faceCount());
  for (int f = 0; f < s.faceCount(); ++f) {
    const double twiceArea = 2.0 * rest.faceAreas[f];
    for (int i = 0; i < 3; ++i) {
      // The angle at vertex i is opposite edge i = (v_{i+1}, v_{i+2}): it weights that edge.
      const int a = s.faces(f, (i + 1) % 3), b = s.faces(f, (i + 2) % 3), c = s.faces(f, i);
      const Eigen::Vector3d u = rest.positions.row(a) - rest.positions.row(c);
      const Eigen::Vector3d w = rest.positions.row(b) - rest.positions.row(c);
      const double halfCot = 0.5 * u.dot(w) / twiceArea;
      entries.emplace_back(a, b, halfCot);
      entries.emplace_back(b, a, halfCot);
      entries.emplace_back(a, a, -halfCot);
      entries.emplace_back(b, b, -halfCot);
    }
  }
  SparseMatrix laplacian(s.vertexCount(), s.vertexCount());
  laplacian.setFromTriplets(entries.begin(), entries.end());
  return laplacian;
}

Eigen::VectorXd solveBiharmonic(const modeling::Stencils& s, const modeling::RestState& rest,
                                const std::vector<bool>& fixedVertex,
                                const Eigen::VectorXd& values) {
  const SparseMatrix laplacian = cotanLaplacian(s, rest);
  const Eigen::VectorXd inverseArea = rest.vertexVoronoiAreas.cwiseInverse();
  // Bi-Laplacian B = Lᵀ M⁻¹ L, split into free and fixed columns.
  const Eigen::SparseMatrix<double> bilaplacian =
      Eigen::SparseMatrix<double>(laplacian.transpose()) * inverseArea.asDiagonal() * laplacian;
  std::vector<int> index(s.vertexCount(), -1);
  int freeCount = 0;
  for (int v = 0; v < s.vertexCount(); ++v)
    if (!fixedVertex[v]) index[v] = freeCount++;
  std::vector<Eigen::Triplet<double>> freeEntries;
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(freeCount);
  for (int col = 0; col < bilaplacian.outerSize(); ++col) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(bilaplacian, col); it; ++it) {
      const int row = index[it.row()];
      if (row < 0) continue;
      if (index[col] >= 0) {
        freeEntries.emplace_back(row, index[col], it.value());
      } else {
        rhs[row] -= it.value() * values[col];
      }
    }
  }
  Eigen::SparseMatrix<double> system(freeCount, freeCount);
  system.setFromTriplets(freeEntries.begin(), freeEntries.end());
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>> cholesky(system);
  const Eigen::VectorXd freeValues = cholesky.solve(rhs);
  if (cholesky.info() != Eigen::Success)
    throw NumericalError("the bi-Laplacian system is singular: fix more vertices");
  Eigen::VectorXd out = values;
  for (int v = 0; v < s.vertexCount(); ++v)
    if (index[v] >= 0) out[v] = freeValues[index[v]];
  return out;
}

}  // namespace flexure::optimize
