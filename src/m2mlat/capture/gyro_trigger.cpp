// The gyroscope's onset as the LED's trigger (gyro_trigger.hpp).
#include "m2mlat/capture/gyro_trigger.hpp"

#include <fmt/format.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "m2mlat/core/error.hpp"

namespace m2mlat::capture {

namespace {

core::Fd make_wake_fd() {
  core::Fd fd(::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC));
  if (fd.get() < 0) throw core::Error(core::ErrorKind::io, fmt::format("eventfd: {}", std::strerror(errno)));
  return fd;
}

}  // namespace

GyroTrigger::GyroTrigger(std::unique_ptr<RegisterBus> bus, std::string name, GyroTriggerOptions options)
    : bus_(std::move(bus)),
      chip_(std::make_unique<Mpu6050>(*bus_)),
      name_(std::move(name)),
      wake_(make_wake_fd()),
      detector_(mpu6050::kCountsPerDegS, options.detector) {
  chip_->configure({});
  GyroSourceOptions so;
  so.period = options.period;
  so.chip_output_period = core::Duration{1'000'000'000 / mpu6050::kGyroRateHz};  // divider 0
  so.rt_priority = options.rt_priority;
  so.cpu = options.cpu;
  so.notify_fd = wake_.get();
  source_ = std::make_unique<GyroSource>(*chip_, so);
  source_->start();
}

GyroTrigger::~GyroTrigger() {
  source_->stop();
  source_->join();
}

bool GyroTrigger::take(TriggerInput& out) {
  std::uint64_t count = 0;
  if (::read(wake_.get(), &count, sizeof count) < 0 && errno != EAGAIN)
    throw core::Error(core::ErrorKind::io, fmt::format("gyroscope trigger: eventfd: {}", std::strerror(errno)));
  // Whether it still runs is read before the samples are taken: a sample taken after would be lost.
  const bool running = source_->running();
  for (const auto& sample : source_->take()) {
    ++samples_;
    if (detector_.add(sample)) {
      ++onsets_;
      out.actions.push_back(LedAction::flash);
    }
  }
  if (running) return true;
  const auto summary = source_->summary();
  if (!reported_ && !summary.error.empty()) out.refused.push_back(fmt::format("gyroscope: {}", summary.error));
  reported_ = true;
  return false;
}

std::string GyroTrigger::describe() const {
  return fmt::format("a flash at each motion onset of the gyroscope {} (streaming detector)", name_);
}

}  // namespace m2mlat::capture
