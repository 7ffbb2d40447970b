#include "cli/available_memory.h"

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <utility>

namespace flexure::cli {
namespace {

// The first number after `key` in a /proc file ("MemAvailable:", "VmSize:"), in kB; -1 if none.
double procField(const char* file, const std::string& key) {
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::string name;
    double kilobytes = 0.0;
    if (fields >> name >> kilobytes && name == key) return kilobytes;
  }
  return -1.0;
}

}  // namespace

double availableMemoryBytes() {
  double available = std::numeric_limits<double>::infinity();
  if (const double kb = procField("/proc/meminfo", "MemAvailable:"); kb >= 0.0)
    available = kb * 1024.0;
  rlimit limit{};
  const double mapped = procField("/proc/self/status", "VmSize:") * 1024.0;
  if (::getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY && mapped >= 0.0)
    available = std::min(available, static_cast<double>(limit.rlim_cur) - mapped);
  const auto number = [](const char* file) {
    std::ifstream in(file);
    double value = -1.0;
    return in >> value ? value : -1.0;  // "max" (no limit) reads as -1
  };
  for (const auto& [max, current] :
       {std::pair{"/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory.current"},
        std::pair{"/sys/fs/cgroup/memory/memory.limit_in_bytes",
                  "/sys/fs/cgroup/memory/memory.usage_in_bytes"}}) {
    const double cap = number(max), used = number(current);
    if (cap > 0.0 && cap < 1e18 && used >= 0.0) available = std::min(available, cap - used);
  }
  return std::isfinite(available) ? std::max(available, 0.0) : 0.0;
}

}  // namespace flexure::cli
