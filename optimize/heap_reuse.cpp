#include "optimize/heap_reuse.h"

#include <malloc.h>

namespace flexure::optimize {

void reuseFreedMemory() {
  constexpr int kGiB = 1 << 30;
  mallopt(M_MMAP_THRESHOLD, kGiB);  // blocks below 1 GiB come from the heap
  mallopt(M_TRIM_THRESHOLD, kGiB);  // and up to 1 GiB of freed heap stays mapped for reuse
}

}  // namespace flexure::optimize
