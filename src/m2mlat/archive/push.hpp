// `m2mlat archive push`: copies one campaign store into the archive, idempotent and resumable.
//
// The campaign is known by its store's identity (store_id): pushing the same store twice, or a copy
// of it, adds nothing the archive holds already. Rows go in batches, each in one transaction that
// also advances the campaign's cursor (m2mlat.push_cursors: the largest store seq / id copied), like
// store::Store::ingest's cursor; a push killed midway leaves whole batches and its cursor, and the
// next push continues after them. The cursor row is locked for the batch, so two pushes of one
// campaign at once take turns and still store every row once.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "m2mlat/archive/connection.hpp"

namespace m2mlat::archive {

struct PushProgress {
  std::int64_t events_done = 0;   // events of the store now in the archive
  std::int64_t events_total = 0;  // events of the store
};

struct PushOptions {
  std::string name;   // the campaign's short name; empty: kept, or the store's file name without .db
  std::string rig;    // empty: kept (or '' for a new campaign)
  std::string label;  // empty: kept (or '' for a new campaign)
  std::size_t batch_rows = 20000;  // events per transaction (and as many clock samples and losses)
  std::function<void(const PushProgress&)> progress;  // after each committed batch
};

struct PushSummary {
  std::int64_t campaign_id = 0;
  std::string store_id, name;
  bool resumed = false;  // the archive held part of the campaign already
  int batches = 0;       // transactions committed by this push
  // Rows this push added.
  std::int64_t sessions = 0, events = 0, clock_samples = 0, losses = 0, rate_blocks = 0;
  // The campaign's rows in the archive after the push.
  std::int64_t total_events = 0;
};

// Opens `store_path` read-only and copies what the archive lacks. Creates or migrates the schema
// first. Throws core::Error: no_input / data for the store, io for the database.
PushSummary push(const std::string& store_path, Connection& connection, const PushOptions& options);

}  // namespace m2mlat::archive
