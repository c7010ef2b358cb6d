// Error kinds to exit codes, and data errors with their location.
#include "m2mlat/core/error.hpp"

#include <fmt/format.h>

namespace m2mlat::core {

int exit_code(ErrorKind kind) {
  switch (kind) {
    case ErrorKind::usage: return 2;
    case ErrorKind::data: return 65;
    case ErrorKind::no_input: return 66;
    case ErrorKind::io: return 74;
    case ErrorKind::internal: return 70;
    case ErrorKind::interrupted: return 130;
  }
  return 70;
}

void throw_data_error(const Location& where, const std::string& what) {
  if (where.line > 0) throw Error(ErrorKind::data, fmt::format("{}:{}: {}", where.file, where.line, what));
  throw Error(ErrorKind::data, fmt::format("{}: {}", where.file, what));
}

}  // namespace m2mlat::core
