// The wire format: every type survives encode -> decode unchanged, and every field's absence, wrong
// type and out-of-range value is refused with an error naming `where` and the field.
#include "m2mlat/net/wire.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <map>
#include <set>

#include "m2mlat/core/error.hpp"

namespace m2mlat::net {
namespace {

using nlohmann::json;

store::Session session() {
  store::Session s;
  s.id = 7;
  s.label = "run-3";
  s.scenario = "urban";
  s.node = "vehicle";
  s.role = core::Role::effect;
  s.config_json = R"({"source":"sim","x":[1,2]})";
  s.start = core::TimePoint::from_ns(core::Clock::realtime, 1'780'304'400'123'456'789);
  s.end = core::TimePoint::from_ns(core::Clock::realtime, 1'780'304'500'000'000'001);
  s.software_version = "0.1.0";
  return s;
}

store::StoredEvent event() {
  store::StoredEvent e;
  e.seq = 12;
  e.session_id = 7;
  e.event.node = "vehicle";
  e.event.channel = "wheel";
  e.event.edge = core::Edge::rising;
  e.event.time = core::TimePoint::from_ns(core::Clock::realtime, std::numeric_limits<std::int64_t>::max());
  e.event.seqno = 41;
  e.event.line_seqno = 40;
  e.event.flags = core::kFlagSimulated | core::kFlagAfterClockStep;
  return e;
}

store::StoredClockSample sample() {
  store::StoredClockSample s;
  s.id = 3;
  s.sample.session_id = 7;
  s.sample.time = core::TimePoint::from_ns(core::Clock::realtime, 1'780'304'400'000'000'000);
  s.sample.source = "chrony";
  s.sample.offset_ns = -1234;
  s.sample.max_error_ns = 50'000;
  s.sample.est_error_ns = 800;
  s.sample.synchronised = true;
  s.sample.detail_json = R"({"stratum":2})";
  return s;
}

store::StoredLoss loss() {
  store::StoredLoss l;
  l.id = 4;
  l.loss.session_id = 7;
  l.loss.channel = "wheel";
  l.loss.detected_at = core::TimePoint::from_ns(core::Clock::realtime, 1'780'304'400'000'000'000);
  l.loss.first_missing = 18;
  l.loss.count = 3;
  l.loss.kind = "seqno_gap";
  return l;
}

Status status() {
  Status s;
  s.software_version = "0.1.0";
  s.node = "vehicle";
  s.role = core::Role::effect;
  s.store_id = "0123456789abcdef0123456789abcdef";
  s.session = session();
  s.session->end.reset();
  s.channels = {{"wheel", 10, 2, 1, 1'780'304'400'000'000'000}, {"pulse", 0, 0, 0, std::nullopt}};
  s.events = 10;
  s.lost = 1;
  s.dropped = 5;
  s.last_seq = 12;
  s.clock = sample().sample;
  s.started_ns = 1;
  s.now_ns = 2;
  s.marks = MarkStatus{"127.0.0.1:8471", "kernel", 5, {{"format", 1}}, "format: 127.0.0.1:4000: ..."};
  return s;
}

// The message of the core::Error(data) that `f` throws.
template <typename F>
std::string refusal(F f) {
  try {
    f();
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::data);
    return e.what();
  }
  ADD_FAILURE() << "not refused";
  return {};
}

TEST(Wire, EveryTypeRoundTripsThroughText) {
  const auto s = session();
  EXPECT_EQ(session_from_json(json::parse(to_json(s).dump()), "t"), s);
  auto open = s;
  open.end.reset();
  EXPECT_EQ(session_from_json(json::parse(to_json(open).dump()), "t"), open);
  const auto e = event();
  EXPECT_EQ(event_from_json(json::parse(to_json(e).dump()), "t", "vehicle", core::Role::effect), e);
  EXPECT_EQ(clock_sample_from_json(json::parse(to_json(sample()).dump()), "t"), sample());
  EXPECT_EQ(loss_from_json(json::parse(to_json(loss()).dump()), "t"), loss());
  EXPECT_EQ(status_from_json(json::parse(to_json(status()).dump()), "t"), status());
  auto bare = status();
  bare.session.reset();
  bare.clock.reset();
  bare.channels.clear();
  EXPECT_EQ(status_from_json(json::parse(to_json(bare).dump()), "t"), bare);
}

TEST(Wire, AnEventsTextIsTheJsonLibrarysByteForByte) {
  auto e = event();
  const auto same = [&] {
    std::string fast;
    append_json(fast, e);
    EXPECT_EQ(fast, to_json(e).dump(-1, ' ', false, json::error_handler_t::replace)) << e.event.channel;
    // And back: the canonical reader takes it whole when the channel is plain printable ASCII (no
    // escapes, no UTF-8), else leaves it to the JSON decoder; either way the same event.
    const auto& c = e.event.channel;
    const bool plain = !c.empty() && std::all_of(c.begin(), c.end(), [](char ch) {
      return ch >= 0x20 && ch <= 0x7e && ch != '"' && ch != '\\';
    });
    auto decoded = event_from_json(json::parse(fast), "test", e.event.node, core::Role::effect);
    auto back = parse_canonical_event(fast);
    ASSERT_EQ(back.has_value(), plain) << fast;
    if (back) {
      back->event.node = e.event.node;
      EXPECT_EQ(back->event, decoded.event) << fast;
      EXPECT_EQ(back->seq, decoded.seq);
      EXPECT_EQ(back->session_id, decoded.session_id);
    }
  };
  same();
  for (const char* channel : {"a", "wheel 2", "say \"hi\"", "back\\slash", "tab\there", "\x7f", "ümlaut",
                              "bad \xff\xfe utf-8", "ctl \x01"}) {
    e.event.channel = channel;
    same();
  }
  e.event.time = core::TimePoint::from_ns(core::Clock::monotonic, std::numeric_limits<std::int64_t>::min());
  e.event.edge = core::Edge::falling;
  e.event.flags = std::numeric_limits<std::uint32_t>::max();
  e.event.seqno = std::numeric_limits<std::uint64_t>::max();
  e.seq = std::numeric_limits<std::int64_t>::max();
  same();
}

TEST(Wire, TheCanonicalReaderRefusesAnythingElse) {
  std::string good;
  append_json(good, event());
  ASSERT_TRUE(parse_canonical_event(good));
  const auto with = [&](std::string_view from, std::string_view to) {
    auto text = good;
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return text.replace(at, from.size(), to);
  };
  for (const auto& bad :
       {with("{", " {"), with("}", "} "), with(R"("seq":12)", R"("seq":012)"),
        with(R"("seq":12)", R"("seq":0)"), with(R"("seq":12)", R"("seq":-12)"),
        with(R"("session":7)", R"("session":0)"), with(R"("flags":9)", R"("flags":4294967296)"),
        with(R"("flags":9)", R"("flags":-1)"), with(R"("clock":"realtime")", R"("clock":"sundial")"),
        with(R"("edge":"rising")", R"("edge":"up")"), with(R"("channel":"wheel")", R"("channel":"")"),
        with(R"("channel":"wheel")", R"("channel":"wh\"eel")"), with(R"("t_ns":)", R"("t_ns": )"),
        with(R"(,"seqno":41)", ""), std::string(good, 0, good.size() - 1), std::string("{}")})
    EXPECT_FALSE(parse_canonical_event(bad)) << bad;
}

TEST(Wire, EventsCarryTheContractsFieldsAndNoNodeOrRole) {
  const auto j = to_json(event());
  EXPECT_EQ(j["edge"], "rising");
  EXPECT_EQ(j["clock"], "realtime");
  EXPECT_EQ(j["t_ns"].get<std::int64_t>(), std::numeric_limits<std::int64_t>::max());
  EXPECT_FALSE(j.contains("node"));
  EXPECT_FALSE(j.contains("role"));
  EXPECT_EQ(to_json(session())["end_ns"].get<std::int64_t>(), 1'780'304'500'000'000'001);
  EXPECT_TRUE(to_json(status())["session"]["end_ns"].is_null());
}

// Removing (unless `optional`), mistyping and (where there is a range) breaking each field of `good`
// is refused with a message naming `where` and the field.
template <typename Decode>
void every_field_refused(const json& good, Decode decode, const std::map<std::string, json>& out_of_range,
                         const std::set<std::string>& optional = {}) {
  for (const auto& [field, value] : good.items()) {
    SCOPED_TRACE(field);
    if (!optional.contains(field)) {
      auto missing = good;
      missing.erase(field);
      const auto message = refusal([&] { decode(missing); });
      EXPECT_NE(message.find("where-42"), std::string::npos) << message;
      EXPECT_NE(message.find("'" + field + "'"), std::string::npos) << message;
    }
    auto mistyped = good;
    mistyped[field] = value.is_array() ? json("x") : json::array({1});
    const auto message = refusal([&] { decode(mistyped); });
    EXPECT_NE(message.find(field), std::string::npos) << message;
  }
  for (const auto& [field, value] : out_of_range) {
    SCOPED_TRACE(field);
    auto bad = good;
    bad[field] = value;
    const auto message = refusal([&] { decode(bad); });
    EXPECT_NE(message.find("'" + field + "'"), std::string::npos) << message;
  }
}

TEST(Wire, EveryEventFieldIsChecked) {
  every_field_refused(to_json(event()),
                      [](const json& j) { event_from_json(j, "where-42", "vehicle", core::Role::effect); },
                      {{"seq", 0},
                       {"session", -1},
                       {"channel", ""},
                       {"edge", "up"},
                       {"clock", "wall"},
                       {"t_ns", 9223372036854775808ull},
                       {"t_ns", 1.5},
                       {"seqno", -1},
                       {"flags", 4294967296ull}});
}

TEST(Wire, EverySessionFieldIsChecked) {
  auto j = to_json(session());
  every_field_refused(j, [](const json& x) { session_from_json(x, "where-42"); },
                      {{"id", 0},
                       {"node", ""},
                       {"role", "operator"},  // only the canonical name on the wire
                       {"end_ns", 1},
                       {"config", "{}"},
                       {"clock", "simulated-ish"}});
}

TEST(Wire, EveryClockSampleAndLossFieldIsChecked) {
  every_field_refused(
      to_json(sample()), [](const json& x) { clock_sample_from_json(x, "where-42"); },
      {{"id", 0}, {"source", "Chrony!"}, {"max_error_ns", -1}, {"synchronised", 1}, {"detail", 3}});
  every_field_refused(to_json(loss()), [](const json& x) { loss_from_json(x, "where-42"); },
                      {{"id", -5}, {"count", 0}, {"kind", "gap"}, {"first_missing", -1}});
}

TEST(Wire, EveryStatusFieldIsChecked) {
  every_field_refused(to_json(status()), [](const json& x) { status_from_json(x, "where-42"); },
                      {{"api", "m2mlat-agent/2"}, {"store_id", "XYZ"}, {"events", -1}, {"last_seq", -1}},
                      {"marks"});
  auto j = to_json(status());
  j["channels"][1]["lost"] = -3;
  const auto message = refusal([&] { status_from_json(j, "where-42"); });
  EXPECT_NE(message.find("channels[1]"), std::string::npos) << message;
  EXPECT_NE(message.find("'lost'"), std::string::npos) << message;
  j = to_json(status());
  j["session"]["node"] = 5;
  EXPECT_NE(refusal([&] { status_from_json(j, "where-42"); }).find("session"), std::string::npos);
  EXPECT_NE(refusal([] { status_from_json(json::array(), "where-42"); }).find("where-42"), std::string::npos);
}

TEST(Wire, ErrorBodiesAreJsonEvenForBytesThatAreNotUtf8) {
  const auto body = json::parse(error_body(400, "after='\xff\xfe'"));
  EXPECT_EQ(body["error"]["status"], 400);
  EXPECT_TRUE(body["error"]["message"].is_string());
}

}  // namespace
}  // namespace m2mlat::net

namespace m2mlat::net {
namespace {

store::StoredRateBlock rate_block() {
  store::StoredRateBlock b;
  b.id = 12;
  b.block.session_id = 3;
  b.block.channel = "wheel_gyro";
  b.block.clock = core::Clock::realtime;
  b.block.counts_per_deg_s = 131.0;
  b.block.first_index = 4096;
  b.block.samples = {{1'780'304'400'000'000'000, 62'500, {-32768, 0, 32767}},
                     {1'780'304'400'001'000'000, 0, {5, -6, 7}},
                     {1'780'304'400'001'000'000, 2'147'483'647, {0, 0, 0}}};
  return b;
}

TEST(Wire, ARateBlockSurvivesTheWireAndEveryFieldIsChecked) {
  const auto b = rate_block();
  const auto back = rate_block_from_json(json::parse(to_json(b).dump()), "t");
  EXPECT_EQ(back.id, b.id);
  EXPECT_EQ(back.block.session_id, b.block.session_id);
  EXPECT_EQ(back.block.channel, b.block.channel);
  EXPECT_EQ(back.block.clock, b.block.clock);
  EXPECT_EQ(back.block.counts_per_deg_s, b.block.counts_per_deg_s);
  EXPECT_EQ(back.block.first_index, b.block.first_index);
  ASSERT_EQ(back.block.samples.size(), b.block.samples.size());
  for (std::size_t i = 0; i < b.block.samples.size(); ++i) {
    EXPECT_EQ(back.block.samples[i].time_ns, b.block.samples[i].time_ns);
    EXPECT_EQ(back.block.samples[i].bound_ns, b.block.samples[i].bound_ns);
    EXPECT_EQ(back.block.samples[i].raw, b.block.samples[i].raw);
  }
  every_field_refused(to_json(b), [](const json& x) { rate_block_from_json(x, "where-42"); },
                      {{"id", 0},
                       {"session", 0},
                       {"channel", ""},
                       {"clock", "wall"},
                       {"counts_per_deg_s", 0},
                       {"first_index", -1},
                       {"samples", json::array()}});
  // One sample wrong: the message names the sample.
  const std::vector<std::pair<json, std::string>> bad_samples{
      {json::array({1, 2, 3, 4}), "samples[1]"},
      {json::array({1'780'304'400'001'000'000, -1, 0, 0, 0}), "bound_ns"},
      {json::array({1'780'304'400'001'000'000, 0, 32768, 0, 0}), "int16"},
      {json::array({1'780'304'400'001'000'000, 0, 0, 0, 1.5}), "integers"},
      {json::array({1'780'304'399'000'000'000, 0, 0, 0, 0}), "before the sample before"}};
  for (const auto& [sample, expected] : bad_samples) {
    auto j = to_json(b);
    j["samples"][1] = sample;
    const auto message = refusal([&] { rate_block_from_json(j, "where-42"); });
    EXPECT_NE(message.find("where-42"), std::string::npos) << message;
    EXPECT_NE(message.find(expected), std::string::npos) << message;
  }
  auto j = to_json(b);
  j["samples"] = json::array();
  for (int i = 0; i < 4097; ++i) j["samples"].push_back({i, 0, 0, 0, 0});
  EXPECT_NE(refusal([&] { rate_block_from_json(j, "where-42"); }).find("4096"), std::string::npos);
}

TEST(Wire, AMarkerSurvivesTheWireAndEveryFieldIsChecked) {
  store::StoredMarker m;
  m.id = 3;
  m.marker.session_id = 2;
  m.marker.name = "planner_out";
  m.marker.time = core::TimePoint::from_ns(core::Clock::realtime, 1'780'304'400'000'000'123);
  m.marker.source = "kernel";
  m.marker.key = "812";
  m.marker.sender_ns = 1'780'304'400'000'000'000;
  m.marker.origin = "udp 127.0.0.1:4000";
  EXPECT_EQ(marker_from_json(json::parse(to_json(m).dump()), "t"), m);
  m.marker.uncertainty_ns = 7;
  m.marker.sender_ns.reset();
  EXPECT_EQ(marker_from_json(json::parse(to_json(m).dump()), "t"), m);
  every_field_refused(to_json(m), [](const json& x) { marker_from_json(x, "where-42"); },
                      {{"id", 0}, {"session", 0}, {"name", ""}, {"source", ""}, {"uncertainty_ns", -1},
                       {"clock", "wall"}});
  auto without = to_json(status());
  without["marks"] = nullptr;
  EXPECT_FALSE(status_from_json(without, "t").marks);
  without.erase("marks");  // an agent that predates markers
  EXPECT_FALSE(status_from_json(without, "t").marks);
}

}  // namespace
}  // namespace m2mlat::net
