// A fill-reducing order for the sparse Cholesky factorizations of flexure's nonlinear solves.
//
// Ceres 2.1 orders SPARSE_NORMAL_CHOLESKY by AMD on the parameter-block graph. The normal
// matrices of the vertex-only energies are graph-Laplacian-like (a vertex couples to its one or
// two rings), where nested dissection (METIS) leaves less fill. Ceres takes no METIS order, but it
// takes a partition of the parameter blocks into ordered groups and then runs constrained AMD
// (CAMD) within them: a nested-dissection order cut into a few hundred consecutive groups hands
// Ceres the separators' order while CAMD orders each group's interior. Measured in one run of
// `solve_bench --sizes 256,512 --energies hinge,cotan,quadfit --baselines` (mode nonlinear_amd =
// Ceres' AMD), nonlinear solve at n = 512, AMD total / nested-dissection total: cotan 1.34
// (57.6 vs 43.0 s; 1.22 at n = 256), hinge 0.99 and quadfit 1.00 — their linear solver gains
// (19.6 → 17.1 s, 33.5 → 29.0 s) go to computing the order (2–3 s). Problems with midedge ξ keep
// Ceres' AMD: with the ξ as graph nodes the solve at n = 512 took 124–143 s against 120 s (METIS
// on 10⁶ nodes alone took 18 s), and with each ξ placed in the group of its latest vertex the
// factorizations took 697 s (separate runs). The one-shot linearized solves keep CHOLMOD's own
// choice: METIS there cost more analysis than it saved (n = 512, separate runs, linear-solver
// seconds METIS vs AMD: hinge 4.3 vs 3.9, triavg 8.8 vs 7.4, midedge 30.4 vs 24.2, cotan 6.3 vs
// 6.8).
#pragma once

#include <ceres/ordered_groups.h>
#include <ceres/problem.h>

#include <memory>

namespace flexure::optimize {

// Smaller problems keep AMD: ordering them is cheap either way.
inline constexpr int kNestedDissectionMinBlocks = 20000;

// Ceres' elimination groups for `problem`: its free vertex blocks in METIS nested-dissection
// order of their coupling graph (two vertices are adjacent when a residual block reads both),
// cut into `groupCount` consecutive groups; constant blocks join the first group (Ceres removes
// them before ordering). nullptr (leave Ceres' AMD) below kNestedDissectionMinBlocks free blocks
// or when a free block is not a vertex (size 3), e.g. a midedge ξ.
std::shared_ptr<ceres::ParameterBlockOrdering> nestedDissectionGroups(const ceres::Problem& problem,
                                                                      int groupCount = 256);

}  // namespace flexure::optimize
