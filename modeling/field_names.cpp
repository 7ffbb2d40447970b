#include "modeling/field_names.h"

#include <cctype>

namespace flexure::modeling {
namespace {

bool continuesName(const std::string& text, size_t at) {
  return at < text.size() &&
         (std::isalnum(static_cast<unsigned char>(text[at])) || text[at] == '_');
}

}  // namespace

std::string renameFields(std::string message, const std::vector<FieldName>& table) {
  for (const FieldName& row : table) {
    for (size_t at = message.find(row.field); at != std::string::npos;
         at = message.find(row.field, at)) {
      if (continuesName(message, at + row.field.size()) ||
          (at > 0 && continuesName(message, at - 1))) {
        at += row.field.size();
        continue;
      }
      message.replace(at, row.field.size(), row.name);
      at += row.name.size();
    }
  }
  return message;
}

}  // namespace flexure::modeling
