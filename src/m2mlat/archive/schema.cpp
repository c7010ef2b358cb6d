// The archive's schema and its migrations.
#include "m2mlat/archive/schema.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <string_view>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/number.hpp"

namespace m2mlat::archive {

namespace {

// Migration N takes the schema from version N-1 to N. Append only; never edit a released one.
constexpr std::string_view kMigrations[] = {
    // Version 1: campaigns, their sessions, events, clock samples, losses, and the push cursor.
    R"sql(
CREATE TABLE m2mlat.campaigns (
  id         bigserial PRIMARY KEY,
  store_id   text NOT NULL UNIQUE,          -- the campaign store's own identity (32 hex digits)
  name       text NOT NULL,                 -- short name: the store's file name without .db, or --name
  rig        text NOT NULL DEFAULT '',      -- the rig that recorded it
  label      text NOT NULL DEFAULT '',      -- free text, e.g. a study's name
  created_ns bigint,                        -- earliest session start, ns since 1970 (CLOCK_REALTIME); NULL without one
  created_by text NOT NULL DEFAULT '',      -- the m2mlat version that created the store
  pushed_at  timestamptz NOT NULL DEFAULT now()
);
CREATE TABLE m2mlat.sessions (
  campaign_id bigint NOT NULL REFERENCES m2mlat.campaigns (id) ON DELETE CASCADE,
  session_id  bigint NOT NULL,              -- the store's session id
  label       text NOT NULL,
  scenario    text NOT NULL,
  node        text NOT NULL,
  role        text NOT NULL,
  config_json text NOT NULL,
  clock       text NOT NULL,                -- the clock of start_ns and end_ns
  start_ns    bigint NOT NULL,
  end_ns      bigint,                       -- NULL while the session was open
  software_version text NOT NULL,
  PRIMARY KEY (campaign_id, session_id)
);
CREATE TABLE m2mlat.events (
  campaign_id bigint NOT NULL,
  seq         bigint NOT NULL,              -- the store's sequence number
  session_id  bigint NOT NULL,
  node        text NOT NULL,
  channel     text NOT NULL,
  edge        text NOT NULL,                -- rising | falling
  clock       text NOT NULL,
  t_ns        bigint NOT NULL,              -- the kernel's timestamp, ns on `clock`
  seqno       bigint NOT NULL,              -- the kernel's event numbers (uint64 stored as its int64 bits)
  line_seqno  bigint NOT NULL,
  flags       bigint NOT NULL,              -- core::EventFlag bits (uint32)
  PRIMARY KEY (campaign_id, seq),
  FOREIGN KEY (campaign_id, session_id) REFERENCES m2mlat.sessions (campaign_id, session_id) ON DELETE CASCADE
);
CREATE INDEX events_time ON m2mlat.events (campaign_id, node, channel, t_ns);
CREATE TABLE m2mlat.clock_samples (
  campaign_id  bigint NOT NULL,
  id           bigint NOT NULL,             -- the store's row id
  session_id   bigint NOT NULL,
  clock        text NOT NULL,
  t_ns         bigint NOT NULL,
  source       text NOT NULL,
  offset_ns    bigint NOT NULL,
  max_error_ns bigint NOT NULL,
  est_error_ns bigint NOT NULL,
  synchronised boolean NOT NULL,
  detail_json  text NOT NULL,
  PRIMARY KEY (campaign_id, id),
  FOREIGN KEY (campaign_id, session_id) REFERENCES m2mlat.sessions (campaign_id, session_id) ON DELETE CASCADE
);
CREATE TABLE m2mlat.losses (
  campaign_id   bigint NOT NULL,
  id            bigint NOT NULL,
  session_id    bigint NOT NULL,
  channel       text NOT NULL,
  clock         text NOT NULL,
  detected_ns   bigint NOT NULL,
  first_missing bigint NOT NULL,            -- uint64 stored as its int64 bits
  count         bigint NOT NULL,
  kind          text NOT NULL,
  PRIMARY KEY (campaign_id, id),
  FOREIGN KEY (campaign_id, session_id) REFERENCES m2mlat.sessions (campaign_id, session_id) ON DELETE CASCADE
);
-- How far a push has copied each campaign: the largest store seq / id committed here. Advanced in
-- the transaction of each batch, so a push killed midway resumes after its last committed batch.
CREATE TABLE m2mlat.push_cursors (
  campaign_id   bigint PRIMARY KEY REFERENCES m2mlat.campaigns (id) ON DELETE CASCADE,
  events        bigint NOT NULL DEFAULT 0,
  clock_samples bigint NOT NULL DEFAULT 0,
  losses        bigint NOT NULL DEFAULT 0,
  complete      boolean NOT NULL DEFAULT false  -- the last push ran to its end
);
)sql",
    // Version 2: raw gyroscope samples (the store's rate_blocks), so that full-loop campaigns' chains
    // can be analysed from the archive; their own cursor.
    R"sql(
CREATE TABLE m2mlat.rate_blocks (
  campaign_id      bigint NOT NULL,
  id               bigint NOT NULL,         -- the store's row id
  session_id       bigint NOT NULL,
  channel          text NOT NULL,
  clock            text NOT NULL,           -- the clock of every sample's stamp
  counts_per_deg_s double precision NOT NULL,
  first_index      bigint NOT NULL,         -- uint64 stored as its int64 bits
  layout           integer NOT NULL,        -- the samples' layout (store/rate_block.hpp)
  count            integer NOT NULL,
  samples          bytea NOT NULL,          -- count records of layout `layout`
  PRIMARY KEY (campaign_id, id),
  FOREIGN KEY (campaign_id, session_id) REFERENCES m2mlat.sessions (campaign_id, session_id) ON DELETE CASCADE
);
ALTER TABLE m2mlat.push_cursors ADD COLUMN rate_blocks bigint NOT NULL DEFAULT 0;
)sql",
};

}  // namespace

int schema_version(Connection& connection) {
  const auto exists = connection.exec("SELECT to_regclass('m2mlat.meta') IS NOT NULL");
  if (exists.at(0, 0) != "t") return 0;
  const auto rows = connection.exec("SELECT value FROM m2mlat.meta WHERE key = 'schema_version'");
  if (rows.rows.empty()) return 0;
  std::int64_t version = 0;
  if (!core::parse_integer(rows.at(0, 0), version))
    throw core::Error(core::ErrorKind::data,
                      fmt::format("archive {}: m2mlat.meta schema_version '{}' is not a number",
                                  connection.name(), rows.at(0, 0)));
  return static_cast<int>(version);
}

int migrate(Connection& connection, int target) {
  Transaction tx(connection);
  // One migrating session at a time; the lock ends with the transaction.
  connection.exec("SELECT pg_advisory_xact_lock(hashtext('m2mlat.archive.schema'))");
  connection.exec("CREATE SCHEMA IF NOT EXISTS m2mlat");
  connection.exec("CREATE TABLE IF NOT EXISTS m2mlat.meta (key text PRIMARY KEY, value text NOT NULL)");
  const int version = schema_version(connection);
  constexpr int latest = static_cast<int>(std::size(kMigrations));
  static_assert(latest == kSchemaVersion);
  if (version > latest)
    throw core::Error(
        core::ErrorKind::data,
        fmt::format("archive {}: schema version {} is newer than this m2mlat's ({}): update m2mlat",
                    connection.name(), version, latest));
  target = std::clamp(target, 1, latest);
  if (version >= target) return version;
  for (int v = version; v < target; ++v) connection.exec(std::string(kMigrations[v]));
  connection.exec(
      "INSERT INTO m2mlat.meta (key, value) VALUES ('schema_version', $1) "
      "ON CONFLICT (key) DO UPDATE SET value = EXCLUDED.value",
      {std::to_string(target)});
  tx.commit();
  return target;
}

}  // namespace m2mlat::archive
