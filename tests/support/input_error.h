// The message of the InputError `f` throws, or "(no InputError)": tests assert on what a refusal
// says.
#pragma once

#include <functional>
#include <string>

#include "modeling/errors.h"

namespace flexure::testing {

inline std::string inputErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

}  // namespace flexure::testing
