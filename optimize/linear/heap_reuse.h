// The solves allocate and free buffers of 10–100 MB many times (Jacobians, normal matrices,
// CHOLMOD's factors and workspaces). glibc serves blocks above its mmap threshold (at most 32 MB,
// adapting) from fresh pages and unmaps them on free, so every such buffer pays its page faults
// again, which on these virtual machines is slow. Programs that solve call this once at start:
// big blocks then come from the heap and reuse its pages. Measured on the 4-8 patch, n = 512,
// three runs each: triavg linearized 15.8–19.3 s → 12.7–13.2 s; hinge nonlinear unchanged
// (22.0 s); peak memory unchanged.
#pragma once

namespace flexure::optimize {

void reuseFreedMemory();

}  // namespace flexure::optimize
