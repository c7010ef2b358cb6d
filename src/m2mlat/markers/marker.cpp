#include "m2mlat/markers/marker.hpp"

#include <array>

namespace m2mlat::markers {

std::string_view to_string(StampSource source) {
  switch (source) {
    case StampSource::adapter: return "adapter";
    case StampSource::host: return "host";
    case StampSource::file: return "file";
    case StampSource::kernel: return "kernel";
    case StampSource::receiver: return "receiver";
    case StampSource::bag_log: return "bag_log";
    case StampSource::bag_header: return "bag_header";
  }
  return "?";
}

std::optional<StampSource> parse_stamp_source(std::string_view name) {
  constexpr std::array kAll{StampSource::adapter, StampSource::host,    StampSource::file,
                            StampSource::kernel,  StampSource::receiver, StampSource::bag_log,
                            StampSource::bag_header};
  for (const auto source : kAll)
    if (to_string(source) == name) return source;
  return std::nullopt;
}

}  // namespace m2mlat::markers
