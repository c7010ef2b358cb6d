// Channel names and the only_line filter for formats that name a pin or label but no channel.
#include "m2mlat/formats/line_selection.hpp"

#include <fmt/format.h>

#include "m2mlat/formats/fields.hpp"

namespace m2mlat::formats {

LineSelection::LineSelection(const ImportOptions& options, std::string_view file)
    : file_(file), channel_(options.channel), only_line_(canonical_label(trim(options.only_line))) {}

const std::string* LineSelection::lookup(std::string_view label, long line, std::string_view field) {
  const std::string_view canonical = canonical_label(label);
  std::size_t found = kNone;
  for (std::size_t i = 0; i < entries_.size(); ++i)
    if (entries_[i].label == canonical) found = i;
  if (found == kNone) {
    Entry entry;
    entry.label = std::string(canonical);
    entry.first_line = line;
    entry.kept = only_line_.empty() || only_line_ == canonical;
    if (!channel_.empty()) {
      entry.channel = channel_;
      if (only_line_.empty() && !entries_.empty()) {
        const Entry& first = entries_.front();
        throw_field_error(file_, line, field, label,
                          fmt::format("is a second line (line {} has '{}') but one channel '{}' was given: "
                                      "choose one line to import, or leave the channel to its default",
                                      first.first_line, first.label, channel_));
      }
    } else {
      entry.channel = is_digits(canonical) ? "gpio" + entry.label : entry.label;
    }
    entries_.push_back(std::move(entry));
    found = entries_.size() - 1;
  }
  last_ = found;
  last_raw_ = label;
  return result(entries_[found]);
}

}  // namespace m2mlat::formats
