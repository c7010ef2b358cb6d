// Which channel the records of a GPIO pin or line label become, and which pins or labels are kept.
//
// The kernel log and the reference rig's export CSV name a pin or a label on every line but no
// node or channel. The caller gives the node; the channel is "gpio<pin>" for a pin number, the label
// itself otherwise, or one channel the caller names (then the file must hold one line, or
// ImportOptions::only_line must choose one: two lines on one channel would mix their edges).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "m2mlat/formats/imported.hpp"

namespace m2mlat::formats {

// A pin or label as compared: a digit string without its leading zeros ("016" and "16" are one pin).
constexpr std::string_view canonical_label(std::string_view label) {
  bool digits = !label.empty();
  for (char c : label)
    if (c < '0' || c > '9') digits = false;
  if (digits)
    while (label.size() > 1 && label.front() == '0') label.remove_prefix(1);
  return label;
}

class LineSelection {
 public:
  // `file` names the input in error messages.
  LineSelection(const ImportOptions& options, std::string_view file);

  // The channel for a record of `label` read at `line` (its column or part is `field`), or nullptr if
  // ImportOptions::only_line leaves it out. Throws core::Error(data) when a single channel was given
  // and `label` is the file's second line label.
  const std::string* channel_for(std::string_view label, long line, std::string_view field) {
    if (last_ != kNone && label == last_raw_) return result(entries_[last_]);
    return lookup(label, line, field);
  }

 private:
  struct Entry {
    std::string label;  // canonical
    std::string channel;
    bool kept = true;
    long first_line = 0;
  };
  static constexpr std::size_t kNone = static_cast<std::size_t>(-1);

  static const std::string* result(const Entry& entry) { return entry.kept ? &entry.channel : nullptr; }
  const std::string* lookup(std::string_view label, long line, std::string_view field);

  std::string file_;
  std::string channel_;    // the caller's single channel, or empty
  std::string only_line_;  // canonical, or empty
  std::vector<Entry> entries_;
  std::size_t last_ = kNone;   // the entry of the previous record: files rarely change line
  std::string_view last_raw_;  // its label as written (a view into the input)
};

}  // namespace m2mlat::formats
