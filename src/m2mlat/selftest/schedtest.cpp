// The scheduling test: running, reporting and storing a cyclictest run.
#include "m2mlat/selftest/schedtest.hpp"

#include "m2mlat/core/clock_read.hpp"

#include <fmt/format.h>
#include <time.h>

#include <algorithm>

namespace m2mlat::selftest {

namespace {

}  // namespace

SchedtestRun run_schedtest(process::CommandRunner& runner, const CyclictestOptions& options) {
  SchedtestRun run;
  run.options = options;
  run.start = core::realtime_now();
  run.result = run_cyclictest(runner, options);
  run.end = core::realtime_now();
  return run;
}

nlohmann::json schedtest_json(const SchedtestRun& run) {
  const auto& o = run.options;
  nlohmann::json threads = nlohmann::json::array();
  for (const auto& t : run.result.threads) {
    nlohmann::json hist = nlohmann::json::array();
    for (const auto& [us, n] : t.histogram) hist.push_back({us, n});
    threads.push_back({{"cpu", t.cpu},
                       {"cycles", t.cycles},
                       {"min_us", t.min_us},
                       {"avg_us", t.avg_us},
                       {"max_us", t.max_us},
                       {"overflows", t.overflows},
                       {"histogram", hist}});
  }
  return {{"kind", "schedtest"},
          {"tool", "cyclictest"},
          {"tool_version", run.result.version},
          {"cmdline", run.result.cmdline},
          {"settings",
           {{"cpu", o.cpu},
            {"priority", o.priority},
            {"interval_us", o.interval_us},
            {"duration_s", std::chrono::duration_cast<std::chrono::seconds>(o.duration).count()},
            {"histogram_us", o.histogram_us}}},
          {"kernel_release", run.result.kernel_release},
          {"realtime_kernel", run.result.realtime_kernel},
          {"start_ns", run.start.ns()},
          {"end_ns", run.end.ns()},
          {"threads", threads}};
}

std::string schedtest_text(const SchedtestRun& run) {
  std::string out =
      fmt::format("cyclictest {} on kernel {}{}: SCHED_FIFO {}, interval {} us, {} s\n", run.result.version,
                  run.result.kernel_release, run.result.realtime_kernel ? " (PREEMPT_RT)" : "",
                  run.options.priority, run.options.interval_us,
                  std::chrono::duration_cast<std::chrono::seconds>(run.options.duration).count());
  for (const auto& t : run.result.threads) {
    out += fmt::format("cpu {}: {} wake-ups, latency min {} us, avg {:.2f} us, max {} us", t.cpu, t.cycles,
                       t.min_us, t.avg_us, t.max_us);
    out += t.overflows > 0 ? fmt::format(", {} beyond {} us\n", t.overflows, run.options.histogram_us) : "\n";
    // Up to kRows rows: buckets of 1 us while they fit, wider ones (e.g. "20-24 us") otherwise.
    constexpr std::int64_t kRows = 40;
    std::vector<std::pair<std::int64_t, std::uint64_t>> rows;  // (first us of the row, count)
    std::int64_t width = 1;
    if (!t.histogram.empty()) {
      const std::int64_t first = t.histogram.front().first;
      const std::int64_t span = t.histogram.back().first - first + 1;
      if (static_cast<std::int64_t>(t.histogram.size()) > kRows) width = (span + kRows - 1) / kRows;
      for (const auto& [us, n] : t.histogram) {
        const std::int64_t start = first + (us - first) / width * width;
        if (rows.empty() || rows.back().first != start)
          rows.emplace_back(start, n);
        else
          rows.back().second += n;
      }
    }
    std::uint64_t top = 1;
    for (const auto& [us, n] : rows) top = std::max(top, n);
    for (const auto& [us, n] : rows) {
      const auto bar = static_cast<std::size_t>((n * 50 + top - 1) / top);
      const std::string range = width == 1 ? fmt::format("{}", us) : fmt::format("{}-{}", us, us + width - 1);
      out += fmt::format("  {:>11} us {:>9} {}\n", range, n, std::string(bar, '#'));
    }
  }
  return out;
}

std::int64_t store_schedtest(store::Store& store, const std::string& node, const SchedtestRun& run) {
  store::Session session;
  session.label = std::string(kSchedtestLabel);
  session.node = node;
  session.role = core::Role::observer;
  session.config_json = schedtest_json(run).dump();
  session.start = run.start;
  const std::int64_t id = store.begin_session(session);
  store.end_session(id, run.end);
  return id;
}

}  // namespace m2mlat::selftest
