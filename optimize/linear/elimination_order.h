// Fill-reducing orders for flexure's sparse Cholesky factorizations.
//
// Nonlinear solves (Ceres): Ceres 2.1 orders SPARSE_NORMAL_CHOLESKY by AMD on the
// parameter-block graph. The normal matrices of the vertex-only energies are graph-Laplacian-like
// (a vertex couples to its one or two rings), where nested dissection (METIS) leaves less fill.
// Ceres takes no METIS order, but it takes a partition of the parameter blocks into ordered groups
// and then runs constrained AMD (CAMD) within them: a nested-dissection order cut into a few
// hundred consecutive groups hands Ceres the separators' order while CAMD orders each group's
// interior. Measured in one run of solve_bench (sizes 256 and 512; hinge, cotan, quadfit;
// with its baselines: mode nonlinear_amd = Ceres' AMD), nonlinear solve at n = 512, AMD total /
// nested-dissection total: cotan 1.34 (57.6 vs 43.0 s; 1.22 at n = 256), hinge 0.99 and quadfit
// 1.00 — their linear solver gains (19.6 → 17.1 s, 33.5 → 29.0 s) go to computing the order
// (2–3 s). The geometric nested dissection below, as Ceres' groups, takes 0.6–1.0 s instead of
// METIS' 2.1–3.0 s, but Ceres' factorizations took longer on it (n = 512, two interleaved runs
// each, total seconds geometric vs METIS: hinge 28.8, 27.1 vs 22.3, 24.9; cotan 39.0, 40.3 vs
// 36.0, 42.3), so Ceres keeps METIS. Problems with midedge ξ keep Ceres' AMD: with the ξ as
// graph nodes the solve at n = 512 took 124–143 s against 120 s (METIS on 10⁶ nodes alone took
// 18 s), and with each ξ placed in the group of its latest vertex the factorizations took 697 s
// (separate runs).
//
// Linearized solves (CHOLMOD, energy_evaluation.h): CHOLMOD by default tries AMD and then METIS
// on A Aᵀ; at n = 512 its analysis took 2.9 s of cotan's 7.6 s solve (METIS chosen) and 16 s of
// midedge's 34.6. Vertex-only problems now take the geometric nested dissection (cotan at
// n = 512: 3.98e7 factor nonzeros against METIS' 4.04e7, found in 0.3 s instead of 2.9 s), and
// problems with free ξ CHOLMOD's AMD alone (analysis 4.1 s, factorization 24 s vs METIS' 18.5 s:
// 28 s in all against 34.6).
#pragma once

#include <ceres/ordered_groups.h>
#include <ceres/problem.h>

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "optimize/assembly/incidence.h"

namespace flexure::optimize {

// A fill-reducing elimination order for the normal matrix AᵀA of a least-squares problem whose
// residuals read the nodes as `residuals` says (two nodes couple when a residual reads both),
// by geometric nested dissection (George 1973; Gilbert, Miller & Teng 1998) of the nodes placed
// at `points`: cut the nodes at the median of their longest bounding-box axis; the nodes of the
// lower half coupled to the upper half form the separator; order both halves the same way
// recursively, then the separator. Below `leafSize` nodes, the given order. On a surface mesh a
// plane meets the surface in a curve, so separators have O(√n) nodes, as METIS finds, at a small
// fraction of METIS' time. Returns order[k] = the node eliminated k-th.
std::vector<int> geometricNestedDissection(const std::vector<Eigen::Vector3d>& points,
                                           const Incidence& residuals, int leafSize = 8);

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
