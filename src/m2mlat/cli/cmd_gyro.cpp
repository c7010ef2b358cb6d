// `m2mlat gyro`: records a gyroscope's raw trace (an MPU-6050 on /dev/i2c-N) into a file of format
// m2mlat-gyro/1 (docs/formats.md). The chip is identified (WHO_AM_I), configured (8 kHz, DLPF off,
// +-250 deg/s), and polled at --period on a sampling thread (SCHED_FIFO with --rt-priority), each
// reading stamped with CLOCK_REALTIME around the read. Stops after --duration or at SIGINT/SIGTERM.
// An I2C error mid-run ends the run: the samples taken before it are written, then the error is
// reported (exit 74).
#include <fmt/format.h>
#include <poll.h>

#include <memory>
#include <nlohmann/json.hpp>

#include "m2mlat/capture/gyro_source.hpp"
#include "m2mlat/capture/i2c_bus.hpp"
#include "m2mlat/capture/mpu6050.hpp"
#include "m2mlat/capture/stop_signal.hpp"
#include "m2mlat/cli/command.hpp"
#include "m2mlat/cli/duration_flag.hpp"
#include "m2mlat/cli/output.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/core/output_file.hpp"
#include "m2mlat/core/printable.hpp"
#include "m2mlat/formats/rate_trace_csv.hpp"

namespace m2mlat::cli {

namespace {

struct GyroCommand {
  std::string device, address = "0x68", period = "1ms", duration, out;
  unsigned divider = 0;
  int rt_priority = 0, cpu = -1;
  bool json = false, quiet = false;
};

int run_gyro(const GyroCommand& c) {
  capture::GyroSourceOptions options;
  options.period = duration_flag("--period", c.period);
  options.duration = duration_flag("--duration", c.duration, true);
  options.rt_priority = c.rt_priority;
  options.cpu = c.cpu;
  // The chip's output period: 8 kHz / (1 + SMPLRT_DIV), the age the values may have at a read.
  options.chip_output_period =
      core::Duration{1'000'000'000 / capture::mpu6050::kGyroRateHz * (1 + c.divider)};
  if (options.period.count() <= 0) throw core::Error(core::ErrorKind::usage, "--period: must be positive");
  if (c.divider > 255) throw core::Error(core::ErrorKind::usage, "--divider: 0..255");
  if (c.json && c.out == "-")
    throw core::Error(core::ErrorKind::usage, "--json and --out - would both write to stdout: choose one");
  core::check_output_target(c.out);  // before the chip is touched: a bad target costs no run

  capture::StopSignal stop;  // before the thread starts, so that it inherits the blocked signals
  capture::I2cBus bus(c.device, capture::parse_i2c_address("--address", c.address));
  capture::Mpu6050 chip(bus);
  chip.configure({.sample_rate_divider = static_cast<std::uint8_t>(c.divider)});
  capture::GyroSource source(chip, options);
  if (!c.quiet)
    fmt::print(
        stderr, "m2mlat: MPU-6050 at {}: reading every {}{}\n", core::printable(bus.describe()),
        core::format_duration(options.period),
        options.duration.count() > 0 ? " for " + core::format_duration(options.duration) : " until stopped");
  source.start();
  std::string stopped_by;
  while (source.running()) {
    pollfd p{stop.fd(), POLLIN, 0};
    if (::poll(&p, 1, 100) > 0) {
      stopped_by = stop.take();
      source.stop();
    }
  }
  source.join();
  const auto summary = source.summary();
  for (const auto& note : summary.notes)
    if (!note.empty() && !c.quiet) fmt::print(stderr, "m2mlat: {}\n", note);

  core::RateTrace trace;
  trace.clock = core::Clock::realtime;
  trace.counts_per_deg_s = capture::mpu6050::kCountsPerDegS;
  trace.samples = source.take();
  core::write_output_file(c.out, [&](std::ostream& os) {
    formats::write_rate_trace_csv(os, trace,
                                  {fmt::format("source: mpu6050 {}, period {} ns, divider {}", bus.describe(),
                                               options.period.count(), c.divider)});
  });

  const auto mean_read =
      summary.reads > 0 ? summary.total_read / static_cast<std::int64_t>(summary.reads) : core::Duration{0};
  const std::string reason = stopped_by.empty() ? summary.stop_reason : stopped_by;
  if (c.json) {
    print_json({{"out", c.out},
                {"samples", trace.samples.size()},
                {"reads", summary.reads},
                {"missed_periods", summary.missed_periods},
                {"i2c_errors", summary.i2c_errors},
                {"read_ns",
                 {{"min", summary.min_read.count()},
                  {"mean", mean_read.count()},
                  {"max", summary.max_read.count()}}},
                {"stop_reason", reason},
                {"error", summary.error}});
  } else {
    // With the trace on stdout, the summary goes to stderr.
    fmt::print(c.out == "-" ? stderr : stdout,
               "gyro: {} samples into {}, {} periods missed, {} I2C errors, stopped by {}; a read took {} on "
               "average "
               "({} .. {})\n",
               trace.samples.size(), core::printable(c.out), summary.missed_periods, summary.i2c_errors,
               reason, core::format_duration(mean_read), core::format_duration(summary.min_read),
               core::format_duration(summary.max_read));
  }
  if (!summary.error.empty())
    throw core::Error(core::ErrorKind::io, fmt::format("{} (the {} samples read before it are in {})",
                                                       summary.error, trace.samples.size(), c.out));
  return 0;
}

}  // namespace

Runner attach_gyro(CLI::App& sub) {
  auto c = std::make_shared<GyroCommand>();
  sub.add_option("--device", c->device, "I2C device of the bus (/dev/i2c-N)")->required();
  sub.add_option("--address", c->address, "Chip address (0x68, or 0x69 with AD0 high)")
      ->capture_default_str();
  sub.add_option("--period", c->period, "Time between two reads")->capture_default_str();
  sub.add_option("--duration", c->duration, "Stop after this long (default: at SIGINT/SIGTERM)");
  sub.add_option("--divider", c->divider, "SMPLRT_DIV: the chip's output rate is 8 kHz / (1 + divider)")
      ->capture_default_str();
  sub.add_option("--out", c->out, "The trace file to write (m2mlat-gyro/1 CSV; - for stdout)")->required();
  sub.add_option("--rt-priority", c->rt_priority, "SCHED_FIFO priority 1..99 of the sampling thread");
  sub.add_option("--cpu", c->cpu, "Run the sampling thread on this CPU");
  sub.add_flag("--quiet", c->quiet, "No messages on stderr");
  sub.add_flag("--json", c->json, "Print the summary as JSON");
  return [c] { return run_gyro(*c); };
}

}  // namespace m2mlat::cli
