// m2mlat-vm-driver: the real-kernel tests' stimulus and judge, run inside the QEMU guest.
//
// gpio-sim turns a write of "pull-up" / "pull-down" to /sys/devices/platform/<dev>/<chip>/sim_gpioK/pull
// into an edge on line K, and the kernel (gpiolib-cdev) timestamps that edge in its interrupt handler
// during the write. So a CLOCK_REALTIME reading just before the write and one just after it bound the
// event's timestamp: before <= time_ns <= after. The driver makes the edges and logs those readings;
// the verify subcommand holds the events a capture program stored (m2mlat-events/1 CSV) against them.
//
//   info DEV                          chip name, label and line count (GPIO_GET_CHIPINFO_IOCTL)
//   wait-used DEV LINE TIMEOUT_MS     waits until some process has requested the line (so that a
//                                     capture program started in the background is ready for edges);
//                                     prints its consumer; exit 1 on timeout
//   rusage OUT -- CMD ARGS...          runs CMD, passing SIGINT and SIGTERM on to it, and writes its CPU
//                                     time and peak resident memory to OUT:
//                                     "user_us=U sys_us=S status=X maxrss_kb=M"; exits with its status
//   sample --file F --duration-ms D --log OUT [--changes N] [--ready FILE]
//       reads a sysfs value file (an output line's sim_gpioK/value) every 100 us for D ms, or until it
//       has seen N changes, and logs each change of value with the CLOCK_REALTIME readings around the
//       read that saw it
//   verify-pulse --values LOG --events CSV --period-us P [--channel pulse]
//       holds the commanded edges `m2mlat pulse` stored against the line changes sample saw: as many
//       edges as changes, each edge's direction the change's, each commanded before it was seen, on
//       consecutive multiples of the period, flagged commanded and without kernel seqno
//   mirror --value F --sim DIR --delay-us D --duration-ms T [--log OUT] [--changes N] [--ready FILE]
//       the camera, screen and phototransistor of a glass-to-glass test: reads an output line's
//       sim_gpioK/value (the LED) every 100 us and, D us after it saw a change, sets line DIR's pull to
//       the new value (an edge on the input `m2mlat record` captures), for T ms or until it has copied
//       N changes. Logs each change with the CLOCK_REALTIME readings around the read that saw it and
//       around the write that copied it, and prints the median delay the copies really had
//       (lag_low_p50_us..lag_high_p50_us).
//   For sample and mirror, --ready creates FILE after the first read, so that a test starts the line's
//   driver only once it is watched, and --changes makes T a time-out rather than a window: under TCG on
//   a slow host the watcher's own reads slow the program under test's start by seconds, more than any
//   fixed window could allow for.
//   toggle --sim DIR --count N [--period-us P] [--burst B --burst-gap-us G] [--log FILE] [--append]
//          [--watch DEV:LINE --events FILE]
//       N writes, each flipping the pull, P us apart (0: as fast as possible), optionally in bursts of
//       B writes separated by G us. --watch requests the line itself with edge detection and waits for
//       each write's event before the next one (true lockstep), writing the events as m2mlat-events/1.
//   verify --driver LOG --events CSV [--channel NAME] [--edges both|rising|falling] [--refractory-us R]
//          [--allow-missing]
//       Every event must lie inside the window of a driver write of its edge type, in order; seqno
//       must advance by exactly the number of kernel events between two stored ones (so a gap is an
//       edge the kernel reported missing); without --allow-missing the events must be exactly the
//       edges the filter (edge type, refractory period from the last kept edge) lets through.
//       Prints one line of key=value figures; exit 0 pass, 1 fail, 2 usage or unreadable input.
//
// Times are int64 nanoseconds of CLOCK_REALTIME throughout; statistics are printed in microseconds.
// Built fully static (the guest has no C library): g++ -std=c++20 -O2 -static.
#include <fcntl.h>
#include <linux/gpio.h>
#include <poll.h>
#include <signal.h>
#include <sys/ioctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace {

constexpr std::int64_t kNsPerUs = 1000;
constexpr std::int64_t kNsPerS = 1000000000;

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::int64_t clock_ns(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return std::int64_t{ts.tv_sec} * kNsPerS + ts.tv_nsec;
}

std::int64_t parse_int(std::string_view text, std::string_view what) {
  std::int64_t value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc{} || end != text.data() + text.size()) {
    throw UsageError("bad " + std::string(what) + " '" + std::string(text) + "' (expected an integer)");
  }
  return value;
}

// Options as --name value pairs (every option of this program takes a value except --append and
// --allow-missing, which are given "1").
std::map<std::string, std::string> parse_options(int argc, char** argv, int first) {
  std::map<std::string, std::string> options;
  for (int i = first; i < argc; ++i) {
    const std::string name = argv[i];
    if (name.rfind("--", 0) != 0) throw UsageError("unexpected argument '" + name + "'");
    if (name == "--append" || name == "--allow-missing") {
      options[name.substr(2)] = "1";
    } else {
      if (i + 1 >= argc) throw UsageError(name + " needs a value");
      options[name.substr(2)] = argv[++i];
    }
  }
  return options;
}

std::string option_or(const std::map<std::string, std::string>& options, const std::string& name,
                      const std::string& fallback) {
  const auto it = options.find(name);
  return it == options.end() ? fallback : it->second;
}

std::string required(const std::map<std::string, std::string>& options, const std::string& name) {
  const auto it = options.find(name);
  if (it == options.end()) throw UsageError("--" + name + " is required");
  return it->second;
}

// ---- info -----------------------------------------------------------------------------------------

int cmd_info(const std::string& dev) {
  const int fd = open(dev.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    std::fprintf(stderr, "cannot open %s: %s\n", dev.c_str(), std::strerror(errno));
    return 1;
  }
  gpiochip_info info{};
  const int rc = ioctl(fd, GPIO_GET_CHIPINFO_IOCTL, &info);
  close(fd);
  if (rc < 0) {
    std::fprintf(stderr, "GPIO_GET_CHIPINFO_IOCTL on %s: %s\n", dev.c_str(), std::strerror(errno));
    return 1;
  }
  std::printf("name=%s label=%s lines=%u\n", info.name, info.label, info.lines);
  return 0;
}

// ---- wait-used ------------------------------------------------------------------------------------

int cmd_wait_used(const std::string& dev, std::int64_t line, std::int64_t timeout_ms) {
  const int fd = open(dev.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    std::fprintf(stderr, "cannot open %s: %s\n", dev.c_str(), std::strerror(errno));
    return 1;
  }
  const std::int64_t deadline = clock_ns(CLOCK_MONOTONIC) + timeout_ms * 1000000;
  gpio_v2_line_info info{};
  for (;;) {
    info = gpio_v2_line_info{};
    info.offset = static_cast<std::uint32_t>(line);
    if (ioctl(fd, GPIO_V2_GET_LINEINFO_IOCTL, &info) < 0) {
      std::fprintf(stderr, "GPIO_V2_GET_LINEINFO_IOCTL on %s line %lld: %s\n", dev.c_str(),
                   static_cast<long long>(line), std::strerror(errno));
      close(fd);
      return 1;
    }
    if ((info.flags & GPIO_V2_LINE_FLAG_USED) != 0 || clock_ns(CLOCK_MONOTONIC) > deadline) break;
    usleep(20000);
  }
  close(fd);
  if ((info.flags & GPIO_V2_LINE_FLAG_USED) == 0) {
    std::fprintf(stderr, "line %lld of %s still unused after %lld ms\n", static_cast<long long>(line),
                 dev.c_str(), static_cast<long long>(timeout_ms));
    return 1;
  }
  std::printf("consumer=%s\n", info.consumer);
  return 0;
}

// ---- rusage ---------------------------------------------------------------------------------------

pid_t g_child = -1;

void forward_signal(int signal_number) {
  if (g_child > 0) kill(g_child, signal_number);
}

// The child's CPU time from wait4(): the kernel's precise per-task runtime, not a tick count.
int cmd_rusage(const std::string& out_path, char** command) {
  struct sigaction action {};
  action.sa_handler = forward_signal;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  g_child = fork();
  if (g_child < 0) throw std::runtime_error(std::string("fork: ") + std::strerror(errno));
  if (g_child == 0) {
    execvp(command[0], command);
    std::fprintf(stderr, "cannot run %s: %s\n", command[0], std::strerror(errno));
    _exit(127);
  }
  int status = 0;
  rusage usage{};
  while (wait4(g_child, &status, 0, &usage) < 0) {
    if (errno != EINTR) throw std::runtime_error(std::string("wait4: ") + std::strerror(errno));
  }
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  std::FILE* out = std::fopen(out_path.c_str(), "w");
  if (out == nullptr) throw std::runtime_error("cannot write " + out_path);
  // ru_maxrss: the child's peak resident set (its VmHWM), KiB.
  std::fprintf(out, "user_us=%lld sys_us=%lld status=%d maxrss_kb=%ld\n",
               static_cast<long long>(usage.ru_utime.tv_sec) * 1000000 + usage.ru_utime.tv_usec,
               static_cast<long long>(usage.ru_stime.tv_sec) * 1000000 + usage.ru_stime.tv_usec, code,
               usage.ru_maxrss);
  std::fclose(out);
  return code;
}

// ---- toggle ---------------------------------------------------------------------------------------

// A line requested by the driver itself for --watch: input, both edges, CLOCK_REALTIME timestamps,
// no debounce (debounce would move the timestamp out of the hard interrupt handler).
class WatchedLine {
 public:
  WatchedLine(const std::string& dev, unsigned offset) {
    const int chip = open(dev.c_str(), O_RDONLY | O_CLOEXEC);
    if (chip < 0) throw std::runtime_error("cannot open " + dev + ": " + std::strerror(errno));
    gpio_v2_line_request request{};
    request.offsets[0] = offset;
    request.num_lines = 1;
    std::snprintf(request.consumer, sizeof request.consumer, "m2mlat-vm-driver");
    request.config.flags = GPIO_V2_LINE_FLAG_INPUT | GPIO_V2_LINE_FLAG_EDGE_RISING |
                           GPIO_V2_LINE_FLAG_EDGE_FALLING | GPIO_V2_LINE_FLAG_EVENT_CLOCK_REALTIME;
    const int rc = ioctl(chip, GPIO_V2_GET_LINE_IOCTL, &request);
    const int saved = errno;
    close(chip);
    if (rc < 0) throw std::runtime_error("cannot request line of " + dev + ": " + std::strerror(saved));
    fd_ = request.fd;
  }
  WatchedLine(const WatchedLine&) = delete;
  WatchedLine& operator=(const WatchedLine&) = delete;
  ~WatchedLine() { close(fd_); }

  // Waits up to timeout_ms for the next event; false on timeout.
  bool next(gpio_v2_line_event& event, int timeout_ms) {
    pollfd pfd{fd_, POLLIN, 0};
    if (poll(&pfd, 1, timeout_ms) <= 0) return false;
    return read(fd_, &event, sizeof event) == static_cast<ssize_t>(sizeof event);
  }

 private:
  int fd_ = -1;
};

void sleep_until_monotonic(std::int64_t when_ns) {
  timespec ts{};
  ts.tv_sec = when_ns / kNsPerS;
  ts.tv_nsec = when_ns % kNsPerS;
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

int cmd_toggle(const std::map<std::string, std::string>& options) {
  const std::string sim = required(options, "sim");
  const std::int64_t count = parse_int(required(options, "count"), "--count");
  const std::int64_t period_ns = parse_int(option_or(options, "period-us", "0"), "--period-us") * kNsPerUs;
  const std::int64_t burst = parse_int(option_or(options, "burst", "0"), "--burst");
  const std::int64_t burst_gap_ns =
      parse_int(option_or(options, "burst-gap-us", "0"), "--burst-gap-us") * kNsPerUs;
  const bool append = options.count("append") != 0;

  // The current pull decides the first edge: pull-down (gpio-sim's default) -> rising first.
  std::string pull;
  {
    std::ifstream in(sim + "/pull");
    if (!(in >> pull)) throw std::runtime_error("cannot read " + sim + "/pull");
  }
  bool high = pull == "pull-up";
  const int fd = open((sim + "/pull").c_str(), O_WRONLY | O_CLOEXEC);
  if (fd < 0) throw std::runtime_error("cannot open " + sim + "/pull: " + std::strerror(errno));

  std::unique_ptr<WatchedLine> watched;
  std::FILE* events_out = nullptr;
  if (options.count("watch") != 0) {
    const std::string watch = options.at("watch");
    const auto colon = watch.rfind(':');
    if (colon == std::string::npos) throw UsageError("--watch wants DEV:LINE");
    watched = std::make_unique<WatchedLine>(
        watch.substr(0, colon), static_cast<unsigned>(parse_int(watch.substr(colon + 1), "--watch line")));
    events_out = std::fopen(required(options, "events").c_str(), "w");
    if (events_out == nullptr) throw std::runtime_error("cannot write --events file");
    std::fprintf(events_out,
                 "# format: m2mlat-events/1\nnode,channel,edge,clock,time_ns,seqno,line_seqno,flags\n");
  }

  std::FILE* log = nullptr;
  const std::string log_path = option_or(options, "log", "");
  if (!log_path.empty()) {
    const bool fresh = !append || access(log_path.c_str(), F_OK) != 0;
    log = std::fopen(log_path.c_str(), append ? "a" : "w");
    if (log == nullptr) throw std::runtime_error("cannot write " + log_path);
    if (fresh) std::fprintf(log, "index,edge,before_ns,after_ns\n");
  }

  // Writes are scheduled on CLOCK_MONOTONIC from the start, so a late write does not shift the rest.
  std::vector<std::int64_t> before(static_cast<std::size_t>(count));
  std::vector<std::int64_t> after(static_cast<std::size_t>(count));
  std::vector<char> rising(static_cast<std::size_t>(count));
  std::int64_t timeouts = 0;
  const std::int64_t start = clock_ns(CLOCK_MONOTONIC);
  std::int64_t when = start;
  for (std::int64_t i = 0; i < count; ++i) {
    if (i > 0) {
      when += (burst > 0 && i % burst == 0) ? burst_gap_ns : period_ns;
      if (when > start) sleep_until_monotonic(when);
    }
    high = !high;
    const char* value = high ? "pull-up" : "pull-down";
    const auto k = static_cast<std::size_t>(i);
    rising[k] = high ? 1 : 0;
    before[k] = clock_ns(CLOCK_REALTIME);
    const ssize_t written = pwrite(fd, value, std::strlen(value), 0);
    after[k] = clock_ns(CLOCK_REALTIME);
    if (written < 0) throw std::runtime_error("write to " + sim + "/pull: " + std::strerror(errno));
    if (watched) {
      gpio_v2_line_event event{};
      if (!watched->next(event, 1000)) {
        ++timeouts;
        continue;
      }
      std::fprintf(events_out, "driver,watch,%s,realtime,%llu,%u,%u,0\n",
                   event.id == GPIO_V2_LINE_EVENT_RISING_EDGE ? "rising" : "falling",
                   static_cast<unsigned long long>(event.timestamp_ns), event.seqno, event.line_seqno);
    }
  }
  const std::int64_t elapsed_ns = clock_ns(CLOCK_MONOTONIC) - start;
  close(fd);
  if (events_out != nullptr) std::fclose(events_out);

  // The log is written after the run so that file I/O does not disturb the pacing. Indices continue
  // an appended log's numbering only in spirit: verify reads the rows in order and ignores the index.
  if (log != nullptr) {
    for (std::size_t k = 0; k < before.size(); ++k) {
      std::fprintf(log, "%zu,%s,%lld,%lld\n", k, rising[k] ? "rising" : "falling",
                   static_cast<long long>(before[k]), static_cast<long long>(after[k]));
    }
    std::fclose(log);
  }
  std::int64_t max_write_ns = 0;
  for (std::size_t k = 0; k < before.size(); ++k) max_write_ns = std::max(max_write_ns, after[k] - before[k]);
  std::printf("toggle: writes=%lld elapsed_us=%lld max_write_us=%lld watch_timeouts=%lld\n",
              static_cast<long long>(count), static_cast<long long>(elapsed_ns / kNsPerUs),
              static_cast<long long>(max_write_ns / kNsPerUs), static_cast<long long>(timeouts));
  return timeouts == 0 ? 0 : 1;
}

// ---- verify ---------------------------------------------------------------------------------------

struct Write {
  bool rising;
  std::int64_t before_ns;
  std::int64_t after_ns;
};

struct Stored {
  bool rising;
  std::string clock;
  std::int64_t time_ns;
  std::int64_t seqno;
  std::int64_t line_seqno;
  std::size_t line;    // in the CSV, for messages
  std::int64_t flags;  // -1 when the CSV has no flag_bits (or version 1's flags) column
};

std::vector<std::string> split_csv(const std::string& line) {
  // The files read here never quote (node and channel names are plain words).
  std::vector<std::string> fields;
  std::stringstream in(line);
  std::string field;
  while (std::getline(in, field, ',')) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

std::vector<Write> read_driver_log(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw UsageError("cannot read " + path);
  std::vector<Write> writes;
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    if (line.empty() || line.rfind("index,", 0) == 0) continue;  // an appended run's header
    const auto f = split_csv(line);
    if (f.size() != 4) throw UsageError(path + ": malformed line '" + line + "'");
    writes.push_back({f[1] == "rising", parse_int(f[2], "before_ns"), parse_int(f[3], "after_ns")});
  }
  return writes;
}

std::vector<Stored> read_events(const std::string& path, const std::string& channel) {
  std::ifstream in(path);
  if (!in) throw UsageError("cannot read " + path);
  std::string line;
  std::map<std::string, std::size_t> column;
  std::vector<Stored> events;
  std::size_t number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty() || line[0] == '#') continue;
    const auto f = split_csv(line);
    if (column.empty()) {
      for (std::size_t i = 0; i < f.size(); ++i) column[f[i]] = i;
      for (const char* name : {"channel", "edge", "clock", "time_ns", "seqno", "line_seqno"}) {
        if (column.count(name) == 0) throw UsageError(path + ": no column " + name);
      }
      continue;
    }
    if (!channel.empty() && f.at(column["channel"]) != channel) continue;
    // flag_bits (m2mlat-events/2) or flags (version 1), as 1 + its index; 0 = no such column.
    const std::size_t flag_column = column.count("flag_bits") != 0 ? column["flag_bits"] + 1
                                    : column.count("flags") != 0   ? column["flags"] + 1
                                                                   : 0;
    events.push_back({f.at(column["edge"]) == "rising", f.at(column["clock"]),
                      parse_int(f.at(column["time_ns"]), "time_ns"),
                      parse_int(f.at(column["seqno"]), "seqno"),
                      parse_int(f.at(column["line_seqno"]), "line_seqno"), number,
                      flag_column != 0 ? parse_int(f.at(flag_column - 1), "flag_bits") : -1});
  }
  return events;
}

int cmd_verify(const std::map<std::string, std::string>& options) {
  const auto writes = read_driver_log(required(options, "driver"));
  const auto events = read_events(required(options, "events"), option_or(options, "channel", ""));
  const std::string edges = option_or(options, "edges", "both");
  if (edges != "both" && edges != "rising" && edges != "falling") throw UsageError("bad --edges " + edges);
  const std::int64_t refractory_ns =
      parse_int(option_or(options, "refractory-us", "0"), "--refractory-us") * kNsPerUs;
  const bool allow_missing = options.count("allow-missing") != 0;

  // The writes the kernel turns into events (edge filter).
  std::vector<std::size_t> reported;  // indices into writes
  for (std::size_t i = 0; i < writes.size(); ++i) {
    if (edges == "both" || (edges == "rising") == writes[i].rising) reported.push_back(i);
  }
  std::vector<std::string> failures;

  // Match each event to the write whose window holds its timestamp (windows are disjoint and in order).
  std::vector<std::size_t> position_in_reported(writes.size(), SIZE_MAX);
  for (std::size_t p = 0; p < reported.size(); ++p) position_in_reported[reported[p]] = p;
  std::vector<std::size_t> matched;
  std::vector<std::int64_t> matched_time_ns;  // of matched[k]
  std::int64_t max_delay_ns = 0;
  std::vector<std::int64_t> delays_ns;
  std::size_t w = 0;
  const Stored* previous = nullptr;
  std::size_t previous_write = 0;
  std::int64_t missing = 0;
  for (const Stored& e : events) {
    auto fail = [&](const std::string& what) {
      failures.push_back("event on line " + std::to_string(e.line) + " (time_ns " +
                         std::to_string(e.time_ns) + "): " + what);
    };
    if (e.clock != "realtime") fail("clock is " + e.clock + ", not realtime");
    while (w < writes.size() && writes[w].after_ns < e.time_ns) ++w;
    if (w == writes.size() || writes[w].before_ns > e.time_ns) {
      fail("outside every write's [before, after] window" +
           (w < writes.size()
                ? " (next write starts " + std::to_string(writes[w].before_ns - e.time_ns) + " ns later)"
                : std::string(" (after the last write)")));
      continue;
    }
    if (writes[w].rising != e.rising)
      fail(std::string("edge is ") + (e.rising ? "rising" : "falling") + ", the write made the other");
    if (position_in_reported[w] == SIZE_MAX) {
      fail("its write's edge type was not requested");
      continue;
    }
    if (!matched.empty() && matched.back() == w) {
      fail("a second event for the same write");
      continue;
    }
    // seqno counts the events the kernel emitted for this request: between two stored events it
    // must advance by the number of requested edges between their writes (each one more is an
    // edge dropped by the kernel or suppressed by the refractory filter, never an unaccounted one).
    const auto expected_step = static_cast<std::int64_t>(
        previous == nullptr ? position_in_reported[w] + 1
                            : position_in_reported[w] - position_in_reported[previous_write]);
    const std::int64_t step = previous == nullptr ? e.seqno : e.seqno - previous->seqno;
    const std::int64_t line_step = previous == nullptr ? e.line_seqno : e.line_seqno - previous->line_seqno;
    if (step != expected_step) {
      fail("seqno advanced by " + std::to_string(step) + " where " + std::to_string(expected_step) +
           " edges were made");
    }
    if (line_step != expected_step) {
      fail("line_seqno advanced by " + std::to_string(line_step) + " where " + std::to_string(expected_step) +
           " edges were made");
    }
    missing += expected_step - 1;
    delays_ns.push_back(e.time_ns - writes[w].before_ns);
    max_delay_ns = std::max(max_delay_ns, e.time_ns - writes[w].before_ns);
    matched.push_back(w);
    matched_time_ns.push_back(e.time_ns);
    previous = &e;
    previous_write = w;
  }

  // Among them, the ones the refractory filter keeps (measured from the last kept edge). A stored
  // edge's time is known exactly; another's only to lie in its write's window. Where the bounds cannot
  // decide (the host stalled the guest in the middle of a write, making its window long), an edge
  // that is stored counts as kept and one that is not as suppressed: the filter's own timestamps
  // decided, and they are in the windows. Such cases are counted in the report.
  std::vector<std::int64_t> exact_ns(writes.size(), -1);
  for (std::size_t k = 0; k < matched.size(); ++k) exact_ns[matched[k]] = matched_time_ns[k];
  const auto earliest = [&](std::size_t i) { return exact_ns[i] >= 0 ? exact_ns[i] : writes[i].before_ns; };
  const auto latest = [&](std::size_t i) { return exact_ns[i] >= 0 ? exact_ns[i] : writes[i].after_ns; };
  std::vector<std::size_t> expected;
  std::size_t undecided = 0;
  for (const std::size_t i : reported) {
    if (refractory_ns > 0 && !expected.empty()) {
      const std::size_t last = expected.back();
      if (latest(i) - earliest(last) < refractory_ns) continue;  // surely a bounce
      if (earliest(i) - latest(last) < refractory_ns) {
        ++undecided;
        if (exact_ns[i] < 0) continue;
      }
    }
    expected.push_back(i);
  }

  // Which of the expected edges are missing, which stored events were not expected.
  std::vector<std::size_t> absent;
  std::set_difference(expected.begin(), expected.end(), matched.begin(), matched.end(),
                      std::back_inserter(absent));
  std::vector<std::size_t> unexpected;
  std::set_difference(matched.begin(), matched.end(), expected.begin(), expected.end(),
                      std::back_inserter(unexpected));
  if (!unexpected.empty()) {
    failures.push_back(std::to_string(unexpected.size()) +
                       " stored events the filter should have suppressed (first: write " +
                       std::to_string(unexpected.front()) + ")");
  }
  if (!absent.empty() && !allow_missing) {
    failures.push_back(std::to_string(absent.size()) + " expected events missing (first: write " +
                       std::to_string(absent.front()) + ")");
  }

  std::sort(delays_ns.begin(), delays_ns.end());
  const std::int64_t median_delay_ns = delays_ns.empty() ? 0 : delays_ns[delays_ns.size() / 2];
  std::printf(
      "verify: writes=%zu requested=%zu expected=%zu events=%zu seqno_gap=%lld absent=%zu "
      "median_delay_us=%lld max_delay_us=%lld undecided=%zu result=%s\n",
      writes.size(), reported.size(), expected.size(), events.size(), static_cast<long long>(missing),
      absent.size(), static_cast<long long>(median_delay_ns / kNsPerUs),
      static_cast<long long>(max_delay_ns / kNsPerUs), undecided, failures.empty() ? "pass" : "fail");
  for (std::size_t i = 0; i < failures.size() && i < 10; ++i) std::printf("  %s\n", failures[i].c_str());
  if (failures.size() > 10) std::printf("  ... and %zu more\n", failures.size() - 10);
  return failures.empty() ? 0 : 1;
}

// ---- sample and verify-pulse ----------------------------------------------------------------------

// The watchers' --ready FILE: created (empty) once the first read is done.
void say_ready(const std::map<std::string, std::string>& options) {
  const auto ready = options.find("ready");
  if (ready == options.end()) return;
  std::FILE* file = std::fopen(ready->second.c_str(), "w");
  if (file == nullptr) throw std::runtime_error("cannot write --ready file " + ready->second);
  std::fclose(file);
}

// The watchers' --changes N: how many changes end the watch (0: only the time-out does).
std::size_t wanted_changes(const std::map<std::string, std::string>& options) {
  const auto changes = options.find("changes");
  return changes == options.end() ? 0 : static_cast<std::size_t>(parse_int(changes->second, "--changes"));
}

int cmd_sample(const std::map<std::string, std::string>& options) {
  const std::string file = required(options, "file");
  const std::int64_t duration_ns = parse_int(required(options, "duration-ms"), "--duration-ms") * 1000000;
  const int fd = open(file.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw std::runtime_error("cannot open " + file + ": " + std::strerror(errno));
  struct Change {
    std::int64_t before_ns, after_ns;
    char value;
  };
  std::vector<Change> changes;  // the first row is the value found at the start
  const std::size_t wanted = wanted_changes(options);
  char last = 0;
  std::size_t reads = 0;
  const std::int64_t end = clock_ns(CLOCK_MONOTONIC) + duration_ns;
  while (clock_ns(CLOCK_MONOTONIC) < end && (wanted == 0 || changes.size() <= wanted)) {
    char buffer[8] = {};
    const std::int64_t before = clock_ns(CLOCK_REALTIME);
    const ssize_t n = pread(fd, buffer, sizeof buffer - 1, 0);
    const std::int64_t after = clock_ns(CLOCK_REALTIME);
    if (n <= 0) throw std::runtime_error("read " + file + ": " + std::strerror(errno));
    if (reads++ == 0) say_ready(options);
    if (buffer[0] != last) changes.push_back({before, after, buffer[0]});
    last = buffer[0];
    // 100 us between reads: far finer than any pulse period, and it leaves the (single) CPU to the
    // program under test.
    const timespec pause{0, 100 * kNsPerUs};
    nanosleep(&pause, nullptr);
  }
  close(fd);
  std::FILE* log = std::fopen(required(options, "log").c_str(), "w");
  if (log == nullptr) throw std::runtime_error("cannot write --log file");
  // The first row is the value found at the start, not a change.
  std::fprintf(log, "before_ns,after_ns,value\n");
  for (const auto& c : changes)
    std::fprintf(log, "%lld,%lld,%c\n", static_cast<long long>(c.before_ns),
                 static_cast<long long>(c.after_ns), c.value);
  std::fclose(log);
  std::printf("sample: reads=%zu changes=%zu\n", reads, changes.empty() ? 0 : changes.size() - 1);
  return 0;
}

int cmd_mirror(const std::map<std::string, std::string>& options) {
  const std::string file = required(options, "value");
  const std::string pull = required(options, "sim") + "/pull";
  const std::int64_t delay_ns = parse_int(required(options, "delay-us"), "--delay-us") * kNsPerUs;
  const std::int64_t duration_ns = parse_int(required(options, "duration-ms"), "--duration-ms") * 1000000;
  const int fd = open(file.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw std::runtime_error("cannot open " + file + ": " + std::strerror(errno));
  const int out = open(pull.c_str(), O_WRONLY | O_CLOEXEC);
  if (out < 0) throw std::runtime_error("cannot open " + pull + ": " + std::strerror(errno));
  struct Copy {
    std::int64_t due_mono;                 // when to write, CLOCK_MONOTONIC
    std::int64_t seen_before, seen_after;  // CLOCK_REALTIME around the read that saw the change
    std::int64_t written_before = 0, written_after = 0;
    char value;
  };
  std::vector<Copy> copies;
  std::size_t next = 0;  // the first copy not yet written
  const std::size_t wanted = wanted_changes(options);
  char last = 0;
  const std::int64_t end = clock_ns(CLOCK_MONOTONIC) + duration_ns;
  const auto watching = [&] { return clock_ns(CLOCK_MONOTONIC) < end && (wanted == 0 || copies.size() < wanted); };
  while (watching() || next < copies.size()) {
    for (; next < copies.size() && clock_ns(CLOCK_MONOTONIC) >= copies[next].due_mono; ++next) {
      auto& c = copies[next];
      const char* word = c.value == '1' ? "pull-up" : "pull-down";
      c.written_before = clock_ns(CLOCK_REALTIME);
      if (pwrite(out, word, std::strlen(word), 0) < 0)
        throw std::runtime_error("write " + pull + ": " + std::strerror(errno));
      c.written_after = clock_ns(CLOCK_REALTIME);
    }
    if (watching()) {  // else only the copies still due are left to write
      char buffer[8] = {};
      const std::int64_t before = clock_ns(CLOCK_REALTIME);
      const ssize_t n = pread(fd, buffer, sizeof buffer - 1, 0);
      const std::int64_t after = clock_ns(CLOCK_REALTIME);
      if (n <= 0) throw std::runtime_error("read " + file + ": " + std::strerror(errno));
      if (last == 0) say_ready(options);
      if (last != 0 && buffer[0] != last)
        copies.push_back({clock_ns(CLOCK_MONOTONIC) + delay_ns, before, after, 0, 0, buffer[0]});
      last = buffer[0];
    }
    const timespec pause{0, 100 * kNsPerUs};
    nanosleep(&pause, nullptr);
  }
  close(fd);
  close(out);
  if (options.count("log") != 0) {
    std::FILE* log = std::fopen(options.at("log").c_str(), "w");
    if (log == nullptr) throw std::runtime_error("cannot write --log file");
    std::fprintf(log, "seen_before_ns,seen_after_ns,written_before_ns,written_after_ns,value\n");
    for (const auto& c : copies)
      std::fprintf(log, "%lld,%lld,%lld,%lld,%c\n", static_cast<long long>(c.seen_before),
                   static_cast<long long>(c.seen_after), static_cast<long long>(c.written_before),
                   static_cast<long long>(c.written_after), c.value);
    std::fclose(log);
  }
  // The delay each copy really had, from the read that saw the change to the write that copied it:
  // at least written_before - seen_after, at most written_after - seen_before (medians, us). A
  // glass-to-glass sample adds to it how long the change waited for that read (0..100 us and the
  // guest's scheduling).
  std::vector<std::int64_t> low, high;
  for (const auto& c : copies) {
    low.push_back(c.written_before - c.seen_after);
    high.push_back(c.written_after - c.seen_before);
  }
  const auto median_us = [](std::vector<std::int64_t> v) -> long long {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return (v[(v.size() - 1) / 2] + v[v.size() / 2]) / 2 / kNsPerUs;
  };
  std::printf("mirror: changes=%zu delay_us=%lld lag_low_p50_us=%lld lag_high_p50_us=%lld\n", copies.size(),
              static_cast<long long>(delay_ns / kNsPerUs), median_us(low), median_us(high));
  return 0;
}

int cmd_verify_pulse(const std::map<std::string, std::string>& options) {
  const std::int64_t period_ns = parse_int(required(options, "period-us"), "--period-us") * kNsPerUs;
  if (period_ns <= 0) throw UsageError("--period-us must be positive");
  const auto events = read_events(required(options, "events"), option_or(options, "channel", "pulse"));
  struct Change {
    std::int64_t before_ns, after_ns;
    bool high;
  };
  std::vector<Change> changes;
  {
    const std::string path = required(options, "values");
    std::ifstream in(path);
    if (!in) throw UsageError("cannot read " + path);
    std::string line;
    std::getline(in, line);  // header
    bool first = true;
    while (std::getline(in, line)) {
      const auto f = split_csv(line);
      if (f.size() != 3) throw UsageError(path + ": malformed line '" + line + "'");
      if (first) {  // the value at the start
        first = false;
        continue;
      }
      changes.push_back({parse_int(f[0], "before_ns"), parse_int(f[1], "after_ns"), f[2] == "1"});
    }
  }
  std::vector<std::string> failures;
  if (events.empty()) failures.push_back("no commanded edge stored");
  if (events.size() != changes.size())
    failures.push_back(std::to_string(events.size()) + " commanded edges stored, " +
                       std::to_string(changes.size()) + " changes of the line seen");
  std::int64_t max_late_ns = 0, max_seen_ns = 0;
  std::vector<std::int64_t> seen_ns;
  for (std::size_t i = 0; i < events.size(); ++i) {
    const Stored& e = events[i];
    const auto fail = [&](const std::string& what) {
      failures.push_back("edge " + std::to_string(i) + " (time_ns " + std::to_string(e.time_ns) +
                         "): " + what);
    };
    if (e.clock != "realtime") fail("clock is " + e.clock);
    // Bits 2 (no kernel seqno) and 4 (commanded) of the event flags.
    if (e.flags < 0 || (e.flags & 0x14) != 0x14) fail("flags " + std::to_string(e.flags) + " lack commanded");
    // The first edge falls on a multiple of the period, every one after on the next multiple.
    const std::int64_t late = e.time_ns % period_ns;
    max_late_ns = std::max(max_late_ns, late);
    if (late >= period_ns / 2)
      fail("commanded " + std::to_string(late / kNsPerUs) + " us after its deadline");
    if (i > 0) {
      const std::int64_t step = e.time_ns / period_ns - events[i - 1].time_ns / period_ns;
      if (step != 1)
        fail("on the " + std::to_string(step) + "th period after the previous edge, not the next");
    }
    if (i < changes.size()) {
      if (changes[i].high != e.rising) fail("stored as the other direction than the line changed");
      if (changes[i].after_ns < e.time_ns) fail("the line changed before it was commanded");
      seen_ns.push_back(changes[i].after_ns - e.time_ns);
      max_seen_ns = std::max(max_seen_ns, changes[i].after_ns - e.time_ns);
    }
  }
  std::sort(seen_ns.begin(), seen_ns.end());
  std::printf(
      "verify-pulse: edges=%zu changes=%zu max_late_us=%lld median_seen_after_us=%lld max_seen_after_us=%lld "
      "result=%s\n",
      events.size(), changes.size(), static_cast<long long>(max_late_ns / kNsPerUs),
      static_cast<long long>(seen_ns.empty() ? 0 : seen_ns[seen_ns.size() / 2] / kNsPerUs),
      static_cast<long long>(max_seen_ns / kNsPerUs), failures.empty() ? "pass" : "fail");
  for (std::size_t i = 0; i < failures.size() && i < 10; ++i) std::printf("  %s\n", failures[i].c_str());
  return failures.empty() ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc < 2)
      throw UsageError(
          "usage: m2mlat-vm-driver info|wait-used|rusage|toggle|verify|sample|verify-pulse|mirror ...");
    const std::string command = argv[1];
    if (command == "info") {
      if (argc != 3) throw UsageError("usage: m2mlat-vm-driver info /dev/gpiochipN");
      return cmd_info(argv[2]);
    }
    if (command == "wait-used") {
      if (argc != 5) throw UsageError("usage: m2mlat-vm-driver wait-used /dev/gpiochipN LINE TIMEOUT_MS");
      return cmd_wait_used(argv[2], parse_int(argv[3], "LINE"), parse_int(argv[4], "TIMEOUT_MS"));
    }
    if (command == "rusage") {
      if (argc < 5 || std::string_view(argv[3]) != "--")
        throw UsageError("usage: m2mlat-vm-driver rusage OUT -- CMD ARGS...");
      return cmd_rusage(argv[2], argv + 4);
    }
    if (command == "toggle") return cmd_toggle(parse_options(argc, argv, 2));
    if (command == "verify") return cmd_verify(parse_options(argc, argv, 2));
    if (command == "sample") return cmd_sample(parse_options(argc, argv, 2));
    if (command == "verify-pulse") return cmd_verify_pulse(parse_options(argc, argv, 2));
    if (command == "mirror") return cmd_mirror(parse_options(argc, argv, 2));
    throw UsageError("unknown command '" + command + "'");
  } catch (const UsageError& e) {
    std::fprintf(stderr, "m2mlat-vm-driver: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "m2mlat-vm-driver: %s\n", e.what());
    return 1;
  }
}
