// The GPIO capture source: one uAPI v2 line request per channel, events read in batches from all
// requests through one epoll descriptor (up to a whole kernel buffer per read), every seqno /
// line_seqno gap reported.
//
// One request per channel (rather than one per chip) so that each channel's interrupt carries its
// own consumer label ("m2mlat-<channel>") in /proc/interrupts, which is how --irq-cpu finds it, and
// so that the request's seqno counts that line's events only. The request asks for the kernel's
// largest event buffer (1024 events) and, by default, no debounce: the timestamp is then taken in
// the hard interrupt handler.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "m2mlat/capture/channel.hpp"
#include "m2mlat/capture/gpio_device.hpp"
#include "m2mlat/capture/sequence_tracker.hpp"
#include "m2mlat/capture/source.hpp"
#include "m2mlat/core/fd.hpp"

namespace m2mlat::capture {

struct GpioSourceOptions {
  std::string node;                         // the node name the events carry
  std::string consumer_prefix = "m2mlat-";  // consumer label = prefix + channel name (max 31 bytes)
  std::uint32_t event_buffer_size = kMaxEventBufferSize;  // events the kernel buffers per request
};

class GpioSource final : public Source {
 public:
  // Resolves every channel's chip and line and requests them; throws core::Error with the fix
  // (missing chip, permission, line in use, bad settings). Nothing stays requested on failure.
  GpioSource(GpioDevices& devices, const std::vector<ChannelSpec>& channels, GpioSourceOptions options);
  ~GpioSource() override;
  GpioSource(const GpioSource&) = delete;
  GpioSource& operator=(const GpioSource&) = delete;

  void read(ReadResult& out, std::size_t max_events) override;
  int fd() const override { return epoll_fd_.get(); }
  std::vector<std::string> describe() const override;
  std::vector<std::string> channels() const override;

  // The consumer label of each channel's request, in channel order (for finding its IRQ).
  std::vector<std::string> consumers() const;
  // Things the user should know about the settings in force (kernel debounce, non-realtime clock).
  std::vector<std::string> warnings() const;

 private:
  struct Channel {
    ChannelSpec spec;
    ChipInfo chip;
    LineInfo line;
    std::string consumer;
    std::unique_ptr<LineRequest> request;
    SequenceTracker seqno{1, 32};
    SequenceTracker line_seqno{1, 32};
  };
  void read_channel(Channel& channel, ReadResult& out, std::size_t max_events);

  GpioSourceOptions options_;
  std::vector<Channel> channels_;
  std::size_t next_ = 0;  // round-robin start, so a busy channel cannot starve the others
  core::Fd epoll_fd_;
  // One read(2) takes up to a whole kernel buffer (1024 events of 48 bytes): under a high edge rate
  // the cost of the system call is shared by many events.
  std::vector<gpio_v2_line_event> scratch_ = std::vector<gpio_v2_line_event>(kMaxEventBufferSize);
};

// The uAPI request for one channel: input, its edges, bias, active-low, event clock, debounce.
gpio_v2_line_request make_input_request(const ChannelSpec& spec, std::uint32_t offset,
                                        const std::string& consumer, std::uint32_t event_buffer_size);

}  // namespace m2mlat::capture
