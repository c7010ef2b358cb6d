// Copying a campaign store into the archive in resumable batches.
#include "m2mlat/archive/push.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <optional>

#include "m2mlat/archive/schema.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/store/rate_block.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::archive {

namespace {

std::string str(std::int64_t v) { return std::to_string(v); }
// The kernel's uint64 counters as their int64 bits (PostgreSQL has no unsigned type); read_campaign
// casts back.
std::string bits(std::uint64_t v) { return std::to_string(static_cast<std::int64_t>(v)); }

std::optional<std::int64_t> created_ns(const std::vector<store::Session>& sessions) {
  std::optional<std::int64_t> first;
  for (const auto& s : sessions)
    if (s.start.clock() == core::Clock::realtime && (!first || s.start.ns() < *first)) first = s.start.ns();
  return first;
}

std::int64_t upsert_campaign(Connection& c, const store::Store& store, const std::string& path,
                             const PushOptions& options, const std::vector<store::Session>& sessions) {
  const auto created = created_ns(sessions);
  const auto default_name = std::filesystem::path(path).stem().string();
  // A given --name, --rig or --label replaces the stored one; an empty one keeps it.
  const auto rows = c.exec(
      "INSERT INTO m2mlat.campaigns (store_id, name, rig, label, created_ns, created_by) "
      "VALUES ($1, COALESCE(NULLIF($2, ''), $3), $4, $5, $6, $7) "
      "ON CONFLICT (store_id) DO UPDATE SET "
      "  name = COALESCE(NULLIF($2, ''), m2mlat.campaigns.name), "
      "  rig = COALESCE(NULLIF($4, ''), m2mlat.campaigns.rig), "
      "  label = COALESCE(NULLIF($5, ''), m2mlat.campaigns.label), "
      "  created_ns = EXCLUDED.created_ns "
      "RETURNING id",
      {store.store_id(), options.name, default_name, options.rig, options.label,
       created ? std::optional(str(*created)) : std::nullopt, store.created_by()});
  const auto id = std::stoll(rows.at(0, 0));
  c.exec("INSERT INTO m2mlat.push_cursors (campaign_id) VALUES ($1) ON CONFLICT DO NOTHING", {str(id)});
  return id;
}

// Every session of the store, new or with its end now known (a few rows: sent with each batch so
// that the batch's events always find theirs).
std::int64_t upsert_sessions(Connection& c, std::int64_t campaign,
                             const std::vector<store::Session>& sessions) {
  std::int64_t added = 0;
  for (const auto& s : sessions) {
    const auto rows = c.exec(
        "INSERT INTO m2mlat.sessions (campaign_id, session_id, label, scenario, node, role, config_json, "
        "clock, "
        "start_ns, end_ns, software_version) VALUES ($1, $2, $3, $4, $5, $6, $7, $8, $9, $10, $11) "
        "ON CONFLICT (campaign_id, session_id) DO UPDATE SET end_ns = EXCLUDED.end_ns "
        "WHERE m2mlat.sessions.end_ns IS DISTINCT FROM EXCLUDED.end_ns "
        "RETURNING (xmax = 0) AS inserted",
        {str(campaign), str(s.id), s.label, s.scenario, s.node, std::string(core::to_string(s.role)),
         s.config_json, std::string(core::to_string(s.start.clock())), str(s.start.ns()),
         s.end ? std::optional(str(s.end->ns())) : std::nullopt, s.software_version});
    if (!rows.rows.empty() && rows.at(0, 0) == "t") ++added;
  }
  return added;
}

struct Cursor {
  std::int64_t events = 0, clock_samples = 0, losses = 0, rate_blocks = 0;
  bool complete = false;
};

// Raw-sample blocks per transaction: up to 72 KiB each (store/rate_block.hpp), so a few MiB a batch.
constexpr std::size_t kRateBlocksPerBatch = 64;

// A BLOB as bytea's hex input, "\\x0a1b..." (join_line then escapes its backslash for COPY).
std::string bytea_hex(const std::vector<std::uint8_t>& bytes) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string out = "\\x";
  out.reserve(2 + 2 * bytes.size());
  for (const auto b : bytes) {
    out += kDigits[b >> 4];
    out += kDigits[b & 0xf];
  }
  return out;
}

Cursor lock_cursor(Connection& c, std::int64_t campaign) {
  const auto rows = c.exec(
      "SELECT events, clock_samples, losses, rate_blocks, complete FROM m2mlat.push_cursors WHERE "
      "campaign_id = $1 "
      "FOR UPDATE",
      {str(campaign)});
  return {std::stoll(rows.at(0, 0)), std::stoll(rows.at(0, 1)), std::stoll(rows.at(0, 2)),
          std::stoll(rows.at(0, 3)), rows.at(0, 4) == "t"};
}

std::string join_line(std::initializer_list<std::string> fields) {
  std::string line;
  for (const auto& f : fields) {
    if (!line.empty()) line += '\t';
    line += copy_text(f);
  }
  line += '\n';
  return line;
}

}  // namespace

PushSummary push(const std::string& store_path, Connection& c, const PushOptions& options) {
  store::Options read;
  read.read_only = true;
  const auto store = store::Store::open(store_path, read);
  migrate(c);

  PushSummary summary;
  summary.store_id = store.store_id();
  const auto sessions = store.sessions();
  {
    Transaction tx(c);
    summary.campaign_id = upsert_campaign(c, store, store_path, options, sessions);
    tx.commit();
  }
  const auto campaign = str(summary.campaign_id);
  summary.name = c.exec("SELECT name FROM m2mlat.campaigns WHERE id = $1", {campaign}).at(0, 0);
  const auto total = store.event_count();
  const auto count_events = [&] {
    return std::stoll(
        c.exec("SELECT count(*) FROM m2mlat.events WHERE campaign_id = $1", {campaign}).at(0, 0));
  };
  const auto before = count_events();

  for (bool first = true;; first = false) {
    Transaction tx(c);
    auto cursor = lock_cursor(c, summary.campaign_id);
    if (first)
      summary.resumed =
          cursor.events > 0 || cursor.clock_samples > 0 || cursor.losses > 0 || cursor.rate_blocks > 0;
    const auto events = store.events_after(cursor.events, options.batch_rows);
    const auto samples = store.clock_samples_after(cursor.clock_samples, options.batch_rows);
    const auto losses = store.losses_after(cursor.losses, options.batch_rows);
    const auto blocks = store.rate_blocks_after(cursor.rate_blocks, kRateBlocksPerBatch);
    summary.sessions += upsert_sessions(c, summary.campaign_id, sessions);
    if (events.empty() && samples.empty() && losses.empty() && blocks.empty()) {
      c.exec("UPDATE m2mlat.push_cursors SET complete = true WHERE campaign_id = $1", {campaign});
      tx.commit();
      break;
    }
    std::string data;
    for (const auto& e : events) {
      const auto& ev = e.event;
      data += join_line({campaign, str(e.seq), str(e.session_id), ev.node, ev.channel,
                         std::string(core::to_string(ev.edge)), std::string(core::to_string(ev.time.clock())),
                         str(ev.time.ns()), bits(ev.seqno), bits(ev.line_seqno), std::to_string(ev.flags)});
    }
    if (!data.empty()) {
      summary.events += c.copy_in(
          "COPY m2mlat.events (campaign_id, seq, session_id, node, channel, edge, clock, t_ns, seqno, "
          "line_seqno, "
          "flags) FROM STDIN",
          data);
      cursor.events = events.back().seq;
    }
    data.clear();
    for (const auto& s : samples) {
      const auto& cs = s.sample;
      data +=
          join_line({campaign, str(s.id), str(cs.session_id), std::string(core::to_string(cs.time.clock())),
                     str(cs.time.ns()), cs.source, str(cs.offset_ns), str(cs.max_error_ns),
                     str(cs.est_error_ns), cs.synchronised ? "t" : "f", cs.detail_json});
    }
    if (!data.empty()) {
      summary.clock_samples += c.copy_in(
          "COPY m2mlat.clock_samples (campaign_id, id, session_id, clock, t_ns, source, offset_ns, "
          "max_error_ns, "
          "est_error_ns, synchronised, detail_json) FROM STDIN",
          data);
      cursor.clock_samples = samples.back().id;
    }
    data.clear();
    for (const auto& l : losses) {
      const auto& loss = l.loss;
      data += join_line({campaign, str(l.id), str(loss.session_id), loss.channel,
                         std::string(core::to_string(loss.detected_at.clock())), str(loss.detected_at.ns()),
                         bits(loss.first_missing), bits(loss.count), loss.kind});
    }
    if (!data.empty()) {
      summary.losses += c.copy_in(
          "COPY m2mlat.losses (campaign_id, id, session_id, channel, clock, detected_ns, first_missing, "
          "count, kind) "
          "FROM STDIN",
          data);
      cursor.losses = losses.back().id;
    }
    data.clear();
    for (const auto& b : blocks) {
      const auto& block = b.block;
      data += join_line({campaign, str(b.id), str(block.session_id), block.channel,
                         std::string(core::to_string(block.clock)), fmt::format("{}", block.counts_per_deg_s),
                         bits(block.first_index), str(store::rate_block::kLayout),
                         std::to_string(block.samples.size()),
                         bytea_hex(store::rate_block::encode(block.samples))});
    }
    if (!data.empty()) {
      summary.rate_blocks += c.copy_in(
          "COPY m2mlat.rate_blocks (campaign_id, id, session_id, channel, clock, counts_per_deg_s, "
          "first_index, "
          "layout, count, samples) FROM STDIN",
          data);
      cursor.rate_blocks = blocks.back().id;
    }
    c.exec(
        "UPDATE m2mlat.push_cursors SET events = $2, clock_samples = $3, losses = $4, rate_blocks = $5, "
        "complete = false WHERE campaign_id = $1",
        {campaign, str(cursor.events), str(cursor.clock_samples), str(cursor.losses),
         str(cursor.rate_blocks)});
    tx.commit();
    ++summary.batches;
    if (options.progress) options.progress({before + summary.events, total});
  }
  summary.total_events = count_events();
  return summary;
}

}  // namespace m2mlat::archive
