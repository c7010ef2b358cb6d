// libpq, loaded with dlopen(3) the first time the archive needs it rather than by the dynamic
// loader at every start of m2mlat. Linked normally, libpq and the twenty libraries it pulls in
// (Kerberos, LDAP, SASL, GnuTLS, ...) were loaded and relocated by every command, `record` on a
// board too: 9.6 M of the loader's 23 M instructions (callgrind), half the libraries mapped.
// Only the functions the archive calls are looked up; their types come from libpq-fe.h.
#pragma once

#include <libpq-fe.h>

namespace m2mlat::archive::libpq {

// X(name) for each libpq function the archive calls.
#define M2MLAT_LIBPQ_FUNCTIONS(X)                                                                          \
  X(PQclear) X(PQcmdTuples) X(PQconnectdb) X(PQconninfoFree) X(PQconninfoParse) X(PQerrorMessage) X(PQexec) \
  X(PQexecParams) X(PQfinish) X(PQfname) X(PQfreemem) X(PQgetResult) X(PQgetisnull) X(PQgetlength)          \
  X(PQgetvalue) X(PQnfields) X(PQntuples) X(PQputCopyData) X(PQputCopyEnd) X(PQresultErrorMessage)          \
  X(PQresultStatus) X(PQsetNoticeProcessor) X(PQstatus)

// The functions, each a pointer named as the function it points to.
struct Api {
#define M2MLAT_LIBPQ_POINTER(name) decltype(&::name) name;
  M2MLAT_LIBPQ_FUNCTIONS(M2MLAT_LIBPQ_POINTER)
#undef M2MLAT_LIBPQ_POINTER
};

// Loads libpq.so.5 on the first call (later calls return the same table; thread-safe). Throws
// core::Error(io) naming the library, the package (libpq5) and dlerror()'s text when it cannot be
// loaded or lacks a function.
const Api& api();

}  // namespace m2mlat::archive::libpq
