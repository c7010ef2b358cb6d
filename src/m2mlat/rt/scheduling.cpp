// sched_setscheduler, sched_setaffinity, mlockall, and the limits and capabilities behind them.
#include "m2mlat/rt/scheduling.hpp"

#include <fmt/format.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/resource.h>

#include <cerrno>
#include <charconv>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

#include "m2mlat/core/number.hpp"

namespace m2mlat::rt {

namespace {

std::string join_cpus(const std::vector<int>& cpus) {
  std::string out;
  for (int c : cpus) out += (out.empty() ? "" : ",") + std::to_string(c);
  return out;
}

std::uint64_t soft_limit(int resource) {
  rlimit limit{};
  if (getrlimit(resource, &limit) != 0) return 0;
  return limit.rlim_cur == RLIM_INFINITY ? std::numeric_limits<std::uint64_t>::max()
                                         : static_cast<std::uint64_t>(limit.rlim_cur);
}

}  // namespace

Outcome set_fifo_priority(int priority) {
  const int low = sched_get_priority_min(SCHED_FIFO), high = sched_get_priority_max(SCHED_FIFO);
  if (priority < low || priority > high)
    return Outcome::failure(
        fmt::format("SCHED_FIFO priority {} is out of range {}..{}", priority, low, high));
  sched_param param{};
  param.sched_priority = priority;
  if (sched_setscheduler(0, SCHED_FIFO, &param) == 0)
    return Outcome::success(fmt::format("running at SCHED_FIFO priority {}", priority));
  const int err = errno;
  if (err == EPERM)
    return Outcome::failure(
        fmt::format("SCHED_FIFO priority {} not permitted: needs CAP_SYS_NICE (run as root, or `setcap "
                    "cap_sys_nice+ep` on "
                    "the binary) or an RLIMIT_RTPRIO of at least {} (limits.conf: `@gpio - rtprio 99`); the "
                    "current limit is {}",
                    priority, priority, soft_limit(RLIMIT_RTPRIO)));
  return Outcome::failure(fmt::format("SCHED_FIFO priority {}: {}", priority, std::strerror(err)));
}

Outcome set_cpu_affinity(int cpu) {
  if (cpu < 0 || cpu >= CPU_SETSIZE) return Outcome::failure(fmt::format("CPU {} does not exist", cpu));
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(static_cast<std::size_t>(cpu), &set);
  if (sched_setaffinity(0, sizeof set, &set) == 0)
    return Outcome::success(fmt::format("running on CPU {}", cpu));
  const int err = errno;
  if (err == EINVAL)
    return Outcome::failure(
        fmt::format("CPU {} is not available to this process (allowed: {})", cpu, join_cpus(allowed_cpus())));
  if (err == EPERM)
    return Outcome::failure(fmt::format("pinning to CPU {} not permitted: needs CAP_SYS_NICE", cpu));
  return Outcome::failure(fmt::format("pinning to CPU {}: {}", cpu, std::strerror(err)));
}

Outcome lock_memory() {
  if (mlockall(MCL_CURRENT | MCL_FUTURE) == 0) return Outcome::success("memory locked (mlockall)");
  const int err = errno;
  if (err == EPERM || err == ENOMEM)
    return Outcome::failure(fmt::format(
        "mlockall not permitted: needs CAP_IPC_LOCK (run as root, or `setcap cap_ipc_lock+ep` on the binary) "
        "or "
        "a larger RLIMIT_MEMLOCK (limits.conf: `@gpio - memlock unlimited`); the current limit is {} bytes",
        soft_limit(RLIMIT_MEMLOCK)));
  return Outcome::failure(fmt::format("mlockall: {}", std::strerror(err)));
}

std::vector<int> allowed_cpus() {
  std::vector<int> cpus;
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) != 0) return cpus;
  for (int c = 0; c < CPU_SETSIZE; ++c)
    if (CPU_ISSET(static_cast<std::size_t>(c), &set)) cpus.push_back(c);
  return cpus;
}

bool parse_cpu_list(std::string_view text, std::vector<int>& cpus) {
  cpus.clear();
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.remove_suffix(1);
  if (text.empty()) return false;
  const auto number = [](std::string_view t, int& value) {
    return core::parse_integer(t, value) && value >= 0;
  };
  while (!text.empty()) {
    const auto comma = text.find(',');
    const auto item = text.substr(0, comma);
    text = comma == std::string_view::npos ? std::string_view{} : text.substr(comma + 1);
    const auto dash = item.find('-');
    int first = 0, last = 0;
    if (dash == std::string_view::npos) {
      if (!number(item, first)) return false;
      last = first;
    } else if (!number(item.substr(0, dash), first) || !number(item.substr(dash + 1), last) || last < first) {
      return false;
    }
    for (int c = first; c <= last; ++c) cpus.push_back(c);
  }
  return true;
}

bool status_has_capability(std::string_view text, int cap) {
  const auto pos = text.find("CapEff:");
  if (pos == std::string_view::npos || cap < 0 || cap > 63) return false;
  auto rest = text.substr(pos + 7);
  while (!rest.empty() && (rest.front() == ' ' || rest.front() == '\t')) rest.remove_prefix(1);
  std::uint64_t mask = 0;
  const auto [end, ec] = std::from_chars(rest.data(), rest.data() + rest.size(), mask, 16);
  if (ec != std::errc{} || end == rest.data()) return false;
  return (mask >> cap) & 1u;
}

bool has_capability(int cap) {
  std::ifstream in("/proc/self/status");
  if (!in) return false;
  std::ostringstream text;
  text << in.rdbuf();
  return status_has_capability(text.str(), cap);
}

Privileges current_privileges() {
  Privileges p;
  p.cap_sys_nice = has_capability(kCapSysNice);
  p.cap_ipc_lock = has_capability(kCapIpcLock);
  p.rtprio_limit = soft_limit(RLIMIT_RTPRIO);
  p.memlock_limit = soft_limit(RLIMIT_MEMLOCK);
  return p;
}

}  // namespace m2mlat::rt
