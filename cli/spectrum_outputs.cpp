#include "cli/spectrum_outputs.h"

#include <iostream>

namespace flexure::cli {

std::string runSpectrumStudyInto(const optimize::SpectrumStudyOptions& o, const std::string& dir,
                                 const GlobalOptions& global, const std::string& commandName) {
  o.validate();
  const std::vector<optimize::SpectrumSeries> all =
      optimize::runSpectrumStudy(o, [&](const std::string& done) {
        if (!global.quiet) std::cerr << commandName << ": " << done << '\n';
      });
  return reports::writeSpectrumOutputs(o, all, dir);
}

}  // namespace flexure::cli
