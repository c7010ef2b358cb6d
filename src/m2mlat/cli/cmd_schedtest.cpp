// `m2mlat schedtest`: the scheduling test. Runs cyclictest on the capture core with the reference
// rig's settings (SCHED_FIFO 99, mlockall, one thread, 1 ms interval), prints min/avg/max and the
// histogram of wake-up latencies (us), and with --store keeps the result as a session labelled
// "schedtest" whose config_json holds it (selftest/schedtest.hpp). Needs root (or CAP_SYS_NICE and
// CAP_IPC_LOCK) like cyclictest itself.
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <memory>

#include "m2mlat/cli/command.hpp"
#include "m2mlat/cli/output.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/rt/scheduling.hpp"
#include "m2mlat/selftest/schedtest.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::cli {

namespace {

struct SchedtestCommand {
  selftest::CyclictestOptions options;
  std::string duration = "5s";
  std::string store_path, node;
  bool json = false;
};

int run_schedtest(SchedtestCommand& c) {
  c.options.duration = core::parse_duration(c.duration, 1'000'000'000);
  if (c.options.duration.count() % 1'000'000'000 != 0)
    throw core::Error(core::ErrorKind::usage, "--duration must be whole seconds (cyclictest's unit)");
  // A CPU this process may not run on (beyond the machine's, or outside its cpuset) is the user's
  // mistake: say so, rather than pass cyclictest's libnuma warning on as a failure of the test.
  if (const auto cpus = rt::allowed_cpus();
      !cpus.empty() && std::find(cpus.begin(), cpus.end(), c.options.cpu) == cpus.end()) {
    std::string list;
    for (const int cpu : cpus) list += (list.empty() ? "" : ",") + std::to_string(cpu);
    throw core::Error(core::ErrorKind::usage,
                      fmt::format("--core {}: this process may run on CPUs {} only", c.options.cpu, list));
  }
  process::ProcessRunner runner;
  if (!c.json) fmt::print(stderr, "running cyclictest on cpu {} for {} ...\n", c.options.cpu, c.duration);
  const selftest::SchedtestRun run = selftest::run_schedtest(runner, c.options);
  std::int64_t session = 0;
  if (!c.store_path.empty()) {
    std::string node = c.node;
    if (node.empty()) {
      char name[256] = {};
      node = ::gethostname(name, sizeof name - 1) == 0 && name[0] != '\0' ? name : "localhost";
    }
    auto store = store::Store::open(c.store_path);
    session = selftest::store_schedtest(store, node, run);
  }
  if (c.json) {
    auto doc = selftest::schedtest_json(run);
    if (session > 0) doc["session_id"] = session;
    print_json(doc);
  } else {
    fmt::print("{}", selftest::schedtest_text(run));
    if (session > 0) fmt::print("stored as session {} (label 'schedtest') in {}\n", session, c.store_path);
  }
  return 0;
}

}  // namespace

Runner attach_schedtest(CLI::App& sub) {
  auto c = std::make_shared<SchedtestCommand>();
  sub.add_option("--core", c->options.cpu, "The CPU to test (the capture core)")->required();
  sub.add_option("--duration", c->duration, "How long (whole seconds, e.g. 5s, 2min)")->capture_default_str();
  sub.add_option("--priority", c->options.priority, "SCHED_FIFO priority")->capture_default_str();
  sub.add_option("--interval-us", c->options.interval_us, "Timer interval, us")->capture_default_str();
  sub.add_option("--histogram-us", c->options.histogram_us, "Histogram range in 1 us buckets")
      ->capture_default_str();
  sub.add_option("--cyclictest", c->options.program, "The cyclictest program")->capture_default_str();
  sub.add_option("--store", c->store_path, "Store the result as a session labelled 'schedtest'");
  sub.add_option("--node", c->node, "The node name of that session (default: the host name)");
  sub.add_flag("--json", c->json, "Print the result as JSON");
  return [c] { return run_schedtest(*c); };
}

}  // namespace m2mlat::cli
