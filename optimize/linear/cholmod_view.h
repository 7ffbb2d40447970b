// CHOLMOD views (no copies) of flexure's compressed-column arrays, for the calls Eigen's
// CholmodSupport does not wrap (factoring A Aᵀ from A, METIS orderings).
#pragma once

#include <cholmod.h>

#include <vector>

namespace flexure::optimize {

// The rows × (columnStart.size() − 1) matrix whose column j holds rows rowIndex[columnStart[j] ..
// columnStart[j + 1]) (sorted or not), with `values` alongside, or a pattern when values is
// nullptr. Unsymmetric (stype 0): CHOLMOD's orderings and factorizations then work on A Aᵀ.
// The arrays must outlive the view.
inline cholmod_sparse cholmodView(size_t rows, std::vector<int>& columnStart,
                                  std::vector<int>& rowIndex, double* values, bool sorted) {
  cholmod_sparse view{};
  view.nrow = rows;
  view.ncol = columnStart.size() - 1;
  view.nzmax = rowIndex.size();
  view.p = columnStart.data();
  view.i = rowIndex.data();
  view.x = values;
  view.stype = 0;
  view.itype = CHOLMOD_INT;
  view.xtype = values != nullptr ? CHOLMOD_REAL : CHOLMOD_PATTERN;
  view.dtype = CHOLMOD_DOUBLE;
  view.sorted = sorted;
  view.packed = 1;
  return view;
}

}  // namespace flexure::optimize
