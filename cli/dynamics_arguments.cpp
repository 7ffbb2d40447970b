#include "cli/dynamics_arguments.h"

#include <Eigen/Core>
#include <cmath>
#include <cstdlib>
#include <vector>

#include "modeling/errors.h"

namespace flexure::cli {

optimize::Integrator parseIntegrator(const std::string& name) {
  using optimize::Integrator;
  if (name == "newmark") return Integrator::Newmark;
  if (name == "backward-euler") return Integrator::BackwardEuler;
  if (name == "central-difference") return Integrator::CentralDifference;
  throw InputError("--integrator " + name +
                   ": expected newmark, backward-euler or central-difference");
}

optimize::PinMotion parsePinMotion(const std::string& spec) {
  using optimize::PinMotion;
  const auto colon = spec.find(':');
  const std::string kind = spec.substr(0, colon);
  const std::string expected = ": expected rotate:ax,ay,az,px,py,pz,omega or translate:vx,vy,vz";
  const int count = kind == "rotate" ? 7 : kind == "translate" ? 3 : 0;
  if (colon == std::string::npos || count == 0) throw InputError("--pin-motion " + spec + expected);
  std::vector<double> value;
  const std::string numbers = spec.substr(colon + 1);
  const char* cursor = numbers.c_str();
  for (int k = 0; k < count; ++k) {
    char* end = nullptr;
    value.push_back(std::strtod(cursor, &end));
    if (end == cursor || (k < count - 1 && *end != ',') || (k == count - 1 && *end != '\0') ||
        !std::isfinite(value.back()))
      throw InputError("--pin-motion " + spec + expected + " (" + std::to_string(count) +
                       " finite numbers)");
    cursor = end + 1;
  }
  PinMotion m;
  if (kind == "translate") {
    m.kind = PinMotion::Kind::Translate;
    m.velocity = Eigen::Vector3d(value[0], value[1], value[2]);
    return m;
  }
  const Eigen::Vector3d axis(value[0], value[1], value[2]);
  if (!(axis.norm() > 0.0)) throw InputError("--pin-motion " + spec + ": the axis is zero");
  m.kind = PinMotion::Kind::Rotate;
  m.axis = axis.normalized();
  m.point = Eigen::Vector3d(value[3], value[4], value[5]);
  m.omega = value[6];
  return m;
}

}  // namespace flexure::cli
