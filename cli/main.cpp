#include <exception>
#include <iostream>

#include "cli/commands.h"
#include "optimize/heap_reuse.h"

int main(int argc, char** argv) {
  flexure::optimize::reuseFreedMemory();
  try {
    return flexure::cli::runFlexure(std::vector<std::string>(argv, argv + argc));
  } catch (const std::exception& e) {
    std::cerr << "flexure: internal error: " << e.what() << "\nplease report this as a bug\n";
    return 1;
  }
}
