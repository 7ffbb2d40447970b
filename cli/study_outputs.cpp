#include "cli/study_outputs.h"

#include <unistd.h>

#include <cstdio>
#include <string>

#include "cli/available_memory.h"
#include "modeling/atomic_write.h"
#include "modeling/errors.h"

namespace flexure::cli {
namespace {

// A bar on a terminal, else a line per tenth of the cases; nothing when quiet.
class ProgressReporter {
 public:
  ProgressReporter(const GlobalOptions& global, std::string commandName)
      : quiet_(global.quiet),
        terminal_(isatty(fileno(stderr)) == 1),
        name_(std::move(commandName)) {}

  void operator()(const optimize::StudyProgress& p) {
    if (quiet_) return;
    if (!p.step.empty()) {  // inside a long case: a line of its own, on a terminal too
      std::fprintf(stderr, "%s%s: %s: %s\n", terminal_ ? "\n" : "", name_.c_str(),
                   p.running.c_str(), p.step.c_str());
      std::fflush(stderr);
      return;
    }
    if (terminal_) {
      constexpr int kWidth = 30;
      const int filled = p.total > 0 ? p.done * kWidth / p.total : kWidth;
      std::string label = p.finished;
      if (label.size() > 48) label = label.substr(0, 45) + "...";
      std::fprintf(stderr, "\r%s [%s%s] %d/%d  %-48s", name_.c_str(),
                   std::string(filled, '#').c_str(), std::string(kWidth - filled, '.').c_str(),
                   p.done, p.total, label.c_str());
      if (p.done == p.total) std::fprintf(stderr, "\n");
      std::fflush(stderr);
      return;
    }
    const int tenth = p.total > 0 ? p.done * 10 / p.total : 10;
    if (tenth > lastTenth_ || p.done == p.total) {
      lastTenth_ = tenth;
      std::fprintf(stderr, "%s: %d/%d cases (%d%%)\n", name_.c_str(), p.done, p.total,
                   p.total > 0 ? p.done * 100 / p.total : 100);
    }
  }

 private:
  bool quiet_, terminal_;
  std::string name_;
  int lastTenth_ = 0;
};

// Refuses a study whose peak memory (optimize::estimateStudyMemory) exceeds what is available,
// before any mesh is made.
void requireMemoryFor(const optimize::StudyOptions& options) {
  const optimize::StudyMemoryEstimate estimate = optimize::estimateStudyMemory(options);
  const double available = availableMemoryBytes();
  if (available <= 0.0 || estimate.peakBytes <= available) return;
  char text[512];
  std::snprintf(
      text, sizeof text,
      "--n %d --levels %d: the study needs about %.3g GB of memory, more than the %.1f GB "
      "available: its largest case, %s (%.3g vertices), about %.3g GB%s; give a smaller "
      "--n or fewer --levels%s",
      options.baseN, options.levels, estimate.peakBytes / 1e9, available / 1e9,
      estimate.largestCase.c_str(), estimate.largestCaseVertices, estimate.largestCaseBytes / 1e9,
      estimate.concurrent > 1
          ? (", " + std::to_string(estimate.concurrent) + " cases at a time (--threads)").c_str()
          : "",
      estimate.concurrent > 1 ? ", or --threads 1" : "");
  throw InputError(text);
}

}  // namespace

std::string runStudyInto(const optimize::StudyOptions& options, const std::string& dir,
                         const GlobalOptions& global, const std::string& commandName) {
  options.validate();  // bad options fail before the directory is made
  requireMemoryFor(options);
  modeling::createOutputDirectory(dir);
  ProgressReporter reporter(global, commandName);
  const optimize::StudyResults results = optimize::runConvergenceStudy(
      options, [&](const optimize::StudyProgress& p) { reporter(p); });
  const optimize::StudySummary summary = optimize::summarizeStudy(options, results);
  return reports::writeStudyOutputs(options, results, summary, dir);
}

}  // namespace flexure::cli
