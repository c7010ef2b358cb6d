// Errors: one exception type carrying a kind, which the CLI turns into an exit code in one place.
#pragma once

#include <stdexcept>
#include <string>

namespace m2mlat::core {

enum class ErrorKind {
  usage,     // bad option or argument (exit 2)
  data,      // malformed input data: the message names file, line and field (exit 65)
  no_input,  // a file or store that does not exist (exit 66)
  io,        // the operating system refused (exit 74)
  internal,  // a bug (exit 70)
  interrupted,  // a signal (SIGINT, SIGTERM) ended the command before it was done: nothing of it kept (exit 130)
};

class Error : public std::runtime_error {
 public:
  Error(ErrorKind kind, const std::string& message) : std::runtime_error(message), kind_(kind) {}
  ErrorKind kind() const { return kind_; }

 private:
  ErrorKind kind_;
};

// Process exit codes (sysexits.h values where one fits).
int exit_code(ErrorKind kind);

// A position in an input for error messages: "file.csv:12: field 'vehicle_ns': not an integer".
struct Location {
  std::string file;  // path as given by the user, or "<stdin>"
  long line = 0;     // 1-based; 0 = whole file
};
[[noreturn]] void throw_data_error(const Location& where, const std::string& what);

}  // namespace m2mlat::core
