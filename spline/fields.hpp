#pragma once
// Libraries speak in fields, not flags: a message that names an option of a
// library request names it by its field (RegionRequest::with is "with",
// ::each_piece "each_piece"), marked with field(). A library user reads the
// field's name (what(), plain_fields()); a program that calls the options
// something else rewrites the marks its own way (the cmr command: as its
// flags, through the one table in tools/field_flags.hpp, show_fields there;
// the Python module: as its keywords, python_fields in python/cmr_module.cpp),
// so the command's lines read as they always have. tools/check_layout.py
// (ctest layout) fails on a CLI flag in a library string and on a marked
// field the table does not map.
//
//   throw InputFieldError(field("with") + " point 3 is named twice");
//     what():            "with point 3 is named twice"
//     cmr prints:   "cmr: --with point 3 is named twice"
#include <cstddef>
#include <exception>
#include <string>
#include <utility>

#include "spline/errors.hpp"

namespace cmr {

/// Delimits a field's name on both sides in a marked message.
inline constexpr char kFieldMark = '\x1f';

/// `name` (a request field) marked in a message.
inline std::string field(const std::string& name) {
  std::string s(1, kFieldMark);
  s.append(name).push_back(kFieldMark);
  return s;
}

/// The message with its marks removed: fields by their names.
inline std::string plain_fields(const std::string& marked) {
  std::string s;
  for (const char c : marked)
    if (c != kFieldMark) s.push_back(c);
  return s;
}

/// The message with each marked field replaced by name(field): how a program
/// that calls the options something else shows it (the cmr command: its
/// flags; the Python module: its keywords).
template <class Name>
std::string rename_fields(const std::string& marked, const Name& name) {
  std::string out;
  for (std::size_t at = 0; at < marked.size();) {
    const std::size_t open = marked.find(kFieldMark, at);
    const std::size_t close = open == std::string::npos ? open : marked.find(kFieldMark, open + 1);
    if (close == std::string::npos) {
      out.append(marked, at, std::string::npos);
      break;
    }
    out.append(marked, at, open - at);
    out += name(marked.substr(open + 1, close - open - 1));
    at = close + 1;
  }
  return out;
}

/// Every string in a JSON document (nlohmann::json or ordered_json) passed
/// through show: for a document that quotes library messages (a fix's
/// reasons), shown as a program names the fields.
template <class Json, class Show>
void show_fields_in(Json& doc, const Show& show) {
  if (doc.is_string()) {
    doc = show(doc.template get<std::string>());
  } else if (doc.is_structured()) {
    for (auto& v : doc) show_fields_in(v, show);
  }
}

/// A message that names fields: the marked text, beside the exception's plain what().
class FieldMessage {
 public:
  explicit FieldMessage(std::string marked) : marked_(std::move(marked)) {}
  virtual ~FieldMessage() = default;
  const std::string& marked() const { return marked_; }

 private:
  std::string marked_;
};

/// InputError whose message names fields.
class InputFieldError : public InputError, public FieldMessage {
 public:
  explicit InputFieldError(const std::string& marked) : InputError(plain_fields(marked)), FieldMessage(marked) {}
};

/// EnvironmentError whose message names fields.
class EnvironmentFieldError : public EnvironmentError, public FieldMessage {
 public:
  explicit EnvironmentFieldError(const std::string& marked)
      : EnvironmentError(plain_fields(marked)), FieldMessage(marked) {}
};

/// The marked text of `e` where it names fields, else what(): for a message
/// built on another's (a note quoting an error) that a program still rewrites.
inline std::string marked_text(const std::exception& e) {
  if (const auto* f = dynamic_cast<const FieldMessage*>(&e)) return f->marked();
  return e.what();
}

}  // namespace cmr
