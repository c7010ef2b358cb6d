// The coordinator's live block on the terminal.
#include "m2mlat/collect/terminal_view.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>

#include "m2mlat/core/printable.hpp"
#include "m2mlat/report/resampling_text.hpp"

namespace m2mlat::collect {

namespace {

std::string ms(double value_ms) { return std::isnan(value_ms) ? "-" : fmt::format("{:.1f} ms", value_ms); }

std::string ns_as_ms(std::int64_t ns, int decimals) {
  return fmt::format("{:.{}f} ms", static_cast<double>(ns) / 1e6, decimals);
}

std::string contact_age(std::int64_t last_contact_ns, std::int64_t now_ns) {
  if (last_contact_ns == 0) return "never";
  const auto age_ns = now_ns - last_contact_ns;
  if (age_ns < 0) return "just now";
  return fmt::format("{:.1f} s ago", static_cast<double>(age_ns) / 1e9);
}

}  // namespace

std::vector<std::string> render_block(const LiveSummary& s, const std::vector<NodeHealth>& nodes,
                                      std::int64_t now_ns) {
  std::vector<std::string> lines;
  if (s.state == LiveState::ok && s.loop) {
    // The full loop: M2M, G2G and E2E side by side over the window.
    const auto& loop = *s.loop;
    lines.push_back(fmt::format("{}: full loop {} -> {} ({} chains over the last {:.0f} s, {} onsets)",
                                s.scenario, core::to_string(s.cause_ref), core::to_string(s.effect_ref),
                                loop.chains, static_cast<double>(loop.window_ns) / 1e9, loop.detector));
    constexpr std::array kNames{"M2M", "G2G", "E2E"};
    std::string row;
    for (std::size_t q = 0; q < kNames.size(); ++q) {
      const auto& x = loop.quantities[q];
      row += fmt::format("{}{} n {}  median {}  P95 {}  last {}", q == 0 ? "" : "  |  ", kNames[q], x.n,
                         ms(x.median_ms), ms(x.p95_ms), x.last_ns ? ns_as_ms(*x.last_ns, 1) : "-");
    }
    lines.push_back(std::move(row));
    std::string gaps;
    for (const auto& [key, count] : loop.incomplete)
      if (count > 0) gaps += fmt::format("{}{} {}", gaps.empty() ? "" : ", ", key, count);
    lines.push_back("incomplete chains: " + (gaps.empty() ? std::string("none") : gaps));
  } else if (s.state == LiveState::ok) {
    lines.push_back(
        fmt::format("{}: {} -> {}", s.scenario, core::to_string(s.cause_ref), core::to_string(s.effect_ref)));
    const auto& st = s.summary;
    lines.push_back(
        fmt::format("samples {}  last {}  median {}  IQR {}  (pairs {}, {} flagged; unmatched {} cause, {} "
                    "effect; {} bounces)",
                    st.n, s.last ? ns_as_ms(s.last->latency_ns, 1) : "-", ms(st.median_ms), ms(st.iqr_ms),
                    s.pairs, s.ambiguous, s.cause_unmatched, s.effect_unmatched, s.bounces));
    if (st.bootstrap) {
      const auto& ci = *st.bootstrap;
      lines.push_back(fmt::format("{:.0f} % CI: median {:.1f}-{:.1f} ms, IQR {:.1f}-{:.1f} ms (resampled: {})",
                                  ci.level * 100, ci.median_ms.lower, ci.median_ms.upper, ci.iqr_ms.lower,
                                  ci.iqr_ms.upper, report::resampling_name(ci.resampling)));
    }
    for (const auto& w : s.warnings) lines.push_back("warning: " + w);
    if (s.breakdown) {
      // The live stage breakdown (--stages): each stage's median and share of the M2M.
      const auto& b = *s.breakdown;
      std::string row = fmt::format("breakdown {} complete / {} incomplete:", b.complete, b.incomplete);
      for (const auto& stage : b.stages)
        row += fmt::format("  {} {}{}", stage.name, ms(stage.median_ns / 1e6),
                           std::isnan(stage.share) ? "" : fmt::format(" ({:.1f} %)", stage.share * 100));
      lines.push_back(std::move(row));
    }
  } else {
    lines.push_back(
        fmt::format("{}{}: {}", to_string(s.state), s.scenario.empty() ? "" : " " + s.scenario, s.message));
    lines.push_back("samples 0");
  }
  if (nodes.empty()) return lines;  // e.g. `m2mlat watch`: no agents to show
  lines.push_back(fmt::format("{:<12} {:<8} {:<12} {:>9} {:>9} {:>6} {:>13} {:>11} {:>13}", "node", "role",
                              "state", "events/s", "events", "lost", "clock offset", "max error",
                              "last contact"));
  for (const auto& n : nodes) {
    const auto name = n.node.empty() ? n.url : n.node;
    std::string offset = "-", max_error = "-";
    if (n.has_clock) {
      offset = fmt::format("{:+.3f} ms", static_cast<double>(n.clock_offset_ns) / 1e6);
      max_error = ns_as_ms(n.clock_max_error_ns, 3);
    }
    std::string state(to_string(n.state));
    if (n.has_clock && !n.synchronised) state += ",unsync";
    auto line = fmt::format("{:<12} {:<8} {:<12} {:>9.1f} {:>9} {:>6} {:>13} {:>11} {:>13}", name,
                            core::to_string(n.role), state, n.events_per_s, n.events, n.lost, offset,
                            max_error, contact_age(n.last_contact_ns, now_ns));
    if (!n.last_error.empty()) line += "  " + n.last_error;
    lines.push_back(std::move(line));
  }
  return lines;
}

TerminalView::TerminalView(std::FILE* out, bool tty, std::chrono::nanoseconds plain_interval)
    : out_(out), tty_(tty), plain_interval_(plain_interval) {}

bool TerminalView::show(const LiveSummary& summary, const std::vector<NodeHealth>& nodes,
                        std::int64_t now_ns) {
  if (!tty_) {
    if (last_plain_ns_ != 0 && now_ns - last_plain_ns_ < plain_interval_.count()) return false;
    last_plain_ns_ = now_ns;
  }
  draw(render_block(summary, nodes, now_ns));
  return true;
}

void TerminalView::finish(const LiveSummary& summary, const std::vector<NodeHealth>& nodes,
                          std::int64_t now_ns) {
  draw(render_block(summary, nodes, now_ns));
  drawn_lines_ = 0;  // the final block stays; anything printed later goes below it
}

void TerminalView::draw(const std::vector<std::string>& lines) {
  // Node and scenario names come from the agents: escaped (core/printable.hpp), so that none can
  // drive the terminal or, with a newline, throw off the count of lines to redraw.
  std::string text;
  if (tty_) {
    // Back to the first line of the previous block (CPL), then each line cleared to its end (EL),
    // then everything below cleared (ED) in case the block got shorter.
    if (drawn_lines_ > 0) text += fmt::format("\x1b[{}F", drawn_lines_);
    for (const auto& line : lines) text += core::printable(line) + "\x1b[K\n";
    text += "\x1b[J";
    drawn_lines_ = lines.size();
  } else {
    for (const auto& line : lines) text += core::printable(line) + "\n";
    text += "\n";  // a blank line between blocks
  }
  std::fwrite(text.data(), 1, text.size(), out_);
  std::fflush(out_);
}

}  // namespace m2mlat::collect
