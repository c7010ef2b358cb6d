// Reads by sequence range (resume after a seq, with a limit) and by time range with filters.
#include <gtest/gtest.h>

#include <limits>
#include <vector>

#include "m2mlat/core/error.hpp"
#include "m2mlat/store/store.hpp"
#include "store_test_util.hpp"

using namespace m2mlat;
using namespace m2mlat::store;
using namespace m2mlat::store::test;

namespace {

std::vector<std::int64_t> seqs(const std::vector<StoredEvent>& events) {
  std::vector<std::int64_t> out;
  for (const auto& e : events) out.push_back(e.seq);
  return out;
}

// Two nodes, two channels each, both edges; events interleaved in time and written out of time
// order, so that time order and seq order differ.
class StoreQuery : public ::testing::Test {
 protected:
  void SetUp() override {
    store_ = std::make_unique<Store>(Store::open(dir_.file("q.m2mlat")));
    op_ = store_->begin_session(make_session("operator"));
    veh_ = store_->begin_session(make_session("vehicle"));
    // operator: wheel at 100, 300, 500 (500 rising); pulse at 200
    std::vector<core::Event> op{
        make_event("operator", "wheel", 500, 3), make_event("operator", "wheel", 100, 1),
        make_event("operator", "pulse", 200, 1), make_event("operator", "wheel", 300, 2)};
    op[0].edge = core::Edge::rising;
    store_->append_events(op_, op);  // seqs 1..4
    // vehicle: wheel at 150, 350, 300 (same time as an operator event); one monotonic event
    std::vector<core::Event> veh{
        make_event("vehicle", "wheel", 150, 1), make_event("vehicle", "wheel", 350, 2),
        make_event("vehicle", "wheel", 300, 3), make_event("vehicle", "wheel", 250, 4)};
    veh[3].time = core::TimePoint::from_ns(core::Clock::monotonic, 250);
    store_->append_events(veh_, veh);  // seqs 5..8
  }

  TempDir dir_;
  std::unique_ptr<Store> store_;
  std::int64_t op_ = 0, veh_ = 0;
};

}  // namespace

TEST_F(StoreQuery, AfterSeqWithLimitPagesThroughEverythingOnce) {
  EXPECT_EQ(seqs(store_->events_after(0, 3)), (std::vector<std::int64_t>{1, 2, 3}));
  EXPECT_EQ(seqs(store_->events_after(3, 3)), (std::vector<std::int64_t>{4, 5, 6}));
  EXPECT_EQ(seqs(store_->events_after(6, 3)), (std::vector<std::int64_t>{7, 8}));
  EXPECT_TRUE(store_->events_after(8, 3).empty());
  EXPECT_TRUE(store_->events_after(0, 0).empty());
  EXPECT_EQ(store_->events_after(-5, std::numeric_limits<std::size_t>::max()).size(), 8u);
  EXPECT_EQ(store_->last_seq(), 8);
  // The stored event carries its session's node.
  const auto five = store_->events_after(4, 1);
  ASSERT_EQ(five.size(), 1u);
  EXPECT_EQ(five[0].session_id, veh_);
  EXPECT_EQ(five[0].event.node, "vehicle");
}

TEST_F(StoreQuery, TimeRangeIsInclusiveAndInTimeOrder) {
  const auto all = store_->events_in_time(rt(0), rt(1000));
  // realtime only: 100(2) 150(5) 200(3) 300(4) 300(7) 350(6) 500(1); ties in seq order
  EXPECT_EQ(seqs(all), (std::vector<std::int64_t>{2, 5, 3, 4, 7, 6, 1}));
  EXPECT_EQ(seqs(store_->events_in_time(rt(150), rt(300))), (std::vector<std::int64_t>{5, 3, 4, 7}));
  EXPECT_EQ(seqs(store_->events_in_time(rt(301), rt(349))), (std::vector<std::int64_t>{}));
  const auto mono = core::TimePoint::from_ns(core::Clock::monotonic, 0);
  EXPECT_EQ(seqs(store_->events_in_time(mono, mono + core::Duration{250})), (std::vector<std::int64_t>{8}));
}

TEST_F(StoreQuery, Filters) {
  const auto from = rt(std::numeric_limits<std::int64_t>::min());
  const auto to = rt(std::numeric_limits<std::int64_t>::max());
  EventFilter by_session;
  by_session.session_id = op_;
  EXPECT_EQ(seqs(store_->events_in_time(from, to, by_session)), (std::vector<std::int64_t>{2, 3, 4, 1}));
  EventFilter by_node;
  by_node.node = "vehicle";
  EXPECT_EQ(seqs(store_->events_in_time(from, to, by_node)), (std::vector<std::int64_t>{5, 7, 6}));
  EventFilter by_channel;
  by_channel.channel = "wheel";
  EXPECT_EQ(seqs(store_->events_in_time(from, to, by_channel)),
            (std::vector<std::int64_t>{2, 5, 4, 7, 6, 1}));
  EventFilter op_wheel_falling;
  op_wheel_falling.node = "operator";
  op_wheel_falling.channel = "wheel";
  op_wheel_falling.edge = core::Edge::falling;
  EXPECT_EQ(seqs(store_->events_in_time(from, to, op_wheel_falling)), (std::vector<std::int64_t>{2, 4}));
  EventFilter nobody;
  nobody.node = "nobody";
  EXPECT_TRUE(store_->events_in_time(from, to, nobody).empty());
}

TEST_F(StoreQuery, TimestampsAreTheSameSelectionAsEvents) {
  const auto from = rt(0);
  const auto to = rt(1000);
  std::vector<EventFilter> filters(4);
  filters[1].session_id = veh_;
  filters[2].node = "operator";
  filters[2].channel = "wheel";
  filters[3].edge = core::Edge::rising;
  for (const auto& filter : filters) {
    const auto events = store_->events_in_time(from, to, filter);
    const auto columns = store_->timestamps(from, to, filter);
    EXPECT_EQ(columns.clock, core::Clock::realtime);
    ASSERT_EQ(columns.seq.size(), events.size());
    ASSERT_EQ(columns.t_ns.size(), events.size());
    for (std::size_t i = 0; i < events.size(); ++i) {
      EXPECT_EQ(columns.seq[i], events[i].seq);
      EXPECT_EQ(columns.t_ns[i], events[i].event.time.ns());
    }
  }
  EXPECT_EQ(store_->timestamps(from, to, filters[2]).t_ns, (std::vector<std::int64_t>{100, 300, 500}));
}

TEST_F(StoreQuery, ChannelsOfASession) {
  EXPECT_EQ(store_->channels(op_), (std::vector<std::string>{"pulse", "wheel"}));
  EXPECT_EQ(store_->channels(veh_), (std::vector<std::string>{"wheel"}));
  EXPECT_TRUE(store_->channels(veh_ + 1).empty());
}

TEST_F(StoreQuery, RangeOverTwoClocksIsRefused) {
  const auto mono = core::TimePoint::from_ns(core::Clock::monotonic, 1000);
  EXPECT_THROW(store_->events_in_time(rt(0), mono), core::Error);
  EXPECT_THROW(store_->timestamps(rt(0), mono), core::Error);
  EXPECT_THROW(store_->clock_samples(op_, rt(0), mono), core::Error);
}

TEST_F(StoreQuery, ClockSamplesByTimeAndSession) {
  store_->append_clock_samples(std::vector<ClockSample>{{op_, rt(30), "chrony", 1, 10, 5, true, "{}"},
                                                        {op_, rt(10), "chrony", 2, 10, 5, true, "{}"},
                                                        {veh_, rt(20), "chrony", 3, 10, 5, true, "{}"}});
  std::vector<std::int64_t> offsets;
  for (const auto& s : store_->clock_samples(op_, rt(0), rt(30))) offsets.push_back(s.offset_ns);
  EXPECT_EQ(offsets, (std::vector<std::int64_t>{2, 1}));
  offsets.clear();
  for (const auto& s : store_->clock_samples(std::nullopt, rt(10), rt(20))) offsets.push_back(s.offset_ns);
  EXPECT_EQ(offsets, (std::vector<std::int64_t>{2, 3}));
}
