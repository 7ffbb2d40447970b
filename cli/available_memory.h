// The memory a new allocation can get, for the commands that refuse a job that cannot fit before
// they start it (`flexure mesh`, `flexure converge`).
#pragma once

namespace flexure::cli {

// In bytes, or 0 when unknown: the least of the kernel's MemAvailable (what can be used without
// swapping), the address-space limit (ulimit -v) less what the process already maps, and a
// cgroup's memory limit (v2 memory.max, v1 limit_in_bytes) less its usage — a job under a cap
// fails at the cap, not at the machine's size.
double availableMemoryBytes();

}  // namespace flexure::cli
