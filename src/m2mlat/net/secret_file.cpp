// Reading a secret file through one descriptor, with its mode checked on that descriptor.
#include "m2mlat/net/secret_file.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/fd.hpp"

namespace m2mlat::net {

std::string read_secret_file(const std::string& path, std::string_view what) {
  const core::Fd opened(::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOCTTY));
  const int fd = opened.get();
  if (fd < 0)
    throw core::Error(core::ErrorKind::no_input,
                      fmt::format("{} {}: cannot open: {}", what, path, std::strerror(errno)));
  struct stat st {};
  if (::fstat(fd, &st) != 0)
    throw core::Error(core::ErrorKind::no_input,
                      fmt::format("{} {}: cannot stat: {}", what, path, std::strerror(errno)));
  const auto mode = st.st_mode & 07777;
  // Group read is allowed only on a file of root's: root keeps the secret and lets a service's own
  // group (the agent's user) read it, as the field guide sets up /etc/m2mlat/token.
  const bool group_ok = (mode & (S_IWGRP | S_IXGRP)) == 0 && ((mode & S_IRGRP) == 0 || st.st_uid == 0);
  if ((mode & S_IRWXO) != 0 || !group_ok)
    throw core::Error(core::ErrorKind::usage,
                      fmt::format("{} {}: the file is accessible by group or others (mode {:04o}); a secret "
                                  "must be the owner's alone: chmod 600 {} (a file of root's may be 0640)",
                                  what, path, mode, path));
  std::string text;
  char buffer[4096];
  for (;;) {
    const auto n = ::read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0)
      throw core::Error(core::ErrorKind::no_input,
                        fmt::format("{} {}: cannot read: {}", what, path, std::strerror(errno)));
    if (n == 0) break;
    if (text.size() + static_cast<std::size_t>(n) > kMaxSecretFileBytes)
      throw core::Error(
          core::ErrorKind::usage,
          fmt::format("{} {}: larger than {} bytes; is it the right file?", what, path, kMaxSecretFileBytes));
    text.append(buffer, static_cast<std::size_t>(n));
  }
  return text;
}

}  // namespace m2mlat::net
