// Outputs are written to a temporary file next to the target and renamed over it, so a failed
// run never leaves a half-written mesh, image or report. Inside an OutputBatch the renames wait
// for the batch's commit, so a failed run leaves none of its outputs at all.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace flexure::modeling {

// Writes `bytes` to `path` atomically. Throws InputError naming the path when the directory does
// not exist or is not writable; the target is untouched on failure. Inside an OutputBatch the file
// is staged: written to its temporary now, renamed into place at the batch's commit().
void writeFileAtomically(const std::string& path, std::string_view bytes);

// Writes `bytes` to `path` atomically at once, even inside an OutputBatch: for the report of a
// failed run, which says why the run failed and so must outlive the failure.
void writeFileNow(const std::string& path, std::string_view bytes);

// Creates the directory `dir` and its missing parents. Inside an OutputBatch, the directories it
// made are removed again (when still empty) if the batch is not committed. Throws InputError
// naming `dir` when it cannot be made.
void createOutputDirectory(const std::string& dir);

// Removes the file `path` when the innermost OutputBatch commits (at once outside a batch): a
// stale output of an earlier run goes only when this run succeeds.
void removeWhenCommitted(const std::string& path);

// The targets staged in the innermost OutputBatch so far (empty outside a batch).
std::vector<std::string> stagedOutputs();

// One run's outputs, all or nothing. While a batch is open, writeFileAtomically stages into the
// innermost one; commit() renames every staged file into place, and a batch destroyed without
// commit() (an exception, an exit 2 or 3) removes its temporaries and the directories it made.
// Batches nest, each committed on its own: `flexure run` opens one per step, so that a step reads
// the files an earlier step wrote.
class OutputBatch {
 public:
  OutputBatch();
  ~OutputBatch();
  OutputBatch(const OutputBatch&) = delete;
  OutputBatch& operator=(const OutputBatch&) = delete;

  // Renames the staged files into place in the order they were written. Throws InputError naming
  // the file a rename fails for (the files renamed before it stay).
  void commit();

 private:
  friend void writeFileAtomically(const std::string&, std::string_view);
  friend void createOutputDirectory(const std::string&);
  friend void removeWhenCommitted(const std::string&);
  friend std::vector<std::string> stagedOutputs();
  struct Staged {
    std::string temporary, target;
  };
  std::vector<Staged> staged_;
  std::vector<std::string> createdDirectories_;  // outermost first
  std::vector<std::string> removals_;
  OutputBatch* outer_;
  bool done_ = false;
};

}  // namespace flexure::modeling
