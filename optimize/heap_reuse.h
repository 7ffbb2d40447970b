// The solves allocate and free buffers of 10–100 MB many times (Jacobians, normal matrices,
// CHOLMOD's factors and workspaces, Ceres' per-iteration storage). glibc serves blocks above its
// mmap threshold (at most 32 MB, adapting) from fresh pages and unmaps them on free, so every
// such buffer pays its page faults again; on these virtual machines that was a quarter of a
// linearized solve. Programs that solve call this once at start: big blocks then come from the
// heap, and freed memory stays there for the next one. Measured on the 4-8 patch, n = 512:
// triavg linearized 15.8 → 12.0 s, hinge nonlinear 21.6 → 18.5 s, peak memory +2 %.
#pragma once

namespace flexure::optimize {

void reuseFreedMemory();

}  // namespace flexure::optimize
