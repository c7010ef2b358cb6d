// The glass-to-glass LED switched by something other than the clock (`m2mlat led`; the schedule is
// the pulse generator's own loop, pulse.hpp): a command (a line on a stream such as stdin, or a UDP
// datagram) or an input edge (the vehicle's motion onset, e.g. its Hall sensor line). Each trigger
// is a pollable descriptor and a non-blocking take(); run_triggered() waits on the trigger and the
// stop descriptor in one poll, switches the line through PulseGenerator::set() (which reads the
// clock just before and just after the ioctl) and switches a flash off `on_for` later.
//
// Commands, one a line or one a datagram, surrounding blanks ignored:
//   on      the LED on (stays on)            off     the LED off
//   flash   (or an empty line) on now, off `on_for` later
// A switch that would not change the line (on while on) makes no edge and no event; a flash while a
// flash is lit only moves its end. Unknown words are not acted on; they are returned with where they
// came from ("stdin line 3", "datagram from 127.0.0.1:40000") for the caller to report.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "m2mlat/capture/channel.hpp"
#include "m2mlat/capture/gpio_device.hpp"
#include "m2mlat/capture/pulse.hpp"
#include "m2mlat/core/event.hpp"
#include "m2mlat/core/fd.hpp"
#include "m2mlat/core/time.hpp"

namespace m2mlat::capture {

enum class LedAction : std::uint8_t { on, off, flash };
// "on", "off", "flash" or "" (a flash); nullopt for anything else. Blanks around the word are ignored.
std::optional<LedAction> parse_led_action(std::string_view word);

// What a trigger had waiting.
struct TriggerInput {
  std::vector<LedAction> actions;    // in arrival order
  std::vector<core::Event> edges;    // the input edges that triggered (edge trigger), to be kept too
  std::vector<std::string> refused;  // "stdin line 3: unknown LED command 'blink' (on, off, flash)"
};

class LedTrigger {
 public:
  virtual ~LedTrigger() = default;
  // Polls readable when take() has something.
  virtual int fd() const = 0;
  // Appends what is waiting, without blocking. Returns false once the trigger has ended for good
  // (the stream was closed); a pending flash is still switched off then.
  virtual bool take(TriggerInput& out) = 0;
  virtual std::string describe() const = 0;
};

// Commands as lines on a stream (stdin: fd 0), read without blocking; `name` names it in messages.
// The descriptor is not closed.
std::unique_ptr<LedTrigger> stream_trigger(int fd, std::string name);

// Commands as UDP datagrams on `address` ("127.0.0.1:9120", "0.0.0.0:9120"; port 0: any free one,
// see port()). Throws core::Error(usage) for a malformed address, (io) when it cannot be bound.
class DatagramTrigger final : public LedTrigger {
 public:
  explicit DatagramTrigger(const std::string& address);
  int fd() const override { return socket_.get(); }
  bool take(TriggerInput& out) override;
  std::string describe() const override;
  std::uint16_t port() const { return port_; }

 private:
  core::Fd socket_;
  std::string host_;
  std::uint16_t port_ = 0;
};

// A flash at each edge of an input line (the vehicle's motion onset), through the GPIO capture
// source (GpioSource: uAPI v2, hard-IRQ timestamps); the edges themselves are returned too.
std::unique_ptr<LedTrigger> edge_trigger(GpioDevices& devices, const ChannelSpec& channel,
                                         const std::string& node);

struct LedRunSummary {
  std::uint64_t switches = 0;  // edges made
  std::uint64_t triggers = 0;  // actions taken from the trigger (including those that changed nothing)
  std::string stop_reason;     // "end of input" or the stop's name
};

// Switches `led` as the trigger says until the trigger ends or `stop_fd` polls readable (-1: never);
// `on_edge` sees each switch after it was made, `on_input` what the trigger delivered (its edges,
// refused commands) after it was acted on (recording them must not delay the LED). The line is left low.
LedRunSummary run_triggered(PulseGenerator& led, LedTrigger& trigger, core::Duration on_for, int stop_fd,
                            const std::function<void(const PulseEdge&)>& on_edge,
                            const std::function<void(const TriggerInput&)>& on_input = {},
                            const std::function<std::string()>& stop_name = {});

}  // namespace m2mlat::capture
