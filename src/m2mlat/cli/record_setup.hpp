// The options `m2mlat record` and `m2mlat agent` share, and what they make of them: a node's
// capture source (gpio, kmsg or the simulated rig), its recorder options and store options, from a
// TOML configuration (capture/record_config.hpp) and flags (a flag given overrides the file). One
// place so that an agent captures exactly as a recorder would.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "m2mlat/capture/channel.hpp"
#include "m2mlat/capture/gpio_device.hpp"
#include "m2mlat/capture/gyro_channel.hpp"
#include "m2mlat/capture/gyro_source.hpp"
#include "m2mlat/capture/i2c_bus.hpp"
#include "m2mlat/capture/mpu6050.hpp"
#include "m2mlat/capture/recorder.hpp"
#include "m2mlat/capture/source.hpp"
#include "m2mlat/store/records.hpp"
#include "m2mlat/sync/clock_monitor.hpp"

namespace m2mlat::cli {

struct RecordFlags {
  std::string store_path, node, role, scenario, label, config_path, source;
  std::vector<std::string> channels;
  std::string edges = "falling", bias = "as-is", clock = "realtime", refractory = "0", debounce = "0";
  bool active_low = false;
  std::uint64_t count = 0;
  std::string duration;
  std::int64_t batch = 512;
  std::string commit_interval = "100ms", durability = "normal";
  int rt_priority = 0, cpu = -1, irq_cpu = -1;
  bool mlock = false, quiet = false, json = false;
  std::string kmsg = "/dev/kmsg", sim_preset = "static_wifi";
  bool sim_paced = false;
  std::uint64_t sim_seed = 1;
  std::vector<std::string> sim_set;  // "key=value" overrides of the simulated rig (sim/overrides.hpp)
  std::uint32_t event_buffer_size = capture::kMaxEventBufferSize;
  // The clock monitor (gpio and kmsg sources): adjtimex, chronyc and pmc intervals ("0" = off).
  bool no_clock_monitor = false;
  std::string kernel_interval = "1s", chrony_interval = "8s", ptp_interval = "0";
  std::string chronyc_socket, pmc_socket;  // other daemons than the system's (chronyc -h, pmc -s)
  // The gyroscope channel: "/dev/i2c-N[:ADDRESS]" or "sim" (capture/sim_gyro.hpp; empty: none), its channel name, what to keep of
  // its raw samples ("all" or "window:<ms>") and the read period.
  std::string gyro, gyro_channel = "gyro", gyro_keep = "all", gyro_period = "1ms";
  // Which of the flags above were given (a flag overrides the file; a file's channel key overrides
  // the flag's default).
  std::map<std::string, CLI::Option*> options;
  bool given(const std::string& name) const { return options.at(name)->count() > 0; }
};

// A gyroscope's bus from "/dev/i2c-N[:ADDRESS]" (address default 0x68) or "sim" (the simulated
// gyroscope, capture/sim_gyro.hpp, seeded with `seed`); errors name `flag`. Shared by `record`,
// `agent` (--gyro) and `led` (--on-gyro).
struct GyroBus {
  std::unique_ptr<capture::RegisterBus> bus;
  std::string device, address;  // as given ("sim", "0x68" for the simulated one)
};
GyroBus open_gyro_bus(const std::string& flag, const std::string& text, std::uint64_t seed);

// Registers the shared options on `sub`, writing into `flags` (which must outlive parsing).
void add_record_options(CLI::App& sub, RecordFlags& flags);

// The gyroscope channel (--gyro): the bus, the chip, its sampling thread and the channel that turns
// its samples into the store's blocks (capture/gyro_channel.hpp). Start the sampler with start()
// once the stop signal is set up (the thread inherits the blocked signals); the recorder's
// raw_samples hook stops it in the last round, so everything it read is committed.
struct GyroSetup {
  std::unique_ptr<capture::RegisterBus> bus;  // /dev/i2c-N, or the simulated gyroscope's twin
  std::unique_ptr<capture::Mpu6050> chip;
  std::unique_ptr<capture::GyroSource> source;
  std::unique_ptr<capture::GyroChannel> channel;
  void start() { source->start(); }
};

// What the flags and the configuration file make: everything but the store and the loop.
struct RecordSetup {
  std::string node;
  core::Role role = core::Role::observer;
  std::string source_kind;  // gpio | kmsg | sim
  std::vector<capture::ChannelSpec> channels;
  std::unique_ptr<capture::GpioDevices> devices;  // the gpio source's devices (must outlive it)
  std::unique_ptr<capture::Source> source;
  std::vector<std::string> consumers;  // the gpio source's interrupt consumer names
  capture::RecorderOptions options;    // session (node, role, label, scenario, config), batching, limits
  store::Options store_options;
  int rt_priority = 0, cpu = -1, irq_cpu = -1;
  bool mlock = false;
  // The board's clock state beside its events (gpio and kmsg sources; the simulated rig's clocks
  // give their own samples): the monitor, what it reads, and options.before_commit calling it.
  std::unique_ptr<sync::SystemClockSource> clocks;
  std::unique_ptr<process::ProcessRunner> runner;
  std::unique_ptr<sync::ClockMonitor> monitor;
  std::unique_ptr<GyroSetup> gyro;  // --gyro; its hook is options.raw_samples
};

// Reads the configuration file, merges the flags and opens the source (so that a wrong line or a
// missing permission fails before the store is touched). Throws core::Error(usage) for bad flags.
RecordSetup prepare_record(const RecordFlags& flags);

// Applies the real-time settings (memory lock, CPU, FIFO priority, IRQ affinity), each reported;
// a refusal is a warning, not a failure.
void apply_rt(const RecordSetup& setup, bool quiet);

// After a run: the source's notes, and the clock monitor's last failure (chronyc or pmc not answering).
void warn_after_run(const RecordSetup& setup);

// The live counters line on stderr.
void print_counters(const capture::RecordCounters& counters);

}  // namespace m2mlat::cli
