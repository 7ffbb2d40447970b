#include "cli/mode_arguments.h"

#include "modeling/errors.h"

namespace flexure::cli {

optimize::Support parseSupport(const std::string& name) {
  if (name == "clamped") return optimize::Support::Clamped;
  if (name == "simply-supported") return optimize::Support::SimplySupported;
  if (name == "free") return optimize::Support::Free;
  throw InputError("--support " + name + ": expected clamped, simply-supported or free");
}

optimize::Clamp parseClamp(const std::string& name) {
  if (name == "rings") return optimize::Clamp::Rings;
  if (name == "normals") return optimize::Clamp::Normals;
  throw InputError("--clamp " + name + ": expected rings or normals");
}

}  // namespace flexure::cli
