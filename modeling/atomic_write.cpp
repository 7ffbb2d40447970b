#include "modeling/atomic_write.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

#include "modeling/errors.h"

namespace flexure::modeling {
namespace {

// The innermost open batch. Writers may run on worker threads (the convergence study's plots), so
// the pointer and the batches' lists are guarded by one mutex.
std::mutex batchMutex;
OutputBatch* currentBatch = nullptr;

// Writes `bytes` to a fresh temporary beside `path` (mode 0666 less the umask) and returns its
// name. Throws InputError naming `path`.
std::string writeTemporary(const std::string& path, std::string_view bytes) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    throw InputError(path + ": cannot write: directory '" + dir.string() + "' does not exist");
  }
  std::string pattern = (dir / ("." + target.filename().string() + ".tmp.XXXXXX")).string();
  std::vector<char> name(pattern.begin(), pattern.end());
  name.push_back('\0');
  const int fd = ::mkstemp(name.data());
  if (fd < 0) {
    throw InputError(path + ": cannot write: " + std::strerror(errno));
  }
  const std::string tmp(name.data());
  size_t written = 0;
  while (written < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + written, bytes.size() - written);
    if (n < 0) {
      if (errno == EINTR) continue;
      const std::string reason = std::strerror(errno);
      ::close(fd);
      ::unlink(tmp.c_str());
      throw InputError(path + ": cannot write: " + reason);
    }
    written += static_cast<size_t>(n);
  }
  // mkstemp creates the file 0600; outputs get the usual 0644 (less the umask).
  const mode_t mask = ::umask(0);
  ::umask(mask);
  ::fchmod(fd, 0666 & ~mask);
  if (::close(fd) != 0) {
    const std::string reason = std::strerror(errno);
    ::unlink(tmp.c_str());
    throw InputError(path + ": cannot write: " + reason);
  }
  return tmp;
}

void renameIntoPlace(const std::string& tmp, const std::string& path) {
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    ::unlink(tmp.c_str());
    throw InputError(path + ": cannot write: " + reason);
  }
}

}  // namespace

void writeFileNow(const std::string& path, std::string_view bytes) {
  renameIntoPlace(writeTemporary(path, bytes), path);
}

void writeFileAtomically(const std::string& path, std::string_view bytes) {
  const std::string tmp = writeTemporary(path, bytes);
  std::lock_guard<std::mutex> lock(batchMutex);
  if (currentBatch == nullptr) {
    renameIntoPlace(tmp, path);
    return;
  }
  // A target written twice keeps its last bytes.
  for (OutputBatch::Staged& s : currentBatch->staged_) {
    if (s.target == path) {
      ::unlink(s.temporary.c_str());
      s.temporary = tmp;
      return;
    }
  }
  currentBatch->staged_.push_back({tmp, path});
}

void createOutputDirectory(const std::string& dir) {
  namespace fs = std::filesystem;
  // The missing ancestors, outermost first, so that a rollback can remove exactly these.
  std::vector<std::string> missing;
  std::error_code ec;
  for (fs::path p = fs::path(dir).lexically_normal(); !p.empty() && !fs::exists(p, ec);
       p = p.parent_path()) {
    missing.insert(missing.begin(), p.string());
    if (p == p.parent_path()) break;
  }
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) {
    throw InputError(dir + ": cannot create the output directory" +
                     (ec ? " (" + ec.message() + ")" : std::string(" (a file is in the way)")));
  }
  std::lock_guard<std::mutex> lock(batchMutex);
  if (currentBatch != nullptr)
    for (const std::string& d : missing) currentBatch->createdDirectories_.push_back(d);
}

OutputBatch::OutputBatch() {
  std::lock_guard<std::mutex> lock(batchMutex);
  outer_ = currentBatch;
  currentBatch = this;
}

OutputBatch::~OutputBatch() {
  std::lock_guard<std::mutex> lock(batchMutex);
  currentBatch = outer_;
  if (done_) return;
  for (const Staged& s : staged_) ::unlink(s.temporary.c_str());
  // Innermost first; a directory that holds anything else (a user's file) stays.
  for (auto d = createdDirectories_.rbegin(); d != createdDirectories_.rend(); ++d)
    ::rmdir(d->c_str());
}

void OutputBatch::commit() {
  std::vector<Staged> staged;
  std::vector<std::string> removals;
  {
    std::lock_guard<std::mutex> lock(batchMutex);
    staged.swap(staged_);
    removals.swap(removals_);
    done_ = true;
  }
  for (const std::string& path : removals) std::remove(path.c_str());
  for (std::size_t k = 0; k < staged.size(); ++k) {
    try {
      renameIntoPlace(staged[k].temporary, staged[k].target);
    } catch (...) {
      for (std::size_t j = k + 1; j < staged.size(); ++j) ::unlink(staged[j].temporary.c_str());
      throw;
    }
  }
}

void removeWhenCommitted(const std::string& path) {
  std::lock_guard<std::mutex> lock(batchMutex);
  if (currentBatch == nullptr) {
    std::remove(path.c_str());
  } else {
    currentBatch->removals_.push_back(path);
  }
}

std::vector<std::string> stagedOutputs() {
  std::lock_guard<std::mutex> lock(batchMutex);
  std::vector<std::string> targets;
  if (currentBatch != nullptr)
    for (const OutputBatch::Staged& s : currentBatch->staged_) targets.push_back(s.target);
  return targets;
}

}  // namespace flexure::modeling
