// The library names an option in its messages by its field ('MinimizeOptions.maxIterations'),
// never by a front end's word for it. Each front end keeps one table from fields to its own words
// (cli/option_names: flags; python/bindings/keyword_names: keyword arguments) and renames the
// fields of every message it shows with renameFields.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace flexure::modeling {

struct FieldName {
  std::string_view field;  // as the library's messages name it: "Struct.field"
  std::string_view name;   // as the user wrote it: a flag, a keyword argument
};

// `message` with every whole "Struct.field" of `table` replaced by its name. A field is whole when
// no letter, digit or '_' continues it on either side ('SpectrumStudyOptions.count' is not
// 'StudyOptions.count'); rows are tried in order, so a longer field that starts with a shorter
// one must come first.
std::string renameFields(std::string message, const std::vector<FieldName>& table);

}  // namespace flexure::modeling
