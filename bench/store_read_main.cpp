// Events through the store as a recorder writes them, and read back as the analyses read them: the
// CPU a stored event costs, and how long the reads of a store of 10^7 (or 10^8) rows take.
//
//   m2mlat_store_read_bench [--events N] [--sessions S] [--keep FILE | --reuse FILE] [--full-check]
//                           [--json FILE]
//
// N events (default 10^7) in S sessions (default 2) one after the other, each session on two
// channels ("wheel" and "motion", alternate edges 100 us apart, as a busy two-line capture), appended
// in the recorder's batches of 512 events (Store::append, synchronous=NORMAL). Then the store is
// closed, reopened read-only and read as an analysis reads a store it has just opened, each step
// timed (wall and CPU seconds, the peak resident memory so far): its sessions, its event count and
// the last session's, that session's channels, one minute of one channel (Store::timestamps: the
// first event read), the whole channel (what pairing reads), the whole session
// (Store::events_in_time), a 1-second window without a session; with --full-check the whole store's
// row check (Store::check_rows, what merge runs) last. --keep FILE leaves the store there instead of
// in a directory under $TMPDIR that is removed at the end; --reuse FILE reads a store a run with
// --keep left, without appending (10^8 events take minutes to append). --json FILE writes the
// figures for bench/report.py. Exit status 1 if a read does not return the number of events written.
#include <fmt/format.h>
#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "m2mlat/core/event.hpp"
#include "m2mlat/store/store.hpp"

namespace {

namespace store = m2mlat::store;
namespace core = m2mlat::core;

constexpr std::int64_t kStartNs = 1'780'304'400'000'000'000;  // 2026-06-01T09:00:00Z
constexpr std::int64_t kSpacingNs = 100'000;                   // one edge every 100 us
constexpr std::size_t kBatch = 512;                            // the recorder's max_batch

double cpu_s() {
  timespec t{};
  ::clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_nsec) * 1e-9;
}

double wall_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Event k of the store (k from 0): alternately on the two channels, 100 us apart.
core::Event event(std::uint64_t k) {
  core::Event e;
  e.node = "vehicle";
  e.channel = k % 2 == 0 ? "wheel" : "motion";
  e.edge = k % 4 < 2 ? core::Edge::rising : core::Edge::falling;
  e.time = core::TimePoint::from_ns(core::Clock::realtime, kStartNs + static_cast<std::int64_t>(k) * kSpacingNs);
  e.seqno = k / 2 + 1;
  e.line_seqno = k / 2 + 1;
  return e;
}

// CPU (user + system) and wall seconds of one step, and the process's peak resident memory after it.
struct Step {
  std::string what;
  double wall_s = 0, cpu_s = 0;
  long peak_mib = 0;
};

long peak_mib() {
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024;  // ru_maxrss is in KiB
}

// Appends `n` events in `sessions` sessions; returns the steps' figures (one: the append).
Step append_events(std::uint64_t n, std::uint64_t sessions, const std::string& path) {
  const std::uint64_t per_session = n / sessions;
  store::Options options;
  options.durability = store::Durability::normal;
  auto s = store::Store::open(path, options);
  const double cpu0 = cpu_s(), wall0 = wall_s();
  std::uint64_t k = 0;
  for (std::uint64_t i = 0; i < sessions; ++i) {
    store::Session session;
    session.label = fmt::format("run-{}", i);
    session.scenario = "bench";
    session.node = "vehicle";
    session.role = core::Role::effect;
    session.start = event(k).time;
    const auto id = s.begin_session(session);
    store::Batch batch;
    batch.session_id = id;
    const std::uint64_t end = k + per_session;
    while (k < end) {
      batch.events.clear();
      for (std::size_t j = 0; j < kBatch && k < end; ++j) batch.events.push_back(event(k++));
      s.append(batch);
    }
    s.end_session(id, event(k - 1).time);
  }
  const double cpu = cpu_s() - cpu0, wall = wall_s() - wall0;
  fmt::print(
      "append: {} events in {} sessions, batches of {}: {:.2f} s CPU ({:.3f} us/event), {:.2f} s wall\n", k,
      sessions, kBatch, cpu, cpu / static_cast<double>(k) * 1e6, wall);
  return {"append", wall, cpu, peak_mib()};
}

// The reads of a store as an analysis makes them after opening it: its sessions, the last session's
// count and channels, one minute of one channel (the first event read), then the whole channel and
// the whole session, a 1 s window without a session, and with `full_check` the whole store's row
// check (what merge runs). Each step's figures are printed and returned; `status` becomes 1 if a read
// does not return what the store holds.
// `total` becomes the store's number of events.
std::vector<Step> read_store(const std::string& path, std::optional<std::uint64_t> expected_total,
                             bool full_check, std::uint64_t& total, int& status) {
  std::vector<Step> steps;
  const auto timed = [&](std::string_view what, auto&& read) {
    const double cpu0 = cpu_s(), wall0 = wall_s();
    auto result = read();
    steps.push_back({std::string(what), wall_s() - wall0, cpu_s() - cpu0, peak_mib()});
    const Step& step = steps.back();
    fmt::print("  {:<52} {:8.3f} s wall {:8.3f} s CPU {:6} MiB peak\n", what, step.wall_s, step.cpu_s,
               step.peak_mib);
    return result;
  };
  const auto check = [&](std::string_view what, std::uint64_t got, std::uint64_t want) {
    if (got == want) return;
    fmt::print("  {}: {} events, expected {}\n", what, got, want);
    status = 1;
  };
  store::Options options;
  options.read_only = true;
  const auto s = timed("open (read-only)", [&] { return store::Store::open(path, options); });
  const auto sessions = timed("sessions", [&] { return s.sessions(); });
  if (sessions.empty()) {
    fmt::print("  the store holds no session\n");
    status = 1;
    return steps;
  }
  const std::int64_t last = sessions.back().id;
  total = timed("event_count of the store", [&] { return static_cast<std::uint64_t>(s.event_count()); });
  if (expected_total) check("store", total, *expected_total);
  const auto per_session =
      timed("event_count of the session", [&] { return static_cast<std::uint64_t>(s.event_count(last)); });
  timed("channels of the session", [&] { return s.channels(last).size(); });
  // The store's events are numbered from the first session's on (event(k)), the last session's last.
  const std::uint64_t first_k = total - per_session, end_k = total;
  fmt::print("reads of session {} ({} events):\n", last, per_session);
  store::EventFilter channel;
  channel.session_id = last;
  channel.channel = "wheel";
  // One minute from the middle of the session (an even k: channel "wheel"), one channel: 300,000
  // events of the 600,000 stored in it.
  const std::uint64_t window_k = (first_k + per_session / 2) & ~std::uint64_t{1};
  const std::uint64_t minute_events = std::min<std::uint64_t>(600'000, end_k - window_k);
  const std::int64_t minute0 = event(window_k).time.ns();
  const auto m0 = core::TimePoint::from_ns(core::Clock::realtime, minute0);
  const auto m1 = core::TimePoint::from_ns(
      core::Clock::realtime, minute0 + static_cast<std::int64_t>(minute_events) * kSpacingNs - 1);
  check("minute",
        timed("timestamps, one minute of one channel (first read)",
              [&] { return s.timestamps(m0, m1, channel).t_ns.size(); }),
        (minute_events + 1) / 2);
  const auto from = core::TimePoint::from_ns(core::Clock::realtime, std::numeric_limits<std::int64_t>::min());
  const auto to = core::TimePoint::from_ns(core::Clock::realtime, std::numeric_limits<std::int64_t>::max());
  check("timestamps",
        timed("timestamps, whole session, one channel",
              [&] { return s.timestamps(from, to, channel).t_ns.size(); }),
        per_session / 2);
  store::EventFilter of_session;
  of_session.session_id = last;
  check("events", timed("events_in_time, whole session", [&] { return s.events_in_time(from, to, of_session).size(); }),
        per_session);
  // The minute's first second, no session given: 10,000 events.
  const auto w0 = m0;
  const auto w1 = core::TimePoint::from_ns(core::Clock::realtime, minute0 + 1'000'000'000 - 1);
  check(
      "window",
      timed("events_in_time, 1 s window, no session given", [&] { return s.events_in_time(w0, w1).size(); }),
      std::min<std::uint64_t>(10'000, end_k - window_k));
  if (full_check)
    timed("check_rows, the whole store", [&] {
      s.check_rows();
      return 0;
    });
  return steps;
}

nlohmann::json to_json(const Step& step) {
  return {{"what", step.what}, {"wall_s", step.wall_s}, {"cpu_s", step.cpu_s}, {"peak_mib", step.peak_mib}};
}

constexpr std::string_view kUsage =
    "usage: m2mlat_store_read_bench [--events N] [--sessions S] [--keep FILE | --reuse FILE] [--full-check] "
    "[--json FILE]\n";

}  // namespace

int main(int argc, char** argv) {
  std::uint64_t n = 10'000'000, sessions = 2;
  std::optional<std::string> keep, reuse, json_path;
  bool full_check = false;
  for (int i = 1; i < argc; ++i) {
    const std::string_view arg = argv[i];
    if (i + 1 < argc && arg == "--events") n = std::strtoull(argv[++i], nullptr, 10);
    else if (i + 1 < argc && arg == "--sessions") sessions = std::strtoull(argv[++i], nullptr, 10);
    else if (i + 1 < argc && arg == "--keep") keep = argv[++i];
    else if (i + 1 < argc && arg == "--reuse")
      reuse = argv[++i];
    else if (i + 1 < argc && arg == "--json")
      json_path = argv[++i];
    else if (arg == "--full-check")
      full_check = true;
    else {
      fmt::print(stderr, "{}", kUsage);
      return 2;
    }
  }
  if (sessions == 0 || n < sessions || (keep && reuse)) {
    fmt::print(stderr,
               "{}m2mlat_store_read_bench: --events must be at least --sessions, which must be at least 1\n",
               kUsage);
    return 2;
  }
  namespace fs = std::filesystem;
  const bool temporary = !keep && !reuse;
  const fs::path dir =
      temporary ? fs::temp_directory_path() / fmt::format("m2mlat-store-read-{}", ::getpid()) : fs::path();
  if (temporary) fs::create_directories(dir);
  const std::string path = keep ? *keep : reuse ? *reuse : (dir / "events.db").string();
  int status = 0;
  try {
    nlohmann::json out;
    std::optional<std::uint64_t> written;
    if (!reuse) {
      out["append"] = to_json(append_events(n, sessions, path));
      written = n / sessions * sessions;
    }
    const auto size = fs::file_size(path);
    fmt::print("store file: {:.1f} MB\n", static_cast<double>(size) / 1e6);
    nlohmann::json steps = nlohmann::json::array();
    std::uint64_t total = 0;
    for (const Step& step : read_store(path, written, full_check, total, status))
      steps.push_back(to_json(step));
    out["steps"] = steps;
    out["events"] = total;
    out["bytes"] = size;
    if (json_path) std::ofstream(*json_path) << out.dump() << '\n';
  } catch (const std::exception& e) {
    fmt::print(stderr, "m2mlat_store_read_bench: {}\n", e.what());
    status = 2;
  }
  if (temporary) fs::remove_all(dir);
  return status;
}
