#include "optimize/linear/linear_algebra_threads.h"

#include <dlfcn.h>

namespace flexure::optimize {
namespace {

std::recursive_mutex linearAlgebraMutex;

// The OpenMP functions this process has loaded, or nullptr.
struct OpenMp {
  int (*getMaxActiveLevels)() = nullptr;
  void (*setMaxActiveLevels)(int) = nullptr;

  static const OpenMp& get() {
    static const OpenMp r = [] {
      OpenMp found;
      found.getMaxActiveLevels =
          reinterpret_cast<int (*)()>(dlsym(RTLD_DEFAULT, "omp_get_max_active_levels"));
      found.setMaxActiveLevels =
          reinterpret_cast<void (*)(int)>(dlsym(RTLD_DEFAULT, "omp_set_max_active_levels"));
      if (found.getMaxActiveLevels == nullptr) found.setMaxActiveLevels = nullptr;
      // Once, under the lock of the first section and so before any of flexure's BLAS calls.
      if (const auto setThreads =
              reinterpret_cast<void (*)(int)>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads")))
        setThreads(1);
      return found;
    }();
    return r;
  }
};

}  // namespace

SingleThreadedLinearAlgebra::SingleThreadedLinearAlgebra() : lock_(linearAlgebraMutex) {
  const OpenMp& omp = OpenMp::get();
  if (omp.setMaxActiveLevels == nullptr) return;
  levels_ = omp.getMaxActiveLevels();
  omp.setMaxActiveLevels(0);
}

SingleThreadedLinearAlgebra::~SingleThreadedLinearAlgebra() {
  const OpenMp& omp = OpenMp::get();
  if (omp.setMaxActiveLevels != nullptr) omp.setMaxActiveLevels(levels_);
}

}  // namespace flexure::optimize
