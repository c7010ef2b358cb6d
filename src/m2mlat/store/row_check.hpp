// Finding rows that break the schema's rules in a store file written or edited by another tool
// (SQLite lets a connection switch CHECK constraints off, and foreign keys are off by default).
//
// The reads of the store select rows by clock, edge, channel and session, so such a row would be
// left out of an analysis or a merge without a word; check() finds the first one instead and names
// the file, the table, the row and the field. One scan of each table: the analysis and merge
// paths run it once per opened store, the agent's resume-by-seq read does not need it (it reads
// every row and refuses a bad one as it decodes it).
#pragma once

#include "m2mlat/store/sqlite.hpp"

namespace m2mlat::store::row_check {

// Throws core::Error(data) "<file>: table 'events' row seq 42: field 'edge' holds 2 (expected 0 or
// 1): ..." for the first row breaking a rule; returns if there is none.
void check(sqlite::Database& db);

}  // namespace m2mlat::store::row_check
