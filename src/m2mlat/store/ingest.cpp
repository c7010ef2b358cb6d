// Campaign stores: taking in what other stores (an agent's, a board's file) hold, exactly once.
//
// Each origin store has a cursor row (origins) with the largest origin seq / id taken of each kind
// (events, clock samples, losses, raw rate blocks, markers),
// and a map from its session ids to local ones (origin_sessions). Items at or below the cursor are
// skipped; the rest are inserted with local seqs and ids; the cursor moves in the same transaction.
// So a batch given twice, a batch that overlaps an earlier one, or a pull resumed after a crash on
// either side all end with every origin item stored once.
#include <fmt/format.h>

#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/version.hpp"
#include "m2mlat/store/rows.hpp"
#include "m2mlat/store/sqlite.hpp"
#include "m2mlat/store/store.hpp"
#include "m2mlat/store/store_impl.hpp"
#include "m2mlat/store/validate.hpp"

namespace m2mlat::store {

namespace {

struct LocalSession {
  std::int64_t id = 0;
  std::string node;
};

// The origin's items must come in increasing id order, beyond what is already stored; `last` is the
// largest id taken so far in this batch (starting at the cursor).
bool take(const std::string& path, std::string_view what, std::size_t index, std::int64_t id,
          std::int64_t cursor, std::int64_t& last) {
  if (id <= cursor) return false;  // already stored
  if (id <= last)
    core::throw_data_error({path, 0}, fmt::format("{} {} of the batch: field 'id' {} is not above the one "
                                                  "before it ({}): the origin's order is broken",
                                                  what, index, id, last));
  last = id;
  return true;
}

// Stores the batch's rows of one kind that carry an origin `id` and a session id (clock samples,
// losses, rate blocks, markers): those beyond the cursor, in order, each with the origin's session id
// replaced by the local one that `local_id(origin session id, what, index)` gives.
template <class Stored, class Row, class LocalId>
void ingest_rows(const std::string& path, std::string_view what, const std::vector<Stored>& items,
                 Row Stored::*row_of, std::int64_t cursor, std::int64_t& last, sqlite::Statement& insert,
                 void (*bind)(sqlite::Statement&, const Row&), const LocalId& local_id) {
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (!take(path, what, i, items[i].id, cursor, last)) continue;
    Row row = items[i].*row_of;
    row.session_id = local_id(row.session_id, what, i);
    bind(insert, row);
    insert.step();
    insert.reset();
  }
}

}  // namespace

IngestCursor Store::ingest_cursor(const std::string& origin) const {
  sqlite::Statement query(impl_->db,
                          "SELECT event_seq, clock_sample_id, loss_id, rate_block_id, marker_id FROM origins "
                          "WHERE origin = ?1");
  query.bind(1, origin);
  if (!query.step()) return {};
  return {query.column_int64(0), query.column_int64(1), query.column_int64(2), query.column_int64(3),
          query.column_int64(4)};
}

std::vector<std::string> Store::origins() const {
  sqlite::Statement query(impl_->db, "SELECT origin FROM origins ORDER BY origin");
  std::vector<std::string> out;
  while (query.step()) out.emplace_back(query.column_text(0));
  return out;
}

IngestCursor Store::ingest(const IngestBatch& batch) {
  Impl& s = *impl_;
  s.require_writable();
  const std::string& origin = batch.origin;
  if (origin.empty()) core::throw_data_error({path(), 0}, "ingest: field 'origin' is empty");
  if (origin == store_id())
    core::throw_data_error({path(), 0}, fmt::format("ingest: origin '{}' is this store itself", origin));
  // Every value is checked before the transaction: a bad one is reported without any write.
  for (const Session& session : batch.sessions) {
    if (session.id <= 0)
      core::throw_data_error({path(), 0},
                             fmt::format("ingest from '{}': session field 'id' {} is not positive", origin,
                                         session.id));
    validate::session(path(), session);
  }
  for (std::size_t i = 0; i < batch.events.size(); ++i) validate::event(path(), i, batch.events[i].event);
  for (std::size_t i = 0; i < batch.clock_samples.size(); ++i)
    validate::clock_sample(path(), i, batch.clock_samples[i].sample);
  for (std::size_t i = 0; i < batch.losses.size(); ++i) validate::loss(path(), i, batch.losses[i].loss);
  for (std::size_t i = 0; i < batch.rate_blocks.size(); ++i)
    validate::rate_block(path(), i, batch.rate_blocks[i].block);
  for (std::size_t i = 0; i < batch.markers.size(); ++i) validate::marker(path(), i, batch.markers[i].marker);

  sqlite::Transaction transaction(s.db);
  const IngestCursor before = ingest_cursor(origin);
  {
    sqlite::Statement insert(s.db,
                             "INSERT OR IGNORE INTO origins (origin, event_seq, clock_sample_id, loss_id) "
                             "VALUES (?1, 0, 0, 0)");
    insert.bind(1, origin);
    insert.step();
  }

  // Origin session id -> local session, from the map table or made now.
  std::map<std::int64_t, LocalSession> sessions;
  sqlite::Statement find(s.db,
                         "SELECT o.session_id, s.node, s.end_ns IS NOT NULL FROM origin_sessions o JOIN "
                         "sessions s ON s.id = o.session_id WHERE o.origin = ?1 AND o.origin_session_id = ?2");
  const auto lookup = [&](std::int64_t origin_id) -> std::optional<std::pair<LocalSession, bool>> {
    ResetOnExit done(find);
    find.bind(1, origin);
    find.bind(2, origin_id);
    if (!find.step()) return std::nullopt;
    return std::pair{LocalSession{find.column_int64(0), std::string(find.column_text(1))},
                     find.column_int64(2) != 0};
  };
  for (const Session& session : batch.sessions) {
    if (auto known = lookup(session.id)) {
      if (known->first.node != session.node)
        core::throw_data_error({path(), 0}, fmt::format("ingest from '{}': session {} field 'node' is '{}', "
                                                        "but it was '{}' before",
                                                        origin, session.id, session.node, known->first.node));
      if (session.end && !known->second) {
        // The end, and the configuration the session ended with (Store::end_session).
        sqlite::Statement update(
            s.db, "UPDATE sessions SET end_clock = ?2, end_ns = ?3, config_json = ?4 WHERE id = ?1");
        update.bind(1, known->first.id);
        update.bind(2, static_cast<std::int64_t>(session.end->clock()));
        update.bind(3, session.end->ns());
        update.bind(4, session.config_json);
        update.step();
      }
      sessions[session.id] = known->first;
      continue;
    }
    Session row = session;
    if (row.software_version.empty()) row.software_version = core::kVersion;
    sqlite::Statement insert(s.db, rows::kInsertSession);
    rows::bind_session(insert, row);
    insert.step();
    const std::int64_t local = s.db.last_insert_rowid();
    sqlite::Statement map(s.db,
                          "INSERT INTO origin_sessions (origin, origin_session_id, session_id) "
                          "VALUES (?1, ?2, ?3)");
    map.bind(1, origin);
    map.bind(2, session.id);
    map.bind(3, local);
    map.step();
    sessions[session.id] = {local, session.node};
  }
  const auto local_session = [&](std::int64_t origin_id, std::string_view what,
                                 std::size_t index) -> const LocalSession& {
    if (auto it = sessions.find(origin_id); it != sessions.end()) return it->second;
    if (auto known = lookup(origin_id)) return sessions[origin_id] = known->first;
    core::throw_data_error({path(), 0}, fmt::format("ingest from '{}': {} {} of the batch names origin "
                                                    "session {}, which neither the batch nor an earlier "
                                                    "one carries",
                                                    origin, what, index, origin_id));
  };

  IngestCursor after = before;
  event_spans::SpanBuilder spans;
  for (std::size_t i = 0; i < batch.events.size(); ++i) {
    const StoredEvent& item = batch.events[i];
    if (!take(path(), "event", i, item.seq, before.events, after.events)) continue;
    const LocalSession& local = local_session(item.session_id, "event", i);
    if (item.event.node != local.node)
      core::throw_data_error({path(), 0}, fmt::format("ingest from '{}': event {} of the batch: field 'node' "
                                                      "is '{}', but its session records node '{}'",
                                                      origin, i, item.event.node, local.node));
    rows::bind_event(s.insert_event, local.id, item.event);
    s.insert_event.step();
    s.insert_event.reset();
    spans.add(s.db.last_insert_rowid(), local.id, item.event.channel, item.event.time.clock(),
                item.event.time.ns());
  }
  spans.write(s.insert_span);
  const auto local_id = [&](std::int64_t origin_id, std::string_view what, std::size_t index) {
    return local_session(origin_id, what, index).id;
  };
  ingest_rows(path(), "clock sample", batch.clock_samples, &StoredClockSample::sample, before.clock_samples,
              after.clock_samples, s.insert_clock_sample, rows::bind_clock_sample, local_id);
  ingest_rows(path(), "loss", batch.losses, &StoredLoss::loss, before.losses, after.losses, s.insert_loss,
              rows::bind_loss, local_id);
  ingest_rows(path(), "rate block", batch.rate_blocks, &StoredRateBlock::block, before.rate_blocks,
              after.rate_blocks, s.insert_rate_block, rows::bind_rate_block, local_id);
  ingest_rows(path(), "marker", batch.markers, &StoredMarker::marker, before.markers, after.markers,
              s.insert_marker, rows::bind_marker, local_id);

  sqlite::Statement cursor(s.db,
                           "UPDATE origins SET event_seq = ?2, clock_sample_id = ?3, loss_id = ?4, "
                           "rate_block_id = ?5, marker_id = ?6 WHERE origin = ?1");
  cursor.bind(1, origin);
  cursor.bind(2, after.events);
  cursor.bind(3, after.clock_samples);
  cursor.bind(4, after.losses);
  cursor.bind(5, after.rate_blocks);
  cursor.bind(6, after.markers);
  cursor.step();
  transaction.commit();
  return after;
}

}  // namespace m2mlat::store
