// The kernel-log source, for rigs that still run the reference rig's kernel module: its interrupt
// handler printed "GPIO_<pin>_IRQ:<CLOCK_REALTIME ns>" with printk. This source follows /dev/kmsg
// (new records only, each read(2) one record) or a file that grows (a log written by another
// program, read from its start), and turns each such line into an event of the channel configured
// for that pin (or "gpio<pin>" when none is configured).
//
// The module numbered nothing, so the events carry no GPIO seqno (flag no-kernel-seqno). /dev/kmsg
// numbers every log record: a jump in that number means records were overwritten before they were
// read (the kernel reports EPIPE), and each is stored as a node-wide kmsg_gap loss, since which of
// them were GPIO lines cannot be known.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "m2mlat/capture/channel.hpp"
#include "m2mlat/capture/sequence_tracker.hpp"
#include "m2mlat/capture/source.hpp"
#include "m2mlat/core/fd.hpp"

namespace m2mlat::capture {

struct KmsgSourceOptions {
  std::string node;
  std::string path = "/dev/kmsg";  // the kmsg device, or a log file to follow
  // Channels by pin: line "16" or "GPIO16" is pin 16; the edge recorded is the channel's edges
  // (falling unless rising). Empty: every pin, as channel "gpio<pin>", falling.
  std::vector<ChannelSpec> channels;
};

class KmsgSource final : public Source {
 public:
  // Opens the device or file; throws core::Error (no_input, or io with the fix for permissions).
  explicit KmsgSource(KmsgSourceOptions options);
  ~KmsgSource() override;
  KmsgSource(const KmsgSource&) = delete;
  KmsgSource& operator=(const KmsgSource&) = delete;

  void read(ReadResult& out, std::size_t max_events) override;
  int fd() const override { return device_ ? fd_.get() : -1; }
  std::vector<std::string> describe() const override;
  std::vector<std::string> channels() const override;
  std::vector<std::string> notes() const override;

  // The pin of a line text: "16" or "GPIO16" (any letters before the number); false if none.
  static bool pin_of(const std::string& line, std::uint32_t& pin);

 private:
  void take_line(std::string_view line, ReadResult& out);

  KmsgSourceOptions options_;
  core::Fd fd_;
  bool device_ = false;
  std::map<std::uint32_t, std::size_t> by_pin_;  // pin -> index in options_.channels
  SequenceTracker kmsg_seq_{0, 64};
  std::string partial_;    // a followed file's unfinished last line (at most formats::kMaxLineBytes)
  bool skipping_ = false;  // inside a line longer than that, passed over up to its newline
  std::uint64_t lines_ = 0, malformed_ = 0, other_pins_ = 0;
  std::string first_malformed_;
};

}  // namespace m2mlat::capture
