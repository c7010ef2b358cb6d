// The in-process twin of the GPIO character device, for tests and demonstrations on machines
// without GPIO. It behaves as gpiolib-cdev does where m2mlat depends on it: chips with labels and
// named lines; a line held by one request is busy for others (EBUSY); a chip can refuse access
// (EACCES); an edge on a requested line becomes a gpio_v2_line_event only if the request watches
// that edge (after active-low inversion); each event takes the request's next seqno and the line's
// next line_seqno; the request's buffer holds event_buffer_size events (0 -> 16 per line, clamped to
// 1024) and, when full, drops the OLDEST event, which the reader sees as a seqno gap.
//
// Not modelled: edges lost before they become events (the kernel's masked-IRQ window), which no
// sequence number shows either.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "m2mlat/capture/gpio_device.hpp"

namespace m2mlat::capture {

class FakeGpio final : public GpioDevices {
 public:
  FakeGpio();
  ~FakeGpio() override;

  // Adds chip gpiochip<N> (N = number of chips so far) at /dev/gpiochip<N>; returns its path.
  // Line i is named line_names[i] when given.
  std::string add_chip(const std::string& label, std::uint32_t lines,
                       std::vector<std::string> line_names = {});
  // Opening the chip fails with EACCES from now on (a user without the gpio group).
  void deny_access(const std::string& path);
  // A line held by another program: requesting it fails with EBUSY.
  void hold_line(const std::string& path, std::uint32_t offset, const std::string& consumer);

  // The physical level of a line changes at `timestamp_ns` (the kernel's stamp on the request's
  // clock). Returns the number of events it produced (0 or 1).
  int edge(const std::string& path, std::uint32_t offset, bool rising, std::uint64_t timestamp_ns);
  // Events generated so far, and events dropped because a request's buffer was full.
  std::uint64_t events_generated() const;
  std::uint64_t events_dropped() const;

  // Values written to output lines, in order.
  struct OutputChange {
    std::string path;
    std::uint32_t offset = 0;
    bool value = false;
  };
  const std::vector<OutputChange>& output_changes() const;

  std::vector<std::string> chip_paths() const override;
  ChipInfo chip_info(const std::string& path) const override;
  LineInfo line_info(const std::string& path, std::uint32_t offset) const override;
  std::unique_ptr<LineRequest> request_lines(const std::string& path, gpio_v2_line_request& request) override;

  struct State;  // shared with the requests it grants (they may outlive nothing, but release lines)

 private:
  std::shared_ptr<State> state_;
};

}  // namespace m2mlat::capture
