#include "cli/command_files.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <thread>

#include "modeling/atomic_write.h"
#include "modeling/errors.h"
#include "modeling/polynomial_surface.h"

namespace flexure::cli {
namespace {

namespace fs = std::filesystem;

// "-o,--output" → "--output": the long name, which the help lists.
std::string optionLabel(const std::string& names) {
  std::string label, name;
  std::istringstream in(names);
  while (std::getline(in, name, ',')) {
    if (label.empty() || name.rfind("--", 0) == 0) label = name;
  }
  return label;
}

// Empty when a file can be created in `dir`, else why not. Creating (and removing) a probe file is
// the only reliable test: access(2) says yes to root for read-only or virtual file systems (/proc).
std::string whyNotWritable(const fs::path& dir) {
  std::string pattern = (dir / ".flexure-probe.XXXXXX").string();
  std::vector<char> name(pattern.begin(), pattern.end());
  name.push_back('\0');
  const int fd = ::mkstemp(name.data());
  if (fd < 0) return std::strerror(errno);
  ::close(fd);
  ::unlink(name.data());
  return "";
}

fs::path directoryOf(const std::string& path) {
  const fs::path p(path);
  return p.has_parent_path() ? p.parent_path() : fs::path(".");
}

bool sameFile(const std::string& a, const std::string& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec);
  return fs::weakly_canonical(a, ec) == fs::weakly_canonical(b, ec);
}

void checkFileOutput(const std::string& option, const std::string& path,
                     bool directoriesMayAppear) {
  const std::string where = option + " " + path;
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw InputError(where + ": is a directory; give a file name");
  const fs::path dir = directoryOf(path);
  if (!fs::exists(dir, ec) && directoriesMayAppear) return;
  if (!fs::exists(dir, ec))
    throw InputError(where + ": directory '" + dir.string() + "' does not exist; create it first");
  if (!fs::is_directory(dir, ec))
    throw InputError(where + ": '" + dir.string() + "' is not a directory");
  const std::string why = whyNotWritable(dir);
  if (!why.empty())
    throw InputError(where + ": cannot create a file in '" + dir.string() + "' (" + why + ")");
}

void checkDirectoryOutput(const std::string& option, const std::string& path) {
  const std::string where = option + " " + path;
  std::error_code ec;
  fs::path existing = fs::path(path).lexically_normal();
  while (!existing.empty() && !fs::exists(existing, ec)) existing = existing.parent_path();
  if (existing.empty()) existing = ".";
  if (!fs::is_directory(existing, ec)) {
    throw InputError(where + ": '" + existing.string() + "' is a file, not a directory");
  }
  const std::string why = whyNotWritable(existing);
  if (!why.empty())
    throw InputError(where + ": cannot create files in '" + existing.string() + "' (" + why + ")");
}

}  // namespace

std::shared_ptr<CommandFiles> CommandFiles::of(CLI::App& sub) {
  return std::shared_ptr<CommandFiles>(new CommandFiles(sub));
}

CLI::Option* CommandFiles::input(const std::string& names, std::string& path,
                                 const std::string& help) {
  inputs_.push_back({optionLabel(names), &path, nullptr, OutputKind::File});
  return sub_.add_option(names, path, help);
}

CLI::Option* CommandFiles::inputs(const std::string& names, std::vector<std::string>& paths,
                                  const std::string& help) {
  inputs_.push_back({optionLabel(names), nullptr, &paths, OutputKind::File});
  return sub_.add_option(names, paths, help);
}

CLI::Option* CommandFiles::output(const std::string& names, std::string& path,
                                  const std::string& help, OutputKind kind, OwnedFiles owned) {
  outputs_.push_back({optionLabel(names), &path, nullptr, kind, std::move(owned)});
  return sub_.add_option(names, path, help);
}

void CommandFiles::onRun(const GlobalOptions& global, std::function<void()> run) {
  const bool fileOutput = std::any_of(outputs_.begin(), outputs_.end(),
                                      [](const Declared& d) { return d.kind == OutputKind::File; });
  if (!inputs_.empty() && fileOutput)
    sub_.add_flag("--force", force_, "Write an output even when it is one of the input files");
  sub_.callback([self = shared_from_this(), &global, run = std::move(run)] {
    self->check(global.checkOnly);
    if (global.checkOnly) return;
    run();
    self->removeStaleFiles();
  });
}

void CommandFiles::removeStaleFiles() const {
  std::vector<fs::path> written;
  for (const std::string& target : modeling::stagedOutputs())
    written.push_back(fs::weakly_canonical(target));
  for (const Declared& out : outputs_) {
    if (out.kind != OutputKind::Directory || !out.owned || out.path->empty()) continue;
    std::error_code ec;
    for (const fs::directory_entry& entry : fs::directory_iterator(*out.path, ec)) {
      if (!entry.is_regular_file(ec) || !out.owned(entry.path().filename().string())) continue;
      const fs::path file = fs::weakly_canonical(entry.path());
      if (std::find(written.begin(), written.end(), file) == written.end())
        modeling::removeWhenCommitted(entry.path().string());
    }
  }
}

void CommandFiles::check(bool directoriesMayAppear) const {
  std::vector<std::pair<std::string, std::string>> inputFiles;  // option, path
  for (const Declared& in : inputs_) {
    if (in.path && !in.path->empty()) inputFiles.emplace_back(in.option, *in.path);
    if (in.paths)
      for (const std::string& p : *in.paths) inputFiles.emplace_back(in.option, p);
  }
  std::vector<std::pair<std::string, std::string>> checked;
  for (const Declared& out : outputs_) {
    const std::string& path = *out.path;
    if (path.empty()) continue;  // an optional output not asked for
    if (out.kind == OutputKind::File) {
      checkFileOutput(out.option, path, directoriesMayAppear);
    } else {
      checkDirectoryOutput(out.option, path);
    }
    for (const auto& [option, other] : checked) {
      if (sameFile(path, other))
        throw InputError(out.option + " " + path + ": is also the file of " + option +
                         "; give each output its own name");
    }
    if (!force_) {
      for (const auto& [option, input] : inputFiles) {
        if (out.kind == OutputKind::File && sameFile(path, input)) {
          // "the input --rest a.obj", "the input mesh a.off"; a positional named input once.
          const std::string named = option == "input" ? "" : option + " ";
          throw InputError(out.option + " " + path + ": would overwrite the input " + named +
                           input + "; give another name, or --force to overwrite it");
        }
      }
    }
    checked.emplace_back(out.option, path);
  }
}

int maxThreads() {
  return 4 * static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

CLI::Validator inRange(double lo, double hi) {
  std::ostringstream range;
  range << lo << " .. " << hi;
  const std::string text = range.str();
  return CLI::Validator(
      [lo, hi, text](std::string& value) -> std::string {
        double x = 0.0;
        if (!CLI::detail::lexical_cast(value, x) || !(x >= lo && x <= hi))
          return value + " is out of range: expected " + text;
        return "";
      },
      "in " + text);
}

CLI::Validator positive() {
  return CLI::Validator(
      [](std::string& value) -> std::string {
        double x = 0.0;
        if (!CLI::detail::lexical_cast(value, x) || !(x > 0.0))
          return value + " is out of range: expected a number > 0";
        return "";
      },
      "> 0");
}

CLI::Validator seedValue() {
  return CLI::Validator(
      [](std::string& value) -> std::string {
        // CLI11's conversion (strtoull) wraps "-5" around to 2^64 - 5 and saturates 2^64.
        std::uint64_t seed = 0;
        const char* end = value.data() + value.size();
        const auto [stop, error] = std::from_chars(value.data(), end, seed);
        if (value.empty() || error != std::errc() || stop != end)
          return value + " is not a seed: expected an integer in [0, 18446744073709551615]";
        return "";
      },
      "0 .. 2^64-1");
}

CLI::Validator surfaceSpec() {
  return CLI::Validator(
      [](std::string& value) -> std::string {
        try {
          modeling::PolynomialSurface::parse(value);
        } catch (const InputError& e) {
          return e.what();
        }
        return "";
      },
      "quadratic:a,b,c | polynomial:EXPR");
}

}  // namespace flexure::cli
