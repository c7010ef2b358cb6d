// A real crash: a child process appends batches forever through the batching writer and reports
// each acknowledged seq on a pipe; the parent SIGKILLs it mid-stream and reopens the store. The
// file must pass integrity_check, hold every acknowledged event, hold only whole batches, and take
// further appends with larger seqs. Repeated with different kill points and durability policies.
#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <set>
#include <vector>

#include "m2mlat/store/event_writer.hpp"
#include "m2mlat/store/store.hpp"
#include "store_test_util.hpp"

using namespace m2mlat;
using namespace m2mlat::store;
using namespace m2mlat::store::test;

namespace {

// Each event says where it belongs: line_seqno = its batch number, seqno = its index in the batch,
// flags = the size of its batch. Large batches make a kill during the commit's WAL write likely.

// The child: never returns into the test framework.
[[noreturn]] void append_forever(const std::string& path, std::int64_t session, Durability durability,
                                 std::uint32_t batch_size, std::uint64_t first_batch, int report_fd) {
  try {
    auto store = Store::open(path, Options{.durability = durability});
    WriterOptions options;
    options.max_batch = batch_size;
    options.max_age = std::chrono::hours(1);  // commits by size only, so commits are whole batches
    EventWriter writer(store, session, options);
    std::int64_t reported = writer.last_committed_seq();
    for (std::uint64_t batch = first_batch;; ++batch) {
      for (std::uint64_t i = 0; i < batch_size; ++i) {
        auto event = make_event("vehicle", "wheel", static_cast<std::int64_t>(batch * 100'000 + i) * 1000);
        event.line_seqno = batch;
        event.seqno = i;
        event.flags = batch_size;
        writer.add(event);
        if (writer.last_committed_seq() != reported) {
          reported = writer.last_committed_seq();
          // 8 bytes: below PIPE_BUF, so the write is atomic.
          if (write(report_fd, &reported, sizeof reported) != sizeof reported) _exit(2);
        }
      }
    }
  } catch (...) {
    _exit(3);
  }
}

// Reads one report; false at end of file. Fails the test after 20 s without data.
bool read_report(int fd, std::int64_t& seq) {
  pollfd p{fd, POLLIN, 0};
  if (poll(&p, 1, 20'000) != 1) {
    ADD_FAILURE() << "no report from the child within 20 s";
    return false;
  }
  std::size_t got = 0;
  auto* bytes = reinterpret_cast<char*>(&seq);
  while (got < sizeof seq) {
    const auto n = read(fd, bytes + got, sizeof seq - got);
    if (n <= 0) return false;
    got += static_cast<std::size_t>(n);
  }
  return true;
}

// Checks the store after a crash; returns the next batch number.
std::uint64_t verify(const std::string& path, const std::vector<std::int64_t>& reported,
                     std::uint32_t last_batch_size) {
  auto store = Store::open(path);
  EXPECT_TRUE(store.integrity_ok());
  const auto events = store.events_after(0, std::numeric_limits<std::size_t>::max());
  const std::int64_t last = store.last_seq();
  EXPECT_EQ(static_cast<std::int64_t>(events.size()), last);  // seqs 1..last, no holes

  // The session the killed writer left open reads the same by time, by session and by count (its
  // stamps increase with seq, so time order is seq order).
  const auto all_time = store.events_in_time(core::TimePoint::from_ns(core::Clock::realtime, 0),
                                             core::TimePoint::from_ns(core::Clock::realtime,
                                                                      std::numeric_limits<std::int64_t>::max()));
  EXPECT_EQ(all_time, events);
  EXPECT_EQ(store.event_count(), last);
  if (!events.empty()) {
    EventFilter of_session;
    of_session.session_id = events.front().session_id;
    EXPECT_EQ(store.timestamps(core::TimePoint::from_ns(core::Clock::realtime, 0),
                               core::TimePoint::from_ns(core::Clock::realtime, std::numeric_limits<std::int64_t>::max()),
                               of_session)
                  .seq.size(),
              events.size());
    EXPECT_EQ(store.channels(of_session.session_id.value()), std::vector<std::string>{"wheel"});
  }

  std::set<std::int64_t> present;
  for (const auto& e : events) present.insert(e.seq);
  for (const auto seq : reported) EXPECT_TRUE(present.count(seq)) << "acknowledged seq " << seq << " lost";
  // At most one batch was committed but not yet reported when the kill came.
  if (!reported.empty()) {
    EXPECT_LE(last - reported.back(), std::int64_t{last_batch_size});
  }

  // Whole batches only: batch b is `size` consecutive events with indexes 0..size-1.
  std::uint64_t batch = 0;
  for (std::size_t i = 0; i < events.size();) {
    const auto size = events[i].event.flags;
    EXPECT_GT(size, 0u);
    EXPECT_LE(i + size, events.size()) << "batch " << batch << " is partial";
    for (std::size_t k = 0; k < size && i + k < events.size(); ++k) {
      const auto& e = events[i + k];
      EXPECT_EQ(e.seq, static_cast<std::int64_t>(i + k) + 1);
      EXPECT_EQ(e.event.line_seqno, batch) << "seq " << e.seq;
      EXPECT_EQ(e.event.seqno, k) << "seq " << e.seq;
      EXPECT_EQ(e.event.flags, size) << "seq " << e.seq;
    }
    if (::testing::Test::HasFailure()) break;
    i += size;
    ++batch;
  }
  return batch;
}

}  // namespace

TEST(StoreCrash, KillNineLosesOnlyTheUncommittedBatch) {
  TempDir dir;
  const auto path = dir.file("crash.m2mlat");
  std::int64_t session = 0;
  { session = Store::open(path).begin_session(make_session("vehicle")); }

  struct Round {
    std::uint32_t batch_size;  // events per commit
    std::size_t reports_before_kill;
    useconds_t extra_delay_us;
    Durability durability;
  };
  const std::vector<Round> rounds{{64, 1, 0, Durability::normal},    {64, 4, 137, Durability::normal},
                                  {4096, 2, 0, Durability::normal},  {64, 90, 1'000, Durability::normal},
                                  {1000, 7, 50, Durability::normal}, {4096, 3, 0, Durability::full},
                                  {64, 30, 0, Durability::off},      {4096, 2, 300, Durability::off}};
  std::uint64_t next_batch = 0;
  for (const auto& round : rounds) {
    SCOPED_TRACE(::testing::Message()
                 << "batches of " << round.batch_size << ", kill after " << round.reports_before_kill
                 << " reports, durability " << to_string(round.durability));
    int fds[2];
    ASSERT_EQ(pipe(fds), 0);
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      close(fds[0]);
      append_forever(path, session, round.durability, round.batch_size, next_batch, fds[1]);
    }
    close(fds[1]);

    std::vector<std::int64_t> reported;
    std::int64_t seq = 0;
    while (reported.size() < round.reports_before_kill && read_report(fds[0], seq)) reported.push_back(seq);
    if (round.extra_delay_us > 0) usleep(round.extra_delay_us);
    kill(child, SIGKILL);
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL)
        << "the child exited by itself: " << status;
    while (read_report(fds[0], seq)) reported.push_back(seq);  // reports written before the kill
    close(fds[0]);
    ASSERT_GE(reported.size(), round.reports_before_kill);
    for (std::size_t i = 1; i < reported.size(); ++i) EXPECT_GT(reported[i], reported[i - 1]);

    const auto batches = verify(path, reported, round.batch_size);
    ASSERT_FALSE(::testing::Test::HasFailure());
    EXPECT_GE(batches, next_batch + round.reports_before_kill);
    next_batch = batches;
  }

  // The store continues: a new append gets larger seqs and the file stays sound.
  auto store = Store::open(path);
  const auto before = store.last_seq();
  EXPECT_GT(before, 0);
  const auto first = store.append_events(session, std::vector{make_event("vehicle", "wheel", -1)});
  EXPECT_EQ(first, before + 1);
  EXPECT_TRUE(store.integrity_ok());
}
