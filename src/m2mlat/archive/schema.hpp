// The archive's tables in PostgreSQL (schema "m2mlat"), versioned by the row
// m2mlat.meta('schema_version') and created or migrated on first use, under a transaction-level
// advisory lock so that two pushes starting at once migrate it once.
//
// A campaign is one campaign store, known by the store's own identity (store_id); every other row
// carries the campaign's id and the store's own ids (session id, event seq, clock-sample id, loss
// id), so that a row pushed twice is the same row (primary keys) and a read gives the store back.
// Times are int64 ns on their clock (a column naming it), exact; pairs are not stored: every read
// re-pairs the raw events with the settings of that read (docs/archive.md).
#pragma once

#include "m2mlat/archive/connection.hpp"

namespace m2mlat::archive {

inline constexpr int kSchemaVersion = 2;

// Creates or migrates the archive's tables up to `target` (tests migrate step by step); returns the
// schema version now in force. Throws core::Error(data) if the database holds a newer schema than
// this build knows.
int migrate(Connection& connection, int target = kSchemaVersion);

// The version stored (0 for a database without the archive's tables).
int schema_version(Connection& connection);

}  // namespace m2mlat::archive
