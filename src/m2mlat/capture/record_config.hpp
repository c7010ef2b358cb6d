// The recorder's TOML configuration: the node, its role, and its channels, optionally real-time and
// store settings. Every key is checked; an error names the file, the line and column, and the key
// ("vehicle.toml:7:9: channel[1].edges: 'fallin': use falling, rising or both").
//
//   node = "vehicle"            role = "effect"        scenario = "..."   label = "..."
//   source = "gpio"             # gpio | kmsg | sim
//   kmsg = "/dev/kmsg"          # kmsg source: the device or a followed file
//   [[channel]]
//   name = "wheel"   chip = "pinctrl-rp1"   line = "GPIO16"
//   edges = "falling"   bias = "pull-up"   active_low = false   clock = "realtime"
//   refractory = "10ms" debounce = "0"
//   [rt]     priority = 80   cpu = 3   mlock = true   irq_cpu = 2
//   [store]  batch = 512   commit_interval = "100ms"   durability = "normal"
//   [clock]  monitor = true   kernel_interval = "1s"   chrony_interval = "8s"   ptp_interval = "0"
#pragma once

#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "m2mlat/capture/channel.hpp"
#include "m2mlat/core/event.hpp"
#include "m2mlat/core/time.hpp"

namespace m2mlat::capture {

struct RecordConfig {
  std::optional<std::string> node, scenario, label, source, kmsg;
  std::optional<core::Role> role;
  std::vector<ChannelSpec> channels;
  // Per channel, the keys the file set (so that command-line defaults fill only the others).
  std::vector<std::set<std::string>> channel_keys;
  std::optional<int> rt_priority, cpu, irq_cpu;
  std::optional<bool> mlock;
  std::optional<std::int64_t> batch;
  std::optional<core::Duration> commit_interval;
  std::optional<std::string> durability;
  // The clock monitor (sync::ClockMonitor) of a gpio or kmsg source; intervals 0 = that reading off.
  std::optional<bool> clock_monitor;
  std::optional<core::Duration> kernel_interval, chrony_interval, ptp_interval;
};

// Reads and checks a TOML file. Throws core::Error: no_input if it is missing or no regular file,
// data (naming file:line:column and key) if it is not valid TOML or a key is unknown, mistyped or
// out of range, or if its last line looks cut mid-write (formats::check_input).
RecordConfig load_record_config(const std::string& path);
// The same for text; `name` is the file name used in messages.
RecordConfig parse_record_config(std::string_view text, const std::string& name);

}  // namespace m2mlat::capture
