// Bad input is refused with a message naming the store and the field, and changes nothing
// stored: a batch is all or nothing, even when the failure is found half-way through writing it.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "m2mlat/core/error.hpp"
#include "m2mlat/store/store.hpp"
#include "store_test_util.hpp"

using namespace m2mlat;
using namespace m2mlat::store;
using namespace m2mlat::store::test;

namespace {

// Runs `f`, expects a core::Error of `kind` whose message contains every one of `parts`.
template <typename F>
void expect_error(F&& f, core::ErrorKind kind, const std::vector<std::string>& parts) {
  try {
    f();
    ADD_FAILURE() << "no error";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), kind) << e.what();
    for (const auto& part : parts) EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

class StoreValidation : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = dir_.file("v.m2mlat");
    store_ = std::make_unique<Store>(Store::open(path_));
    session_ = store_->begin_session(make_session("vehicle"));
    store_->append_events(session_, std::vector{make_event("vehicle", "wheel", 1, 1)});
  }
  // Nothing changed since SetUp.
  void expect_unchanged() {
    EXPECT_EQ(store_->last_seq(), 1);
    EXPECT_EQ(store_->event_count(), 1);
    EXPECT_TRUE(store_->losses().empty());
    EXPECT_TRUE(store_->clock_samples().empty());
    EXPECT_EQ(store_->sessions().size(), 1u);
  }
  std::vector<core::Event> good(int n) {
    std::vector<core::Event> out;
    for (int i = 0; i < n; ++i)
      out.push_back(make_event("vehicle", "wheel", 100 + i, 2 + static_cast<unsigned>(i)));
    return out;
  }

  TempDir dir_;
  std::string path_;
  std::unique_ptr<Store> store_;
  std::int64_t session_ = 0;
};

}  // namespace

TEST_F(StoreValidation, EventsForAMissingSession) {
  expect_error([&] { store_->append_events(session_ + 41, good(3)); }, core::ErrorKind::data,
               {path_, "session 42 does not exist"});
  expect_unchanged();
}

TEST_F(StoreValidation, EventOfAnotherNodeLateInTheBatch) {
  auto events = good(50);
  events[37].node = "operator";
  expect_error([&] { store_->append_events(session_, events); }, core::ErrorKind::data,
               {path_, "event 37", "'node'", "operator", "vehicle"});
  expect_unchanged();
}

TEST_F(StoreValidation, EmptyChannelAndInvalidEnums) {
  auto events = good(4);
  events[2].channel.clear();
  expect_error([&] { store_->append_events(session_, events); }, core::ErrorKind::data,
               {path_, "event 2", "'channel'"});
  events = good(4);
  events[1].edge = static_cast<core::Edge>(7);
  expect_error([&] { store_->append_events(session_, events); }, core::ErrorKind::data,
               {"event 1", "'edge'"});
  events = good(4);
  events[3].time = core::TimePoint::from_ns(static_cast<core::Clock>(9), 5);
  expect_error([&] { store_->append_events(session_, events); }, core::ErrorKind::data,
               {"event 3", "'time'"});
  expect_unchanged();
}

// The loss's session is checked inside the transaction, after the events were written: the
// rollback must take the events back out.
TEST_F(StoreValidation, FailureAfterEventsWereWrittenRollsThemBack) {
  Batch batch;
  batch.session_id = session_;
  batch.events = good(100);
  batch.losses = {{session_ + 5, "wheel", rt(5), 2, 1, "seqno_gap"}};
  expect_error([&] { store_->append(batch); }, core::ErrorKind::data, {path_, "losses", "does not exist"});
  expect_unchanged();
  // The next good batch continues right after the last committed seq.
  EXPECT_EQ(store_->append_events(session_, good(2)), 2);
}

TEST_F(StoreValidation, InvalidJsonInAClockSample) {
  Batch batch;
  batch.session_id = session_;
  batch.events = good(10);
  batch.clock_samples = {{session_, rt(1), "chrony", 0, 0, 0, true, "{}"},
                         {session_, rt(2), "chrony", 0, 0, 0, true, R"({"stratum": )"}};
  expect_error([&] { store_->append(batch); }, core::ErrorKind::data,
               {path_, "clock sample 1", "'detail_json'", "not valid JSON"});
  batch.clock_samples = {{session_, rt(1), "Chrony!", 0, 0, 0, true, "{}"}};
  expect_error([&] { store_->append(batch); }, core::ErrorKind::data, {"'source'", "Chrony!"});
  expect_unchanged();
}

TEST_F(StoreValidation, BadLosses) {
  expect_error(
      [&] {
        store_->append_losses(std::vector<Loss>{{session_, "wheel", rt(1), 5, 0, "seqno_gap"}});
      },
      core::ErrorKind::data, {"loss 0", "'count'"});
  expect_error(
      [&] {
        store_->append_losses(std::vector<Loss>{{session_, "wheel", rt(1), 5, 1, "gap"}});
      },
      core::ErrorKind::data, {"loss 0", "'kind'", "seqno_gap"});
  expect_unchanged();
}

TEST_F(StoreValidation, SessionWithInvalidConfigJson) {
  auto session = make_session("operator", "broken");
  session.config_json = R"({"window_ms": 2000,})";
  expect_error([&] { store_->begin_session(session); }, core::ErrorKind::data,
               {path_, "session 'broken'", "'config_json'", "not valid JSON"});
  session.config_json = "";
  expect_error([&] { store_->begin_session(session); }, core::ErrorKind::data, {"'config_json'"});
  session = make_session("");
  expect_error([&] { store_->begin_session(session); }, core::ErrorKind::data, {"'node'"});
  session = make_session("operator");
  session.end = core::TimePoint::from_ns(core::Clock::monotonic, session.start.ns());
  expect_error([&] { store_->begin_session(session); }, core::ErrorKind::data, {"'end'", "clock"});
  session.end = session.start - core::Duration{1};
  expect_error([&] { store_->begin_session(session); }, core::ErrorKind::data, {"'end'", "before"});
  expect_unchanged();
}

TEST_F(StoreValidation, EndedSessionTakesNoMoreRecords) {
  const auto start = store_->session(session_)->start;
  expect_error([&] { store_->end_session(session_, start - core::Duration{1}); }, core::ErrorKind::data,
               {"'end'", "before"});
  EXPECT_FALSE(store_->session(session_)->end.has_value());
  store_->end_session(session_, start + core::Duration{10});
  expect_error([&] { store_->end_session(session_, start + core::Duration{20}); }, core::ErrorKind::data,
               {"session 1", "already ended"});
  expect_error([&] { store_->end_session(99, start); }, core::ErrorKind::data,
               {"session 99", "no such session"});
  expect_error([&] { store_->append_events(session_, good(1)); }, core::ErrorKind::data,
               {"session 1 has ended"});
  expect_error(
      [&] {
        store_->append_clock_samples(std::vector<ClockSample>{{session_, rt(1), "sim", 0, 0, 0, true, "{}"}});
      },
      core::ErrorKind::data, {"session 1 has ended"});
  EXPECT_EQ(store_->session(session_)->end, start + core::Duration{10});
  expect_unchanged();
}

TEST_F(StoreValidation, ReadOnlyStoreRefusesWrites) {
  auto reader = Store::open(path_, Options{.read_only = true});
  expect_error([&] { reader.append_events(session_, good(1)); }, core::ErrorKind::usage,
               {path_, "read-only"});
  expect_error([&] { reader.begin_session(make_session("x")); }, core::ErrorKind::usage, {"read-only"});
  EXPECT_EQ(reader.last_seq(), 1);
  expect_unchanged();
}
