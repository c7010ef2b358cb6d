// Writing the reference rig's kernel-log lines, "GPIO_<pin>_IRQ:<ns>", one per edge: what its
// kernel module printed. m2mlat writes them to produce test and benchmark input that the rig's own
// scripts (and m2mlat's importer) read. Streaming: call write() per block of events.
#pragma once

#include <cstdint>
#include <ostream>
#include <span>

#include "m2mlat/core/event.hpp"

namespace m2mlat::formats {

class KernelLogWriter {
 public:
  KernelLogWriter(std::ostream& out, std::uint32_t pin) : out_(out), pin_(pin) {}
  // Throws core::Error(data) for an event not on CLOCK_REALTIME (the module used ktime_get_real_ns)
  // and core::Error(io) if the stream fails. With `log_time_us` (one per event: the log's own stamp,
  // us since boot) each line gets dmesg's "[ seconds.micro] " prefix.
  void write(std::span<const core::Event> events, std::span<const std::int64_t> log_time_us = {});

 private:
  std::ostream& out_;
  std::uint32_t pin_;
};

}  // namespace m2mlat::formats
