#include "m2mlat/capture/gyro_source.hpp"

#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <limits>

#include "m2mlat/core/clock_read.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/rt/scheduling.hpp"

namespace m2mlat::capture {

GyroSource::GyroSource(Mpu6050& chip, GyroSourceOptions options) : chip_(chip), options_(options) {
  if (options_.period.count() <= 0)
    throw core::Error(core::ErrorKind::usage, "the gyroscope's read period must be positive");
  if (options_.chip_output_period.count() < 0)
    throw core::Error(core::ErrorKind::usage, "the gyroscope's output period must not be negative");
}

GyroSource::~GyroSource() {
  stop();
  join();
}

void GyroSource::start() {
  if (thread_.joinable()) throw core::Error(core::ErrorKind::internal, "gyroscope source started twice");
  stop_ = false;
  running_ = true;
  thread_ = std::thread([this] { loop(); });
}

void GyroSource::stop() { stop_ = true; }

void GyroSource::join() {
  if (thread_.joinable()) thread_.join();
}

std::vector<core::RateSample> GyroSource::take() {
  std::lock_guard lock(mutex_);
  std::vector<core::RateSample> out;
  out.swap(samples_);
  return out;
}

GyroSummary GyroSource::summary() const {
  std::lock_guard lock(mutex_);
  return summary_;
}

void GyroSource::loop() {
  std::vector<std::string> notes;
  // On Linux these apply to the calling thread: the sampling thread, not the whole process.
  if (options_.cpu >= 0) notes.push_back(rt::set_cpu_affinity(options_.cpu).message);
  if (options_.rt_priority > 0) notes.push_back(rt::set_fifo_priority(options_.rt_priority).message);
  {
    std::lock_guard lock(mutex_);
    summary_.notes = std::move(notes);
    summary_.min_read = core::Duration{std::numeric_limits<std::int64_t>::max()};
  }

  const std::int64_t period = options_.period.count();
  const std::int64_t start = core::now_ns(CLOCK_MONOTONIC);
  const std::int64_t end = options_.duration.count() > 0 ? start + options_.duration.count()
                                                         : std::numeric_limits<std::int64_t>::max();
  std::int64_t deadline = start;
  std::string reason = "stopped";
  while (!stop_.load(std::memory_order_relaxed)) {
    if (deadline >= end) {
      reason = "duration";
      break;
    }
    core::sleep_until_ns(CLOCK_MONOTONIC, deadline);
    core::RateSample sample;
    const std::int64_t before = core::now_ns(CLOCK_REALTIME);
    try {
      sample.raw = chip_.read_rates();
    } catch (const std::exception& e) {
      std::lock_guard lock(mutex_);
      ++summary_.i2c_errors;
      summary_.error = e.what();
      reason = "i2c error";
      break;
    }
    const std::int64_t after = core::now_ns(CLOCK_REALTIME);
    const std::int64_t took = after - before;
    // The middle of [before - output period, after], and half its width rounded up, so that the
    // interval covers both ends.
    const std::int64_t earliest = before - options_.chip_output_period.count();
    const std::int64_t width = after - earliest;
    sample.time_ns = earliest + width / 2;
    sample.bound_ns = static_cast<std::int32_t>(
        std::min<std::int64_t>((width + 1) / 2, std::numeric_limits<std::int32_t>::max()));
    {
      std::lock_guard lock(mutex_);
      samples_.push_back(sample);
      ++summary_.reads;
      summary_.total_read += core::Duration{took};
      summary_.min_read = std::min(summary_.min_read, core::Duration{took});
      summary_.max_read = std::max(summary_.max_read, core::Duration{took});
    }
    notify();
    // The next deadline; those already past (a slow read, a late wake-up) are skipped and counted.
    deadline += period;
    const std::int64_t now = core::now_ns(CLOCK_MONOTONIC);
    if (now > deadline) {
      const std::int64_t skipped = (now - deadline) / period + 1;
      // Only deadlines inside the run count as missed (the last read may end after the run's end).
      const std::int64_t missed =
          deadline >= end ? 0 : std::min(skipped, (end - deadline + period - 1) / period);
      deadline += skipped * period;
      std::lock_guard lock(mutex_);
      summary_.missed_periods += static_cast<std::uint64_t>(missed);
    }
  }
  {
    std::lock_guard lock(mutex_);
    if (summary_.reads == 0) summary_.min_read = core::Duration{0};
    summary_.stop_reason = reason;
    running_ = false;
  }
  notify();
}

void GyroSource::notify() const {
  if (options_.notify_fd < 0) return;
  const std::uint64_t one = 1;
  // A full counter or pipe means the consumer has not read yet: it will see the samples anyway.
  if (::write(options_.notify_fd, &one, sizeof one) < 0) return;
}

}  // namespace m2mlat::capture
