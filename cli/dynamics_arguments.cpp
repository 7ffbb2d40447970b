#include "cli/dynamics_arguments.h"

#include <Eigen/Core>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <vector>

#include "modeling/errors.h"
#include "optimize/boundary_conditions.h"

namespace flexure::cli {

optimize::PinMotion parsePinMotion(const std::string& spec, const std::string& option) {
  using optimize::PinMotion;
  const auto colon = spec.find(':');
  const std::string kind = spec.substr(0, colon);
  const std::string expected = ": expected rotate:ax,ay,az,px,py,pz,omega or translate:vx,vy,vz";
  const int count = kind == "rotate" ? 7 : kind == "translate" ? 3 : 0;
  if (colon == std::string::npos || count == 0) throw InputError(option + " " + spec + expected);
  std::vector<double> value;
  const std::string numbers = spec.substr(colon + 1);
  const char* cursor = numbers.c_str();
  for (int k = 0; k < count; ++k) {
    char* end = nullptr;
    value.push_back(std::strtod(cursor, &end));
    if (end == cursor || (k < count - 1 && *end != ',') || (k == count - 1 && *end != '\0') ||
        !std::isfinite(value.back()))
      throw InputError(option + " " + spec + expected + " (" + std::to_string(count) +
                       " finite numbers)");
    cursor = end + 1;
  }
  try {
    if (kind == "translate") return PinMotion::translation({value[0], value[1], value[2]});
    return PinMotion::rotation({value[0], value[1], value[2]}, {value[3], value[4], value[5]},
                               value[6]);
  } catch (const InputError& e) {
    throw InputError(option + " " + spec + ": " + e.what());
  }
}

namespace {

// A --pin text split at its '@'s: the set, the motion and the release (each empty when none).
struct PinSpec {
  std::string set, motion, release;  // release: the text "release:T"
  std::string option;                // "--pin SPEC", with "(group k)" when several are given
};

// SET[@MOTION][@release:T]: the parts after the set, each a motion or a release, at most one of
// each (InputError naming the option otherwise).
void splitPinTail(const std::string& spec, std::size_t at, PinSpec& g) {
  while (at != std::string::npos) {
    const std::size_t next = spec.find('@', at + 1);
    const std::string part = spec.substr(at + 1, next == std::string::npos ? next : next - at - 1);
    if (part.empty())
      throw InputError(g.option + " " + spec +
                       ": nothing after '@': expected SET[@MOTION][@release:T]");
    std::string& slot = part.rfind("release:", 0) == 0 ? g.release : g.motion;
    if (!slot.empty())
      throw InputError(g.option + " " + spec + ": two " +
                       (&slot == &g.release ? "releases" : "motions") +
                       ": expected SET[@MOTION][@release:T]");
    slot = part;
    at = next;
  }
}

std::vector<PinSpec> splitPinSpecs(const std::vector<std::string>& specs) {
  std::vector<PinSpec> groups;
  for (std::size_t k = 0; k < specs.size(); ++k) {
    const std::string& spec = specs[k];
    const auto at = spec.find('@');
    PinSpec g;
    g.set = spec.substr(0, at);
    g.option = "--pin";
    if (specs.size() > 1) g.option += " (group " + std::to_string(k + 1) + ")";
    splitPinTail(spec, at, g);
    if (g.set == "none" && (specs.size() > 1 || at != std::string::npos))
      throw InputError(g.option + " " + spec +
                       ": none pins nothing; give it alone, without a motion or release");
    groups.push_back(g);
  }
  return groups;
}

// The T of @release:T: a finite time > 0 (InputError naming the option otherwise); +∞ without.
double parseRelease(const PinSpec& g) {
  if (g.release.empty()) return std::numeric_limits<double>::infinity();
  const std::string time = g.release.substr(std::string("release:").size());
  char* end = nullptr;
  const double t = std::strtod(time.c_str(), &end);
  if (end == time.c_str() || *end != '\0' || !std::isfinite(t) || !(t > 0.0))
    throw InputError(g.option + " " + g.set + "@" + g.release +
                     ": expected a finite release time T > 0 (seconds)");
  return t;
}

}  // namespace

void checkPinSpecs(const std::vector<std::string>& specs, const std::string& pinMotion) {
  for (const PinSpec& g : splitPinSpecs(specs)) {
    parseRelease(g);
    if (g.motion.empty()) continue;
    if (!pinMotion.empty())
      throw InputError(g.option + " " + g.set + "@" + g.motion + ": --pin-motion " + pinMotion +
                       " moves every pinned vertex; give each group its motion instead");
    parsePinMotion(g.motion, g.option);
  }
}

std::vector<optimize::PinGroup> pinGroupMotions(const std::vector<std::string>& specs,
                                                const optimize::PinMotion& pinMotion) {
  std::vector<optimize::PinGroup> groups;
  for (const PinSpec& g : splitPinSpecs(specs)) {
    if (g.motion.empty() && g.release.empty()) continue;
    optimize::PinGroup group;
    // A group with a release and no motion of its own follows --pin-motion until it is let go.
    group.motion = g.motion.empty() ? pinMotion : parsePinMotion(g.motion, g.option);
    group.releaseTime = parseRelease(g);
    groups.push_back(std::move(group));
  }
  return groups;
}

PinnedGroups pinnedGroups(const std::vector<std::string>& specs, const modeling::Stencils& stencils,
                          const modeling::Positions& rest,
                          std::vector<optimize::PinGroup>& groups) {
  PinnedGroups pinned;
  pinned.held.assign(stencils.vertexCount(), false);
  std::size_t group = 0;
  for (const PinSpec& g : splitPinSpecs(specs)) {
    if (g.set == "none") continue;
    const std::vector<bool> set = optimize::parseFixedSet(g.option, g.set, stencils, rest);
    for (int v = 0; v < stencils.vertexCount(); ++v) {
      if (set[v] && pinned.held[v])
        throw InputError(g.option + " " + g.set + ": vertex " + std::to_string(v) +
                         " is in an earlier group too; the groups must not overlap");
      pinned.held[v] = pinned.held[v] || set[v];
    }
    const std::vector<bool> clamped = optimize::clampedBoundaryEdges(g.set, stencils);
    if (!clamped.empty()) {
      pinned.clampedEdges.resize(clamped.size(), false);
      for (std::size_t e = 0; e < clamped.size(); ++e)
        pinned.clampedEdges[e] = pinned.clampedEdges[e] || clamped[e];
    }
    if (!g.motion.empty() || !g.release.empty()) groups.at(group++).vertices = set;
  }
  return pinned;
}

}  // namespace flexure::cli
