// The two kinds of failure a user can act on, and the exit codes the CLI maps them to.
#pragma once

#include <cstdio>
#include <stdexcept>
#include <string>

namespace flexure {

// Bad input or usage: the message names the file, the element and what is wrong. Exit code 2.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A numerical failure (no convergence, a degenerate element hit during a solve). Exit code 3.
class NumericalError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A number as a message shows it: 6 significant digits, no trailing zeros ("1e-09", "0.3", "-inf").
inline std::string numberText(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

inline constexpr int kExitInputError = 2;
inline constexpr int kExitNumericalError = 3;

}  // namespace flexure
