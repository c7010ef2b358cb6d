#include "m2mlat/markers/marker.hpp"

namespace m2mlat::markers {

std::string_view to_string(StampSource source) {
  switch (source) {
    case StampSource::adapter: return "adapter";
    case StampSource::host: return "host";
    case StampSource::file: return "file";
  }
  return "?";
}

}  // namespace m2mlat::markers
