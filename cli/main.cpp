#include <glog/logging.h>

#include <exception>
#include <iostream>
#include <new>

#include "cli/commands.h"
#include "modeling/errors.h"
#include "optimize/linear/heap_reuse.h"

int main(int argc, char** argv) {
  flexure::optimize::reuseFreedMemory();
  // Ceres logs through glog; initialized here so that glog writes no log files and no "logging
  // before InitGoogleLogging" line. runFlexure sets how much of it shows (--verbose).
  FLAGS_logtostderr = true;
  FLAGS_minloglevel = google::GLOG_FATAL;
  google::InitGoogleLogging(argv[0]);
  try {
    return flexure::cli::runFlexure(std::vector<std::string>(argv, argv + argc));
  } catch (const std::bad_alloc&) {
    std::cerr << "flexure: out of memory: the job needs more memory than this machine has "
                 "available\n";
    return flexure::kExitNumericalError;
  } catch (const std::exception& e) {
    std::cerr << "flexure: internal error: " << e.what() << "\nplease report this as a bug\n";
    return 1;
  }
}
