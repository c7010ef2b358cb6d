// Events through the store as a recorder writes them, and read back as the analyses read them: the
// CPU a stored event costs, and how long a session's reads take at 10^7 (or 10^8) rows.
//
//   m2mlat_store_read_bench [--events N] [--sessions S] [--keep FILE]
//
// N events (default 10^7) in S sessions (default 2) one after the other, each session on two
// channels ("wheel" and "motion", alternate edges 100 us apart, as a busy two-line capture), appended
// in the recorder's batches of 512 events (Store::append, synchronous=NORMAL). Then the store is
// closed, reopened read-only, and timed: the last session's events (Store::events_in_time), its
// timestamps on one channel (Store::timestamps, what pairing reads), a 1-second window of it, the
// event count and channel list. CPU is the process's (user + system) per event. --keep FILE leaves
// the store there instead of in a directory under $TMPDIR that is removed at the end. Exit status 1 if
// a read does not return the number of events written.
#include <fmt/format.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <limits>
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

int run(std::uint64_t n, std::uint64_t sessions, const std::string& path) {
  int status = 0;
  std::vector<std::int64_t> ids;
  const std::uint64_t per_session = n / sessions;
  {
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
      ids.push_back(id);
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
    fmt::print("append: {} events in {} sessions, batches of {}: {:.2f} s CPU ({:.3f} us/event), {:.2f} s wall\n",
               k, sessions, kBatch, cpu, cpu / static_cast<double>(k) * 1e6, wall);
  }
  const auto size = std::filesystem::file_size(path);
  fmt::print("store file: {:.1f} MB ({:.1f} bytes/event)\n", static_cast<double>(size) / 1e6,
             static_cast<double>(size) / static_cast<double>(per_session * sessions));

  store::Options options;
  options.read_only = true;
  const auto s = store::Store::open(path, options);
  const auto timed = [](std::string_view what, auto&& read) {
    const double wall0 = wall_s();
    const auto result = read();
    fmt::print("  {:<52} {:8.3f} s\n", what, wall_s() - wall0);
    return result;
  };
  const auto check = [&](std::string_view what, std::uint64_t got, std::uint64_t want) {
    if (got == want) return;
    fmt::print("  {}: {} events, expected {}\n", what, got, want);
    status = 1;
  };
  const std::int64_t last = ids.back();
  const auto from = core::TimePoint::from_ns(core::Clock::realtime, std::numeric_limits<std::int64_t>::min());
  const auto to = core::TimePoint::from_ns(core::Clock::realtime, std::numeric_limits<std::int64_t>::max());
  store::EventFilter of_session;
  of_session.session_id = last;
  fmt::print("reads of session {} ({} events):\n", last, per_session);
  check("row check", timed("row check (once per Store, before the first read)", [&] {
          s.check_rows();
          return per_session;
        }), per_session);
  check("events", timed("events_in_time, whole session", [&] { return s.events_in_time(from, to, of_session).size(); }),
        per_session);
  store::EventFilter channel = of_session;
  channel.channel = "wheel";
  check("timestamps", timed("timestamps, whole session, one channel", [&] { return s.timestamps(from, to, channel).t_ns.size(); }),
        per_session / 2);
  // One second in the middle of the last session: 10,000 events.
  const std::int64_t middle = kStartNs + static_cast<std::int64_t>(per_session * sessions - per_session / 2) * kSpacingNs;
  const auto w0 = core::TimePoint::from_ns(core::Clock::realtime, middle);
  const auto w1 = core::TimePoint::from_ns(core::Clock::realtime, middle + 1'000'000'000 - 1);
  check("window", timed("events_in_time, 1 s window, no session given", [&] { return s.events_in_time(w0, w1).size(); }),
        std::min<std::uint64_t>(10'000, per_session));
  check("count", timed("event_count of the session", [&] { return static_cast<std::uint64_t>(s.event_count(last)); }),
        per_session);
  timed("channels of the session", [&] { return s.channels(last).size(); });
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  std::uint64_t n = 10'000'000, sessions = 2;
  std::optional<std::string> keep;
  for (int i = 1; i < argc; ++i) {
    const std::string_view arg = argv[i];
    if (i + 1 < argc && arg == "--events") n = std::strtoull(argv[++i], nullptr, 10);
    else if (i + 1 < argc && arg == "--sessions") sessions = std::strtoull(argv[++i], nullptr, 10);
    else if (i + 1 < argc && arg == "--keep") keep = argv[++i];
    else {
      fmt::print(stderr, "usage: m2mlat_store_read_bench [--events N] [--sessions S] [--keep FILE]\n");
      return 2;
    }
  }
  if (sessions == 0 || n < sessions) {
    fmt::print(stderr, "m2mlat_store_read_bench: --events must be at least --sessions, which must be at least 1\n");
    return 2;
  }
  namespace fs = std::filesystem;
  const fs::path dir = keep ? fs::path() : fs::temp_directory_path() / fmt::format("m2mlat-store-read-{}", ::getpid());
  if (!keep) fs::create_directories(dir);
  const std::string path = keep ? *keep : (dir / "events.db").string();
  int status = 2;
  try {
    status = run(n, sessions, path);
  } catch (const std::exception& e) {
    fmt::print(stderr, "m2mlat_store_read_bench: {}\n", e.what());
  }
  if (!keep) fs::remove_all(dir);
  return status;
}
