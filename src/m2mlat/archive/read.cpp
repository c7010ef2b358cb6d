// Listing the archive's campaigns and giving one back as a campaign store.
#include "m2mlat/archive/read.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <set>

#include "m2mlat/archive/schema.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/core/number.hpp"
#include "m2mlat/store/rate_block.hpp"

namespace m2mlat::archive {

namespace {

// A number of the archive's row `key` in `table`; a non-number names where it is.
std::int64_t number(const Rows& rows, std::size_t r, std::size_t c, const char* table,
                    const std::string& key) {
  std::int64_t v = 0;
  if (!core::parse_integer(rows.at(r, c), v))
    throw core::Error(core::ErrorKind::data,
                      fmt::format("archive m2mlat.{} row {}: {} '{}' is not an integer", table, key,
                                  rows.columns.at(c), rows.at(r, c)));
  return v;
}

template <typename T>
bool selected(const std::vector<T>& wanted, const T& value) {
  return wanted.empty() || std::find(wanted.begin(), wanted.end(), value) != wanted.end();
}

// A PostgreSQL array literal of integers: '{1,2,3}'.
std::string int_array(const std::vector<std::int64_t>& values) {
  std::string out = "{";
  for (std::size_t i = 0; i < values.size(); ++i) out += (i ? "," : "") + std::to_string(values[i]);
  return out + "}";
}

// The clock named by an archive column, refused like the store refuses it (naming the row).
core::TimePoint time_of(const std::string& clock, std::int64_t ns, const char* table,
                        const std::string& key) {
  try {
    return core::TimePoint::from_ns(core::parse_clock(clock), ns);
  } catch (const core::Error&) {
    throw core::Error(core::ErrorKind::data,
                      fmt::format("archive m2mlat.{} row {}: unknown clock '{}'", table, key, clock));
  }
}

// encode(samples, 'hex') back to bytes; a malformed text names the row.
std::vector<std::uint8_t> from_hex(const std::string& hex, const std::string& where) {
  const auto digit = [&](char ch) -> std::uint8_t {
    if (ch >= '0' && ch <= '9') return static_cast<std::uint8_t>(ch - '0');
    if (ch >= 'a' && ch <= 'f') return static_cast<std::uint8_t>(ch - 'a' + 10);
    throw core::Error(core::ErrorKind::data, fmt::format("{}: samples are not hex", where));
  };
  if (hex.size() % 2 != 0)
    throw core::Error(core::ErrorKind::data, fmt::format("{}: samples are not hex", where));
  std::vector<std::uint8_t> bytes(hex.size() / 2);
  for (std::size_t i = 0; i < bytes.size(); ++i)
    bytes[i] = static_cast<std::uint8_t>(digit(hex[2 * i]) << 4 | digit(hex[2 * i + 1]));
  return bytes;
}

}  // namespace

std::vector<CampaignInfo> list_campaigns(Connection& c, const CampaignFilter& filter) {
  if (schema_version(c) == 0) return {};
  const auto rows = c.exec(
      "SELECT c.id, c.store_id, c.name, c.rig, c.label, c.created_ns, COALESCE(p.complete, false) "
      "FROM m2mlat.campaigns c LEFT JOIN m2mlat.push_cursors p ON p.campaign_id = c.id "
      "ORDER BY c.created_ns NULLS LAST, c.id");
  std::vector<CampaignInfo> campaigns;
  for (std::size_t r = 0; r < rows.rows.size(); ++r) {
    CampaignInfo info;
    info.id = number(rows, r, 0, "campaigns", rows.at(r, 0));
    info.store_id = rows.at(r, 1);
    info.name = rows.at(r, 2);
    info.rig = rows.at(r, 3);
    info.label = rows.at(r, 4);
    if (rows.rows[r][5]) info.created_ns = number(rows, r, 5, "campaigns", rows.at(r, 0));
    info.complete = rows.at(r, 6) == "t";
    if (!selected(filter.rigs, info.rig) || !selected(filter.labels, info.label)) continue;
    if (!filter.campaigns.empty() && !selected(filter.campaigns, info.name) &&
        !selected(filter.campaigns, info.store_id))
      continue;
    if ((filter.since_ns || filter.until_ns) && !info.created_ns) continue;
    if (filter.since_ns && *info.created_ns < *filter.since_ns) continue;
    if (filter.until_ns && *info.created_ns >= *filter.until_ns) continue;
    campaigns.push_back(std::move(info));
  }
  if (campaigns.empty()) return campaigns;

  std::vector<std::int64_t> ids;
  for (const auto& info : campaigns) ids.push_back(info.id);
  const auto counts = c.exec(
      "SELECT s.campaign_id, s.scenario, count(*), COALESCE(sum(e.n), 0) FROM m2mlat.sessions s "
      "LEFT JOIN (SELECT campaign_id, session_id, count(*) AS n FROM m2mlat.events "
      "           WHERE campaign_id = ANY($1::bigint[]) GROUP BY 1, 2) e "
      "  ON e.campaign_id = s.campaign_id AND e.session_id = s.session_id "
      "WHERE s.campaign_id = ANY($1::bigint[]) GROUP BY 1, 2 ORDER BY 1, 2",
      {int_array(ids)});
  const auto extra = c.exec(
      "SELECT c.id, (SELECT count(*) FROM m2mlat.clock_samples k WHERE k.campaign_id = c.id), "
      "(SELECT count(*) FROM m2mlat.losses l WHERE l.campaign_id = c.id) "
      "FROM m2mlat.campaigns c WHERE c.id = ANY($1::bigint[])",
      {int_array(ids)});
  for (auto& info : campaigns) {
    for (std::size_t r = 0; r < counts.rows.size(); ++r) {
      if (number(counts, r, 0, "sessions", "") != info.id) continue;
      const auto& scenario = counts.at(r, 1);
      if (!filter.scenarios.empty() && !selected(filter.scenarios, scenario) &&
          !selected(filter.scenarios, info.name + "/" + scenario))
        continue;
      info.scenarios.push_back(
          {scenario, number(counts, r, 2, "sessions", scenario), number(counts, r, 3, "events", scenario)});
    }
    for (std::size_t r = 0; r < extra.rows.size(); ++r)
      if (number(extra, r, 0, "campaigns", "") == info.id) {
        info.clock_samples = number(extra, r, 1, "clock_samples", "");
        info.losses = number(extra, r, 2, "losses", "");
      }
  }
  std::erase_if(campaigns, [](const CampaignInfo& info) { return info.scenarios.empty(); });
  return campaigns;
}

std::map<std::pair<std::int64_t, std::string>, std::string> scenario_names(
    const std::vector<CampaignInfo>& campaigns) {
  std::map<std::string, int> holders;
  for (const auto& info : campaigns)
    for (const auto& s : info.scenarios) ++holders[s.name];
  std::map<std::pair<std::int64_t, std::string>, std::string> names;
  for (const auto& info : campaigns)
    for (const auto& s : info.scenarios)
      names[{info.id, s.name}] = holders[s.name] > 1 ? info.name + "/" + s.name : s.name;
  return names;
}

void read_campaign(Connection& c, const CampaignInfo& campaign,
                   const std::map<std::pair<std::int64_t, std::string>, std::string>& names,
                   store::Store& into, std::size_t batch_rows) {
  const auto id = std::to_string(campaign.id);
  store::IngestBatch base;
  base.origin = campaign.store_id;
  const auto sessions = c.exec(
      "SELECT session_id, label, scenario, node, role, config_json, clock, start_ns, end_ns, "
      "software_version "
      "FROM m2mlat.sessions WHERE campaign_id = $1 ORDER BY session_id",
      {id});
  for (std::size_t r = 0; r < sessions.rows.size(); ++r) {
    const auto name = names.find({campaign.id, sessions.at(r, 2)});
    const auto key = fmt::format("({}, {})", id, sessions.at(r, 0));
    store::Session s;
    s.id = number(sessions, r, 0, "sessions", key);
    s.label = sessions.at(r, 1);
    s.scenario = name == names.end() ? sessions.at(r, 2) : name->second;
    s.node = sessions.at(r, 3);
    s.role = core::parse_role(sessions.at(r, 4));
    s.config_json = sessions.at(r, 5);
    s.start = time_of(sessions.at(r, 6), number(sessions, r, 7, "sessions", key), "sessions", key);
    if (sessions.rows[r][8])
      s.end = time_of(sessions.at(r, 6), number(sessions, r, 8, "sessions", key), "sessions", key);
    s.software_version = sessions.at(r, 9);
    base.sessions.push_back(std::move(s));
  }

  // Events in seq order, one ingest per batch (its cursor makes a re-read harmless).
  for (std::int64_t after = 0;;) {
    const auto rows = c.exec(
        "SELECT seq, session_id, node, channel, edge, clock, t_ns, seqno, line_seqno, flags FROM "
        "m2mlat.events "
        "WHERE campaign_id = $1 AND seq > $2 ORDER BY seq LIMIT $3",
        {id, std::to_string(after), std::to_string(batch_rows)});
    if (rows.rows.empty()) break;
    auto batch = base;
    batch.events.reserve(rows.rows.size());
    for (std::size_t r = 0; r < rows.rows.size(); ++r) {
      const auto key = fmt::format("({}, {})", id, rows.at(r, 0));
      store::StoredEvent e;
      e.seq = number(rows, r, 0, "events", key);
      e.session_id = number(rows, r, 1, "events", key);
      e.event.node = rows.at(r, 2);
      e.event.channel = rows.at(r, 3);
      e.event.edge = core::parse_edge(rows.at(r, 4));
      e.event.time = time_of(rows.at(r, 5), number(rows, r, 6, "events", key), "events", key);
      e.event.seqno = static_cast<std::uint64_t>(number(rows, r, 7, "events", key));
      e.event.line_seqno = static_cast<std::uint64_t>(number(rows, r, 8, "events", key));
      e.event.flags = static_cast<std::uint32_t>(number(rows, r, 9, "events", key));
      batch.events.push_back(std::move(e));
    }
    after = batch.events.back().seq;
    into.ingest(batch);
  }

  auto batch = base;
  const auto samples = c.exec(
      "SELECT id, session_id, clock, t_ns, source, offset_ns, max_error_ns, est_error_ns, synchronised, "
      "detail_json "
      "FROM m2mlat.clock_samples WHERE campaign_id = $1 ORDER BY id",
      {id});
  for (std::size_t r = 0; r < samples.rows.size(); ++r) {
    const auto key = fmt::format("({}, {})", id, samples.at(r, 0));
    store::StoredClockSample s;
    s.id = number(samples, r, 0, "clock_samples", key);
    s.sample.session_id = number(samples, r, 1, "clock_samples", key);
    s.sample.time =
        time_of(samples.at(r, 2), number(samples, r, 3, "clock_samples", key), "clock_samples", key);
    s.sample.source = samples.at(r, 4);
    s.sample.offset_ns = number(samples, r, 5, "clock_samples", key);
    s.sample.max_error_ns = number(samples, r, 6, "clock_samples", key);
    s.sample.est_error_ns = number(samples, r, 7, "clock_samples", key);
    s.sample.synchronised = samples.at(r, 8) == "t";
    s.sample.detail_json = samples.at(r, 9);
    batch.clock_samples.push_back(std::move(s));
  }
  const auto losses = c.exec(
      "SELECT id, session_id, channel, clock, detected_ns, first_missing, count, kind FROM m2mlat.losses "
      "WHERE campaign_id = $1 ORDER BY id",
      {id});
  for (std::size_t r = 0; r < losses.rows.size(); ++r) {
    const auto key = fmt::format("({}, {})", id, losses.at(r, 0));
    store::StoredLoss l;
    l.id = number(losses, r, 0, "losses", key);
    l.loss.session_id = number(losses, r, 1, "losses", key);
    l.loss.channel = losses.at(r, 2);
    l.loss.detected_at = time_of(losses.at(r, 3), number(losses, r, 4, "losses", key), "losses", key);
    l.loss.first_missing = static_cast<std::uint64_t>(number(losses, r, 5, "losses", key));
    l.loss.count = static_cast<std::uint64_t>(number(losses, r, 6, "losses", key));
    l.loss.kind = losses.at(r, 7);
    batch.losses.push_back(std::move(l));
  }
  into.ingest(batch);

  // Raw-sample blocks, a few at a time (up to 72 KiB each).
  for (std::int64_t after = 0;;) {
    const auto rows = c.exec(
        "SELECT id, session_id, channel, clock, counts_per_deg_s, first_index, layout, count, "
        "encode(samples, 'hex') "
        "FROM m2mlat.rate_blocks WHERE campaign_id = $1 AND id > $2 ORDER BY id LIMIT 64",
        {id, std::to_string(after)});
    if (rows.rows.empty()) break;
    auto blocks = base;
    for (std::size_t r = 0; r < rows.rows.size(); ++r) {
      const auto key = fmt::format("({}, {})", id, rows.at(r, 0));
      const auto where = fmt::format("archive {} m2mlat.rate_blocks row {}", c.name(), key);
      store::StoredRateBlock b;
      b.id = number(rows, r, 0, "rate_blocks", key);
      b.block.session_id = number(rows, r, 1, "rate_blocks", key);
      b.block.channel = rows.at(r, 2);
      b.block.clock = time_of(rows.at(r, 3), 0, "rate_blocks", key).clock();
      if (!core::parse_double(rows.at(r, 4), b.block.counts_per_deg_s))
        throw core::Error(core::ErrorKind::data,
                          fmt::format("{}: counts_per_deg_s '{}'", where, rows.at(r, 4)));
      b.block.first_index = static_cast<std::uint64_t>(number(rows, r, 5, "rate_blocks", key));
      b.block.samples =
          store::rate_block::decode(from_hex(rows.at(r, 8), where), number(rows, r, 6, "rate_blocks", key),
                                    number(rows, r, 7, "rate_blocks", key), where);
      blocks.rate_blocks.push_back(std::move(b));
    }
    after = blocks.rate_blocks.back().id;
    into.ingest(blocks);
  }
}

std::int64_t parse_date(const std::string& text, const std::string& flag) {
  int y = 0;
  unsigned m = 0, d = 0;
  char tail = 0;
  const bool shaped = text.size() == 10 && text[4] == '-' && text[7] == '-' &&
                      std::sscanf(text.c_str(), "%4d-%2u-%2u%c", &y, &m, &d, &tail) == 3;
  const std::chrono::year_month_day day{std::chrono::year{y}, std::chrono::month{m}, std::chrono::day{d}};
  if (!shaped || !day.ok())
    throw core::Error(core::ErrorKind::usage,
                      fmt::format("{} '{}': expected a date YYYY-MM-DD (UTC)", flag, text));
  const auto since_epoch = std::chrono::sys_days{day}.time_since_epoch();
  return std::chrono::duration_cast<std::chrono::nanoseconds>(since_epoch).count();
}

}  // namespace m2mlat::archive
