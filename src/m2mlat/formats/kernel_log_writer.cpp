// Kernel-log lines through the block output buffer.
#include "m2mlat/formats/kernel_log_writer.hpp"

#include "m2mlat/core/error.hpp"
#include "m2mlat/formats/output_text.hpp"

namespace m2mlat::formats {

void KernelLogWriter::write(std::span<const core::Event> events) {
  OutputBuffer buffer(out_);
  for (const auto& e : events) {
    if (e.time.clock() != core::Clock::realtime)
      throw core::Error(core::ErrorKind::data, "the kernel-log format holds CLOCK_REALTIME timestamps only");
    buffer << "GPIO_";
    buffer.integer(pin_) << "_IRQ:";
    buffer.integer(e.time.ns()) << '\n';
    buffer.end_record();
  }
  buffer.flush();
}

}  // namespace m2mlat::formats
