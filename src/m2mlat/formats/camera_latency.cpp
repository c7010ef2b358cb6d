// Reading the camera-to-monitor latency file.
#include "m2mlat/formats/camera_latency.hpp"

#include <fmt/format.h>

#include "m2mlat/formats/fields.hpp"
#include "m2mlat/formats/input_text.hpp"

namespace m2mlat::formats {

CameraLatencyImport import_camera_latency(std::string_view text, std::string_view name) {
  LineReader reader(text);
  std::string_view line;
  do {
    if (!reader.next(line))
      throw_line_error(name, 0, fmt::format("is empty (expected the header '{}')", kCameraLatencyHeader));
  } while (is_blank(line));
  if (trim(line) != kCameraLatencyHeader)
    throw_line_error(
        name, reader.line_number(),
        fmt::format("header is {}, expected '{}'", quote_for_message(line), kCameraLatencyHeader));
  CameraLatencyImport result;
  while (reader.next(line)) {
    if (is_blank(line)) continue;
    result.latency_ns.push_back(
        require_decimal_ms(name, reader.line_number(), kCameraLatencyHeader, trim(line)));
    result.lines.push_back(reader.line_number());
  }
  return result;
}

}  // namespace m2mlat::formats
