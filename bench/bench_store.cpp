// Store append throughput: events per second committed to a new store file, by batch size (events
// per transaction) and durability (normal: WAL + synchronous=NORMAL, survives a process crash;
// full: every commit fsynced, survives a power loss), and through the batching writer the
// recorder uses (one add() per event, a commit every max_batch events).
//
// Each case starts from an empty store in the run's temporary directory and keeps appending for as
// long as the case runs, with timestamps and sequence numbers increasing as a capture's would, so
// the indexes grow at their end as in a recording.
#include <fmt/format.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "m2mlat/core/event.hpp"
#include "m2mlat/store/event_writer.hpp"
#include "m2mlat/store/store.hpp"
#include "registry.hpp"
#include "workload.hpp"

namespace m2mlat::bench {

namespace {

constexpr std::int64_t kStartNs = 1'780'304'400'000'000'000;  // 2026-06-01T09:00:00Z
constexpr std::int64_t kEdgeSpacingNs = 20'000'000;           // one edge every 20 ms

// A new store file with one open session of node "operator"; removed (with its WAL) on destruction.
class ScratchStore {
 public:
  ScratchStore(const std::string& name, store::Durability durability)
      : path_((scratch_dir() / (name + ".db")).string()), store_(open(path_, durability)) {
    store::Session session;
    session.label = "bench";
    session.scenario = "bench";
    session.node = "operator";
    session.role = core::Role::cause;
    session.start = core::TimePoint::from_ns(core::Clock::realtime, kStartNs);
    session_ = store_->begin_session(session);
  }
  ScratchStore(const ScratchStore&) = delete;
  ScratchStore& operator=(const ScratchStore&) = delete;
  ~ScratchStore() {
    store_.reset();  // close before removing
    for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(path_ + suffix);
  }
  store::Store& store() { return *store_; }
  std::int64_t session() const { return session_; }

 private:
  static store::Store open(const std::string& path, store::Durability durability) {
    for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(path + suffix);
    store::Options options;
    options.durability = durability;
    return store::Store::open(path, options);
  }

  std::string path_;
  std::optional<store::Store> store_;
  std::int64_t session_ = 0;
};

// The k-th edge of a capture on the operator's wheel (k from 0).
core::Event edge(std::uint64_t k) {
  core::Event e;
  e.node = "operator";
  e.channel = "wheel";
  e.edge = core::Edge::falling;
  e.time = core::TimePoint::from_ns(core::Clock::realtime,
                                    kStartNs + static_cast<std::int64_t>(k) * kEdgeSpacingNs);
  e.seqno = k + 1;
  e.line_seqno = k + 1;
  return e;
}

void add_append(std::size_t batch_size, store::Durability durability) {
  const auto name = fmt::format("append/batch:{}/durability:{}", batch_size, store::to_string(durability));
  add("store/" + name, [=](benchmark::State& state) {
    ScratchStore scratch(fmt::format("append-{}-{}", batch_size, store::to_string(durability)), durability);
    std::vector<core::Event> batch;
    for (std::size_t k = 0; k < batch_size; ++k) batch.push_back(edge(k));
    const auto step = core::Duration{static_cast<std::int64_t>(batch_size) * kEdgeSpacingNs};
    for (auto _ : state) {
      scratch.store().append_events(scratch.session(), batch);
      for (auto& e : batch) {  // the next batch continues where this one ended
        e.time = e.time + step;
        e.seqno += batch_size;
        e.line_seqno += batch_size;
      }
    }
    set_rate(state, batch_size, "events");
  });
}

void add_writer(std::size_t max_batch, store::Durability durability) {
  const auto name = fmt::format("writer/max_batch:{}/durability:{}", max_batch, store::to_string(durability));
  add("store/" + name, [=](benchmark::State& state) {
    ScratchStore scratch(fmt::format("writer-{}-{}", max_batch, store::to_string(durability)), durability);
    store::WriterOptions options;
    options.max_batch = max_batch;
    options.max_age = std::chrono::seconds(3600);  // commits by size only: the rate of a busy capture
    store::EventWriter writer(scratch.store(), scratch.session(), options);
    std::uint64_t k = 0;
    for (auto _ : state) writer.add(edge(k++));
    writer.flush();  // after the timed loop: the last partial batch is not counted
    set_rate(state, 1, "events");
  });
}

}  // namespace

void register_store_benchmarks() {
  for (auto durability : {store::Durability::normal, store::Durability::full})
    for (std::size_t batch : {1u, 100u, 10'000u}) add_append(batch, durability);
  for (auto durability : {store::Durability::normal, store::Durability::full}) add_writer(512, durability);
}

}  // namespace m2mlat::bench
