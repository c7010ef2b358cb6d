// Kernel-log lines through the block output buffer.
#include "m2mlat/formats/kernel_log_writer.hpp"

#include <fmt/format.h>

#include "m2mlat/core/error.hpp"
#include "m2mlat/formats/output_text.hpp"

namespace m2mlat::formats {

void KernelLogWriter::write(std::span<const core::Event> events, std::span<const std::int64_t> log_time_us) {
  if (!log_time_us.empty() && log_time_us.size() != events.size())
    throw core::Error(core::ErrorKind::internal, "kernel-log writer: one log stamp per event");
  OutputBuffer buffer(out_);
  for (std::size_t i = 0; i < events.size(); ++i) {
    const auto& e = events[i];
    if (e.time.clock() != core::Clock::realtime)
      throw core::Error(core::ErrorKind::data, "the kernel-log format holds CLOCK_REALTIME timestamps only");
    if (!log_time_us.empty()) {
      if (log_time_us[i] < 0) throw core::Error(core::ErrorKind::data, "a kernel-log stamp before boot");
      buffer << fmt::format("[{:5d}.{:06d}] ", log_time_us[i] / 1'000'000, log_time_us[i] % 1'000'000);
    }
    buffer << "GPIO_";
    buffer.integer(pin_) << "_IRQ:";
    buffer.integer(e.time.ns()) << '\n';
    buffer.end_record();
  }
  buffer.flush();
}

}  // namespace m2mlat::formats
