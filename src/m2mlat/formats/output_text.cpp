// Output blocks, JSON string escaping, and atomic file writing for the exporters.
#include "m2mlat/formats/output_text.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>

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

void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write) {
  if (path == "-") {
    write(std::cout);
    std::cout.flush();
    if (!std::cout) throw core::Error(core::ErrorKind::io, "<stdout>: write failed");
    return;
  }
  const std::string temporary = path + ".tmp";
  try {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out)
      throw core::Error(core::ErrorKind::io,
                        fmt::format("{}: cannot create: {}", temporary, std::strerror(errno)));
    write(out);
    out.close();
    if (!out) throw core::Error(core::ErrorKind::io, fmt::format("{}: write failed", temporary));
    if (std::rename(temporary.c_str(), path.c_str()) != 0)
      throw core::Error(core::ErrorKind::io,
                        fmt::format("{}: cannot rename to {}: {}", temporary, path, std::strerror(errno)));
  } catch (...) {
    std::remove(temporary.c_str());
    throw;
  }
}

}  // namespace m2mlat::formats
