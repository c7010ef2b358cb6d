// Output blocks and JSON string escaping for the exporters.
#include "m2mlat/formats/output_text.hpp"

#include <fmt/format.h>

#include "m2mlat/core/error.hpp"

namespace m2mlat::formats {

void OutputBuffer::flush() {
  out_.write(text_.data(), static_cast<std::streamsize>(text_.size()));
  text_.clear();
  if (!out_) throw core::Error(core::ErrorKind::io, "writing the export failed");
}

void append_json_string(std::string& out, std::string_view s) {
  out.push_back('"');
  for (char c : s) {
    const auto u = static_cast<unsigned char>(c);
    switch (c) {
      case '"': out.append("\\\""); break;
      case '\\': out.append("\\\\"); break;
      case '\n': out.append("\\n"); break;
      case '\r': out.append("\\r"); break;
      case '\t': out.append("\\t"); break;
      default:
        if (u < 0x20 || u == 0x7f)
          out.append(fmt::format("\\u{:04x}", u));
        else
          out.push_back(c);
    }
  }
  out.push_back('"');
}

}  // namespace m2mlat::formats
