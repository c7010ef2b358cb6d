// Loading libpq.so.5 and looking up the archive's functions (see libpq.hpp for why).
#include "m2mlat/archive/libpq.hpp"

#include <dlfcn.h>
#include <fmt/format.h>

#include "m2mlat/core/error.hpp"

namespace m2mlat::archive::libpq {

namespace {

// Debian's libpq5 (PostgreSQL's client library, ABI 5 since PostgreSQL 8.0).
constexpr const char* kLibrary = "libpq.so.5";

[[noreturn]] void fail(const char* what) {
  const char* reason = dlerror();
  throw core::Error(core::ErrorKind::io,
                    fmt::format("archive: cannot load {} ({}: {}); the archive needs PostgreSQL's client "
                                "library: apt-get install libpq5",
                                kLibrary, what, reason != nullptr ? reason : "unknown error"));
}

Api load() {
  // Never closed: the pointers are used until the process exits.
  void* library = dlopen(kLibrary, RTLD_NOW | RTLD_LOCAL);
  if (library == nullptr) fail("dlopen");
  Api api{};
#define M2MLAT_LIBPQ_LOOKUP(name)                                          \
  api.name = reinterpret_cast<decltype(api.name)>(dlsym(library, #name)); \
  if (api.name == nullptr) fail(#name);
  M2MLAT_LIBPQ_FUNCTIONS(M2MLAT_LIBPQ_LOOKUP)
#undef M2MLAT_LIBPQ_LOOKUP
  return api;
}

}  // namespace

const Api& api() {
  static const Api loaded = load();  // a failed load throws, and the next call tries again
  return loaded;
}

}  // namespace m2mlat::archive::libpq
