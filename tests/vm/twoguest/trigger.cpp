// m2mlat-2g-trigger: the host's end of the two-guest test's stimulus (tests/vm/twoguest.sh). It runs
// on the host, whose clock is the one physical time both guests share, and writes the trigger bytes
// of stimulus.cpp to the two guests' stimulus ports (QEMU TCP chardevs) on a fixed schedule:
//
//   cycle i starts at t_i = t_0 + i * PERIOD   (CLOCK_MONOTONIC, absolute sleeps: no drift)
//     t_i              'A' to the operator     (the cause edge, line 0)
//     t_i + DELAY      'A' to the vehicle      (the effect edge, line 0): the true latency is DELAY
//     t_i + PERIOD/2   'B' to both, one right after the other, the order alternating with i
//                      (the shared pulse, line 1): the true offset between the two edges is 0
//
// Each guest echoes every byte after its edge is made; the time from the send to the echo is the
// round trip through QEMU's serial emulation and the guest's kernel, whose spread bounds the delivery
// jitter that separates a guest's edge from the host's send.
//
//   m2mlat-2g-trigger OP_PORT VEH_PORT DELAY_US PERIOD_MS COUNT LOG.csv
// LOG.csv: cycle,what,guest,before_ns,after_ns,echo_ns (CLOCK_MONOTONIC of the host, ns: just before
// and just after the write, so the byte left inside [before, after]; echo_ns empty if no echo came). On
// a busy host the thread can be preempted around the write; the window shows it. On stdout one summary
// line of key=value pairs: the actual delays and pulse skews (from the windows' midpoints), the widest
// window and the round trips (us). Exit 1 if a port cannot be reached or an echo is missing.
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <deque>
#include <string>
#include <vector>

namespace {

constexpr std::int64_t kNsPerS = 1'000'000'000;

std::int64_t now_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * kNsPerS + ts.tv_nsec;
}

timespec to_timespec(std::int64_t ns) {
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(ns / kNsPerS);
  ts.tv_nsec = static_cast<long>(ns % kNsPerS);
  return ts;
}

// One write and its echo.
struct Send {
  long cycle = 0;
  char what = 'A';
  int guest = 0;  // 0 operator, 1 vehicle
  std::int64_t before_ns = 0;
  std::int64_t after_ns = 0;
  std::int64_t echo_ns = -1;
  std::int64_t mid() const { return before_ns + (after_ns - before_ns) / 2; }
};

struct Guest {
  const char* name = "";
  int fd = -1;
  std::deque<std::size_t> waiting;  // indices of sends whose echo has not come yet, oldest first
};

int connect_port(int port) {
  // QEMU listens as soon as it starts; retry for a few seconds in case it is still coming up.
  for (int attempt = 0; attempt < 50; ++attempt) {
    const int fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0) return -1;
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<std::uint16_t>(port));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (connect(fd, reinterpret_cast<const sockaddr*>(&a), sizeof a) == 0) {
      const int one = 1;  // each trigger is one byte and must leave at once
      setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
      return fd;
    }
    close(fd);
    usleep(100'000);
  }
  return -1;
}

// Reads the echoes that have arrived on `g` and gives them to its oldest waiting sends.
bool take_echoes(Guest& g, std::vector<Send>& sends) {
  char buf[64];
  const ssize_t n = recv(g.fd, buf, sizeof buf, MSG_DONTWAIT);
  const std::int64_t t = now_ns();
  if (n == 0) return false;
  if (n < 0) return errno == EAGAIN || errno == EINTR;
  for (ssize_t i = 0; i < n; ++i) {
    if (g.waiting.empty()) continue;
    sends[g.waiting.front()].echo_ns = t;
    g.waiting.pop_front();
  }
  return true;
}

// Waits until `deadline` (CLOCK_MONOTONIC ns), collecting echoes; the last stretch is slept with
// clock_nanosleep so that the send itself is on time.
bool wait_until(std::int64_t deadline, std::array<Guest, 2>& guests, std::vector<Send>& sends) {
  constexpr std::int64_t kSleepSlack = 2'000'000;  // stop polling 2 ms before the deadline
  for (;;) {
    const std::int64_t left = deadline - kSleepSlack - now_ns();
    if (left <= 0) break;
    std::array<pollfd, 2> p{{{guests[0].fd, POLLIN, 0}, {guests[1].fd, POLLIN, 0}}};
    const int r = poll(p.data(), p.size(), static_cast<int>(left / 1'000'000));
    if (r < 0 && errno != EINTR) return false;
    for (std::size_t i = 0; i < p.size(); ++i)
      if (p[i].revents != 0 && !take_echoes(guests[i], sends)) return false;
  }
  const timespec ts = to_timespec(deadline);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
  return true;
}

bool send_byte(std::array<Guest, 2>& guests, int guest, char what, long cycle, std::vector<Send>& sends) {
  const std::int64_t before = now_ns();
  if (write(guests[guest].fd, &what, 1) != 1) return false;
  sends.push_back(Send{cycle, what, guest, before, now_ns(), -1});
  guests[guest].waiting.push_back(sends.size() - 1);
  return true;
}

double percentile(std::vector<std::int64_t> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const auto i = static_cast<std::size_t>(p / 100.0 * static_cast<double>(v.size() - 1) + 0.5);
  return static_cast<double>(v[i]);
}

// "name_med=.. name_p95=.. name_min=.. name_max=.." in us.
std::string summary(const char* name, const std::vector<std::int64_t>& v) {
  if (v.empty()) return std::string(name) + "_n=0";
  const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
  char out[256];
  std::snprintf(out, sizeof out, "%s_med=%.1f %s_p95=%.1f %s_min=%.1f %s_max=%.1f", name,
                percentile(v, 50) / 1e3, name, percentile(v, 95) / 1e3, name, static_cast<double>(*lo) / 1e3,
                name, static_cast<double>(*hi) / 1e3);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 7) {
    std::fprintf(stderr, "usage: m2mlat-2g-trigger OP_PORT VEH_PORT DELAY_US PERIOD_MS COUNT LOG.csv\n");
    return 2;
  }
  const int op_port = std::atoi(argv[1]);
  const int veh_port = std::atoi(argv[2]);
  const std::int64_t delay_ns = std::atoll(argv[3]) * 1000;
  const std::int64_t period_ns = std::atoll(argv[4]) * 1'000'000;
  const long count = std::atol(argv[5]);
  if (delay_ns <= 0 || period_ns <= 2 * delay_ns || count <= 0) {
    std::fprintf(stderr, "m2mlat-2g-trigger: need 0 < 2 * DELAY < PERIOD and COUNT > 0\n");
    return 2;
  }
  std::array<Guest, 2> guests{
      {{"operator", connect_port(op_port), {}}, {"vehicle", connect_port(veh_port), {}}}};
  for (const auto& g : guests)
    if (g.fd < 0) {
      std::fprintf(stderr, "m2mlat-2g-trigger: cannot connect to the %s's stimulus port\n", g.name);
      return 1;
    }
  std::vector<Send> sends;
  sends.reserve(static_cast<std::size_t>(count) * 4);
  // The first cycle starts 200 ms from now, so the connection's set-up is out of the way.
  const std::int64_t t0 = now_ns() + 200'000'000;
  bool ok = true;
  for (long i = 0; ok && i < count; ++i) {
    const std::int64_t ti = t0 + i * period_ns;
    ok = wait_until(ti, guests, sends) && send_byte(guests, 0, 'A', i, sends) &&
         wait_until(ti + delay_ns, guests, sends) && send_byte(guests, 1, 'A', i, sends) &&
         wait_until(ti + period_ns / 2, guests, sends);
    const int first = static_cast<int>(i % 2);
    ok = ok && send_byte(guests, first, 'B', i, sends) && send_byte(guests, 1 - first, 'B', i, sends);
  }
  // The last echoes: up to a second more.
  const std::int64_t give_up = now_ns() + kNsPerS;
  while (ok && (!guests[0].waiting.empty() || !guests[1].waiting.empty()) && now_ns() < give_up)
    ok = wait_until(now_ns() + 10'000'000, guests, sends);
  if (!ok) {
    std::fprintf(stderr, "m2mlat-2g-trigger: a stimulus connection failed: %s\n", std::strerror(errno));
    return 1;
  }

  std::FILE* log = std::fopen(argv[6], "w");
  if (log == nullptr) {
    std::fprintf(stderr, "m2mlat-2g-trigger: %s: %s\n", argv[6], std::strerror(errno));
    return 1;
  }
  std::fprintf(log, "cycle,what,guest,before_ns,after_ns,echo_ns\n");
  const auto n = static_cast<std::size_t>(count);
  std::vector<std::int64_t> a_op(n), a_veh(n), b_op(n), b_veh(n);
  std::vector<std::int64_t> rtt_op, rtt_veh, windows;
  long missing = 0;
  for (const auto& s : sends) {
    std::fprintf(log, "%ld,%c,%s,%lld,%lld,", s.cycle, s.what, guests[s.guest].name,
                 static_cast<long long>(s.before_ns), static_cast<long long>(s.after_ns));
    windows.push_back(s.after_ns - s.before_ns);
    if (s.echo_ns < 0) {
      ++missing;
      std::fprintf(log, "\n");
    } else {
      std::fprintf(log, "%lld\n", static_cast<long long>(s.echo_ns));
      (s.guest == 0 ? rtt_op : rtt_veh).push_back(s.echo_ns - s.mid());
    }
    auto& slot = s.what == 'A' ? (s.guest == 0 ? a_op : a_veh) : (s.guest == 0 ? b_op : b_veh);
    slot[static_cast<std::size_t>(s.cycle)] = s.mid();
  }
  // The actual delay of each latency cycle and the skew of each pulse, vehicle minus operator.
  std::vector<std::int64_t> delays, skews;
  for (std::size_t i = 0; i < n; ++i) {
    delays.push_back(a_veh[i] - a_op[i]);
    skews.push_back(b_veh[i] - b_op[i]);
  }
  std::fclose(log);
  std::printf("sends=%zu missing_echoes=%ld %s %s %s %s %s\n", sends.size(), missing,
              summary("delay", delays).c_str(), summary("skew", skews).c_str(),
              summary("window", windows).c_str(), summary("rtt_op", rtt_op).c_str(),
              summary("rtt_veh", rtt_veh).c_str());
  return missing == 0 ? 0 : 1;
}
