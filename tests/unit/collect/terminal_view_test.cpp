// The terminal block: its text, redraw in place on a terminal, plain blocks at an interval otherwise.
#include "m2mlat/collect/terminal_view.hpp"

#include <gtest/gtest.h>

#include <tuple>
#include <stdio.h>

#include <algorithm>
#include <cstdlib>

using namespace m2mlat;

namespace {

constexpr std::int64_t kMs = 1'000'000;
constexpr std::int64_t kViewNow = 1'780'304'400'000'000'000;

collect::LiveSummary summary_with_samples() {
  collect::LiveSummary s;
  s.state = collect::LiveState::ok;
  s.scenario = "static_wifi";
  s.cause_ref = {"operator", "wheel"};
  s.effect_ref = {"vehicle", "wheel"};
  s.pairs = 13;
  s.ambiguous = 1;
  s.cause_unmatched = 2;
  s.effect_unmatched = 3;
  s.bounces = 4;
  s.summary.n = 12;
  s.summary.median_ms = 874.04;
  s.summary.iqr_ms = 198.26;
  s.last = collect::LiveSample{kViewNow - 2'000 * kMs, 873'249'000, false};
  return s;
}

std::vector<collect::NodeHealth> two_nodes() {
  collect::NodeHealth op;
  op.node = "operator";
  op.url = "http://10.0.0.1:8470";
  op.role = core::Role::cause;
  op.state = collect::NodeState::ok;
  op.last_contact_ns = kViewNow - 200 * kMs;
  op.events_per_s = 0.75;
  op.events = 812;
  op.lost = 0;
  op.has_clock = true;
  op.synchronised = true;
  op.clock_offset_ns = 12'000;
  op.clock_max_error_ns = 1'200'000;
  collect::NodeHealth veh;
  veh.url = "http://10.0.0.2:8470";
  veh.role = core::Role::effect;
  veh.state = collect::NodeState::unreachable;
  veh.last_error = "connection refused";
  return {op, veh};
}

// Captures what a TerminalView writes.
class Capture {
 public:
  Capture() : file_(open_memstream(&buffer_, &size_)) {}
  ~Capture() {
    std::fclose(file_);
    std::free(buffer_);
  }
  std::FILE* file() { return file_; }
  std::string text() {
    std::fflush(file_);
    return std::string(buffer_, size_);
  }

 private:
  char* buffer_ = nullptr;
  std::size_t size_ = 0;
  std::FILE* file_;
};

}  // namespace

TEST(TerminalView, BlockShowsTheNumbersAndEveryNode) {
  const auto lines = collect::render_block(summary_with_samples(), two_nodes(), kViewNow);
  ASSERT_EQ(lines.size(), 5u);
  EXPECT_EQ(lines[0], "static_wifi: operator/wheel -> vehicle/wheel");
  EXPECT_EQ(lines[1],
            "samples 12  last 873.2 ms  median 874.0 ms  IQR 198.3 ms  (pairs 13, 1 flagged; unmatched 2 "
            "cause, 3 "
            "effect; 4 bounces)");
  EXPECT_NE(lines[2].find("events/s"), std::string::npos);
  EXPECT_NE(lines[2].find("last contact"), std::string::npos);
  // operator: ok, rate, events, no loss, clock offset and bound, contact 0.2 s ago.
  EXPECT_EQ(lines[3].rfind("operator ", 0), 0u) << lines[3];
  for (const char* part : {" cause ", " ok ", " 0.8 ", " 812 ", "+0.012 ms", "1.200 ms", "0.2 s ago"})
    EXPECT_NE(lines[3].find(part), std::string::npos) << part << " in " << lines[3];
  // vehicle: not heard from yet, named by its URL, no clock, its error.
  EXPECT_EQ(lines[4].rfind("http://10.0.0.2:8470 ", 0), 0u) << lines[4];
  for (const char* part : {" effect ", " unreachable ", "never", "connection refused"})
    EXPECT_NE(lines[4].find(part), std::string::npos) << part << " in " << lines[4];
}

TEST(TerminalView, BreakdownLineWithAStageRule) {
  auto s = summary_with_samples();
  analysis::Breakdown b;
  b.complete = 9;
  b.incomplete = 2;
  for (const auto& [name, median_ns, share] :
       {std::tuple{"to_command", 5'180'000.0, 0.0046}, std::tuple{"actuator", 1'131'000'000.0, 0.9954}}) {
    analysis::StageStats stage;
    stage.name = name;
    stage.median_ns = median_ns;
    stage.share = share;
    b.stages.push_back(stage);
  }
  s.breakdown = b;
  const auto lines = collect::render_block(s, {}, kViewNow);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[2], "breakdown 9 complete / 2 incomplete:  to_command 5.2 ms (0.5 %)  actuator 1131.0 ms (99.5 %)");
  // Without a rule, no such line.
  EXPECT_EQ(collect::render_block(summary_with_samples(), {}, kViewNow).size(), 2u);
}

TEST(TerminalView, WaitingBlockSaysWhy) {
  collect::LiveSummary s;
  s.message = "scenario 'x' has no effect session";
  s.scenario = "x";
  const auto lines = collect::render_block(s, {}, kViewNow);
  ASSERT_EQ(lines.size(), 2u);  // no agents: no agents' table
  EXPECT_EQ(lines[0], "waiting x: scenario 'x' has no effect session");
  EXPECT_EQ(lines[1], "samples 0");
}

TEST(TerminalView, UnsynchronisedClockIsMarked) {
  auto nodes = two_nodes();
  nodes[0].synchronised = false;
  const auto lines = collect::render_block(summary_with_samples(), nodes, kViewNow);
  EXPECT_NE(lines[3].find("ok,unsync"), std::string::npos) << lines[3];
}

TEST(TerminalView, RedrawsInPlaceOnATerminal) {
  Capture out;
  collect::TerminalView view(out.file(), true);
  EXPECT_TRUE(view.show(summary_with_samples(), two_nodes(), kViewNow));
  const auto first = out.text();
  EXPECT_EQ(first.find("\x1b[5F"), std::string::npos);  // nothing to go back over yet
  EXPECT_NE(first.find("samples 12"), std::string::npos);
  EXPECT_NE(first.find("\x1b[K\n"), std::string::npos);
  EXPECT_TRUE(view.show(summary_with_samples(), two_nodes(), kViewNow + 250 * kMs));
  const auto second = out.text().substr(first.size());
  EXPECT_EQ(second.rfind("\x1b[5F", 0), 0u);  // back to the block's first line (5 lines)
  EXPECT_NE(second.find("samples 12"), std::string::npos);
  // The final block redraws too; later output goes below it, with no moving back.
  const auto before_finish = out.text().size();
  view.finish(summary_with_samples(), two_nodes(), kViewNow + 500 * kMs);
  const auto after_finish = out.text();
  EXPECT_EQ(after_finish.substr(before_finish).rfind("\x1b[5F", 0), 0u);
  view.show(summary_with_samples(), two_nodes(), kViewNow + 750 * kMs);
  const auto later = out.text().substr(after_finish.size());
  EXPECT_EQ(later.find("\x1b[5F"), std::string::npos);
  EXPECT_NE(later.find("samples 12"), std::string::npos);
}

TEST(TerminalView, PlainBlocksAtMostEveryInterval) {
  Capture out;
  collect::TerminalView view(out.file(), false, std::chrono::seconds(5));
  EXPECT_TRUE(view.show(summary_with_samples(), two_nodes(), kViewNow));
  EXPECT_FALSE(view.show(summary_with_samples(), two_nodes(), kViewNow + 1'000 * kMs));
  EXPECT_FALSE(view.show(summary_with_samples(), two_nodes(), kViewNow + 4'999 * kMs));
  EXPECT_TRUE(view.show(summary_with_samples(), two_nodes(), kViewNow + 5'000 * kMs));
  const auto text = out.text();
  EXPECT_EQ(text.find('\x1b'), std::string::npos);  // no ANSI codes in a file
  std::size_t blocks = 0;
  for (auto at = text.find("samples 12"); at != std::string::npos; at = text.find("samples 12", at + 1))
    ++blocks;
  EXPECT_EQ(blocks, 2u);
  view.finish(summary_with_samples(), two_nodes(), kViewNow + 5'001 * kMs);  // always written
  const auto final_text = out.text();
  EXPECT_GT(final_text.size(), text.size());
}

// A node name sent by an agent with an ESC sequence and a newline: shown escaped, and the redraw
// still goes back over exactly the block's 5 lines.
TEST(TerminalView, ControlCharactersInNamesEscaped) {
  auto nodes = two_nodes();
  nodes[0].node = "op\x1b[2J\nx";
  auto summary = summary_with_samples();
  summary.scenario = "s\x1b]0;owned\x07";
  Capture out;
  collect::TerminalView view(out.file(), true);
  view.show(summary, nodes, kViewNow);
  view.show(summary, nodes, kViewNow + 250 * kMs);
  const auto text = out.text();
  EXPECT_EQ(text.find("\x1b[2J"), std::string::npos);
  EXPECT_EQ(text.find("\x1b]0"), std::string::npos);
  EXPECT_NE(text.find("op\\x1b[2J\\nx"), std::string::npos) << text;
  EXPECT_NE(text.find("s\\x1b]0;owned\\x07: "), std::string::npos) << text;
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 10);  // two blocks of 5 lines
  EXPECT_NE(text.find("\x1b[5F"), std::string::npos);
}
