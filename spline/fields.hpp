#pragma once
// Libraries speak in fields, not flags: a message that names an option of a
// library request names it by its field (RegionRequest::with is "with",
// ::each_piece "each_piece"), marked with field(). A library user reads the
// field's name (what(), plain_fields()); a program that calls the options
// something else rewrites the marks its own way (the cmr command: as its
// flags, through the one table in tools/cli_common.cpp, show_fields there),
// so the command's lines read as they always have.
//
//   throw InputFieldError(field("with") + " point 3 is named twice");
//     what():            "with point 3 is named twice"
//     cmr prints:   "cmr: --with point 3 is named twice"
#include <string>

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
