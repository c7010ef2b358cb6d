// Scheduling, CPU affinity and memory locking of the calling process, as the reference rig used
// them: a SCHED_FIFO priority so that the reader (or the pulse generator) runs as soon as it is
// woken, a fixed core so that it is not migrated, and locked memory so that a page fault cannot
// stall it. Each function returns an Outcome naming the privilege needed when the kernel refuses
// (CAP_SYS_NICE or RLIMIT_RTPRIO; CAP_IPC_LOCK or RLIMIT_MEMLOCK) instead of throwing.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "m2mlat/rt/outcome.hpp"

namespace m2mlat::rt {

// SCHED_FIFO at `priority` (1..99) for the calling thread's process.
Outcome set_fifo_priority(int priority);
// Runs the calling process on CPU `cpu` only.
Outcome set_cpu_affinity(int cpu);
// mlockall(MCL_CURRENT | MCL_FUTURE).
Outcome lock_memory();

// The CPUs this process may run on, in increasing order.
std::vector<int> allowed_cpus();
// "0-3,6" -> {0,1,2,3,6} (the kernel's cpu-list format, as in smp_affinity_list). Returns false on
// malformed text.
bool parse_cpu_list(std::string_view text, std::vector<int>& cpus);

// Linux capability numbers used in messages and checks (from linux/capability.h).
inline constexpr int kCapIpcLock = 14;
inline constexpr int kCapSysNice = 23;
// True if the effective capability set in a /proc/<pid>/status text ("CapEff:\t000001ffffffffff")
// holds capability `cap`.
bool status_has_capability(std::string_view proc_status_text, int cap);
// The same for this process (reads /proc/self/status; false if unreadable).
bool has_capability(int cap);

// What the process may do without trying it: used by `m2mlat doctor`.
struct Privileges {
  bool cap_sys_nice = false;
  bool cap_ipc_lock = false;
  std::uint64_t rtprio_limit = 0;   // RLIMIT_RTPRIO soft limit (highest FIFO priority allowed)
  std::uint64_t memlock_limit = 0;  // RLIMIT_MEMLOCK soft limit, bytes (UINT64_MAX: unlimited)
  bool can_fifo() const { return cap_sys_nice || rtprio_limit > 0; }
  bool can_mlock_all() const { return cap_ipc_lock || memlock_limit == UINT64_MAX; }
};
Privileges current_privileges();

}  // namespace m2mlat::rt
