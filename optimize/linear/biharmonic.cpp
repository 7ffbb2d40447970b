#include "optimize/linear/biharmonic.h"

#include <Eigen/CholmodSupport>

#include "modeling/errors.h"
#include "optimize/linear/linear_algebra_threads.h"

namespace flexure::optimize {

SparseMatrix cotanLaplacian(const modeling::Stencils& s, const modeling::RestState& rest) {
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(12 * s.faceCount());
  for (int f = 0; f < s.faceCount(); ++f) {
    for (int i = 0; i < 3; ++i) {
      // The angle at vertex i is opposite edge i = (v_{i+1}, v_{i+2}): it weights that edge.
      const int a = s.faces(f, (i + 1) % 3), b = s.faces(f, (i + 2) % 3);
      const double halfCot = 0.5 * rest.faceCotangents(f, i);
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

BiharmonicSystem assembleBiharmonic(const modeling::Stencils& s, const modeling::RestState& rest,
                                    const std::vector<bool>& fixedVertex,
                                    const Eigen::VectorXd& values) {
  const SparseMatrix laplacian = cotanLaplacian(s, rest);
  const Eigen::VectorXd inverseArea = rest.vertexVoronoiAreas.cwiseInverse();
  const Eigen::SparseMatrix<double> bilaplacian =
      Eigen::SparseMatrix<double>(laplacian.transpose()) * inverseArea.asDiagonal() * laplacian;
  BiharmonicSystem system;
  system.freeIndex.assign(s.vertexCount(), -1);
  int freeCount = 0;
  for (int v = 0; v < s.vertexCount(); ++v)
    if (!fixedVertex[v]) system.freeIndex[v] = freeCount++;
  std::vector<Eigen::Triplet<double>> entries;
  system.rhs = Eigen::VectorXd::Zero(freeCount);
  for (int col = 0; col < bilaplacian.outerSize(); ++col) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(bilaplacian, col); it; ++it) {
      const int row = system.freeIndex[it.row()];
      if (row < 0) continue;
      if (system.freeIndex[col] >= 0) {
        entries.emplace_back(row, system.freeIndex[col], it.value());
      } else {
        system.rhs[row] -= it.value() * values[col];
      }
    }
  }
  system.matrix.resize(freeCount, freeCount);
  system.matrix.setFromTriplets(entries.begin(), entries.end());
  return system;
}

Eigen::VectorXd solveBiharmonic(const modeling::Stencils& s, const modeling::RestState& rest,
                                const std::vector<bool>& fixedVertex,
                                const Eigen::VectorXd& values) {
  const BiharmonicSystem system = assembleBiharmonic(s, rest, fixedVertex, values);
  const SingleThreadedLinearAlgebra oneThread;
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>> cholesky(system.matrix);
  const Eigen::VectorXd freeValues = cholesky.solve(system.rhs);
  if (cholesky.info() != Eigen::Success)
    throw NumericalError("the bi-Laplacian system is singular: fix more vertices");
  Eigen::VectorXd out = values;
  for (int v = 0; v < s.vertexCount(); ++v)
    if (system.freeIndex[v] >= 0) out[v] = freeValues[system.freeIndex[v]];
  return out;
}

}  // namespace flexure::optimize
