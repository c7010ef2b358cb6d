// The inertial motion source: a sampling thread that reads a gyroscope's rate registers at a set
// period (absolute CLOCK_MONOTONIC deadlines, SCHED_FIFO where permitted, as the GPIO capture and
// the pulse generator run) and stamps each reading with CLOCK_REALTIME taken just before and just
// after the read. The chip puts a new sample into its output registers once per output period (125 us
// at 8 kHz) on its own clock, so the values read were sampled within one output period before the
// read began, or during the read: the interval [before - output period, after] certainly holds the
// sampling instant; the stamp is its middle and the bound half its width (core::RateSample). On a
// Raspberry Pi at 400 kHz a 6-byte read is about 0.2 ms on the wire, so the bound is about 0.16 ms
// (see docs/capture.md for the figures, and for why polling and not the data-ready pin). The chip's
// own filter delay (0.98 ms for the gyro at DLPF_CFG 0, per its datasheet) is a constant, not in the
// bound: it cancels between two such chips (M2M) and is stated in the docs.
//
// Counted: reads, I2C errors, missed periods (a deadline that passed with no read started in it,
// because the previous read or a wake-up was late). An I2C error ends the run: the samples already
// taken are kept and the error is reported with them.
#pragma once

#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "m2mlat/capture/mpu6050.hpp"
#include "m2mlat/core/rate_sample.hpp"
#include "m2mlat/core/time.hpp"

namespace m2mlat::capture {

struct GyroSourceOptions {
  core::Duration period{1'000'000};  // between two reads, ns (the chip's output period or longer)
  core::Duration duration{0};        // stop after this long, ns; 0: until stop()
  // How old the values may be when the read begins: the chip's output period, ns (8 kHz / (1 +
  // SMPLRT_DIV) -> 125 us at divider 0).
  core::Duration chip_output_period{125'000};
  int rt_priority = 0;  // SCHED_FIFO 1..99 for the sampling thread; 0: leave it
  int cpu = -1;         // run the sampling thread on this CPU; -1: leave it
  // An eventfd (or pipe) written after each sample is taken and when the thread ends, so that a
  // consumer acting on the samples at once (the LED's onset trigger) can poll it; -1: none.
  int notify_fd = -1;
};

struct GyroSummary {
  std::uint64_t reads = 0;
  std::uint64_t i2c_errors = 0;
  std::uint64_t missed_periods = 0;
  core::Duration min_read{0}, max_read{0}, total_read{0};  // time a read took (after - before), ns
  std::string stop_reason;                                 // "duration", "stopped" or "i2c error"
  std::string error;                                       // the error that ended the run (empty: none)
  std::vector<std::string> notes;  // what the real-time settings did, or why they were refused
};

class GyroSource {
 public:
  // `chip` is configured already and outlives the source.
  GyroSource(Mpu6050& chip, GyroSourceOptions options);
  ~GyroSource();  // stops and joins the thread
  GyroSource(const GyroSource&) = delete;
  GyroSource& operator=(const GyroSource&) = delete;

  void start();
  void stop();  // asks the thread to end after its current read; returns at once
  bool running() const { return running_.load(); }
  void join();  // waits for the thread to end (after its duration, stop() or an error)

  // The samples taken since the last call, oldest first (moved out).
  std::vector<core::RateSample> take();
  // The counts so far; complete after join().
  GyroSummary summary() const;

 private:
  void loop();
  void notify() const;  // writes options_.notify_fd, if any

  Mpu6050& chip_;
  GyroSourceOptions options_;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::atomic<bool> running_{false};
  mutable std::mutex mutex_;  // guards samples_ and summary_
  std::vector<core::RateSample> samples_;
  GyroSummary summary_;
};

}  // namespace m2mlat::capture
