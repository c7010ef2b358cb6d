// The coordinator's live block on the terminal: the latency numbers so far and one line per agent.
//
// On a terminal the block is redrawn in place (ANSI: cursor to the block's first line, each line
// cleared to its end) every time it is shown; into a file or a pipe it is written as plain lines,
// at most once per `plain_interval`, so a log stays readable.
#pragma once

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "m2mlat/collect/health.hpp"
#include "m2mlat/collect/live_pairing.hpp"

namespace m2mlat::collect {

// The block as lines without ANSI codes, e.g.
//   static_wifi: operator/wheel -> vehicle/wheel
//   samples 412  last 873.2 ms  median 874.0 ms  IQR 198.3 ms  (pairs 420, 8 ambiguous; unmatched 3 cause,
//   5 effect; 12 bounces)
//   node      role    state        events/s   events  lost  clock offset  max error  last contact
//   operator  cause   ok                0.8      812     0     +0.012 ms   1.200 ms        0.2 s ago
// (the agents' table only when there are nodes). `now_ns` (CLOCK_REALTIME) dates the contact ages.
std::vector<std::string> render_block(const LiveSummary& summary, const std::vector<NodeHealth>& nodes,
                                      std::int64_t now_ns);

class TerminalView {
 public:
  // `out` is written only by show() and finish(); `tty` chooses redraw-in-place.
  TerminalView(std::FILE* out, bool tty, std::chrono::nanoseconds plain_interval = std::chrono::seconds(5));

  // Draws the block (always on a terminal; in plain mode only if plain_interval has passed since
  // the last one, by now_ns). Returns whether it wrote.
  bool show(const LiveSummary& summary, const std::vector<NodeHealth>& nodes, std::int64_t now_ns);
  // Writes the final block (also in plain mode, whatever the interval).
  void finish(const LiveSummary& summary, const std::vector<NodeHealth>& nodes, std::int64_t now_ns);

 private:
  void draw(const std::vector<std::string>& lines);
  std::FILE* out_;
  bool tty_;
  std::chrono::nanoseconds plain_interval_;
  std::size_t drawn_lines_ = 0;     // lines of the block on screen (tty)
  std::int64_t last_plain_ns_ = 0;  // when the last plain block was written; 0 = never
};

}  // namespace m2mlat::collect
