// The library names an option in its messages by its field (modeling/field_names.h); a Python user
// reads the keyword argument instead ("ProblemOptions.fixedRings" → "fixed_rings"). Every
// ValueError the module raises from a library message passes through withKeywordNames.
#pragma once

#include <string>

namespace flexure::python {

// `message` with every known "Struct.field" replaced by the keyword argument that sets it.
std::string withKeywordNames(std::string message);

}  // namespace flexure::python
