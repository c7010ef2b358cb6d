// Buffering, the size/age commit rule, and the acknowledged point.
#include "m2mlat/store/event_writer.hpp"

#include <fmt/format.h>

#include <utility>

#include "m2mlat/core/error.hpp"
#include "m2mlat/store/validate.hpp"

namespace m2mlat::store {

EventWriter::EventWriter(Store& store, std::int64_t session_id, WriterOptions options)
    : store_(store), options_(std::move(options)) {
  if (options_.max_batch == 0) options_.max_batch = 1;
  const auto session = store_.session(session_id);
  if (!session)
    core::throw_data_error({store_.path(), 0},
                           fmt::format("writing events: session {} does not exist", session_id));
  if (session->end)
    core::throw_data_error({store_.path(), 0},
                           fmt::format("writing events: session {} has ended", session_id));
  node_ = session->node;
  batch_.session_id = session_id;
  last_committed_seq_ = store_.last_seq();
}

EventWriter::~EventWriter() {
  try {
    flush();
  } catch (...) {  // NOLINT(bugprone-empty-catch): a destructor cannot report; flush() first to see errors
  }
}

void EventWriter::add(const core::Event& event) {
  validate::event(store_.path(), batch_.events.size(), event);
  if (event.node != node_)
    core::throw_data_error({store_.path(), 0},
                           fmt::format("event: field 'node' is '{}', but session {} records node '{}'",
                                       event.node, batch_.session_id, node_));
  batch_.events.push_back(event);
  buffered();
}

void EventWriter::add(const Loss& loss) {
  validate::loss(store_.path(), batch_.losses.size(), loss);
  if (loss.session_id != batch_.session_id)
    core::throw_data_error({store_.path(), 0},
                           fmt::format("loss: field 'session_id' is {}, the writer's session is {}",
                                       loss.session_id, batch_.session_id));
  batch_.losses.push_back(loss);
  buffered();
}

void EventWriter::add(const ClockSample& sample) {
  validate::clock_sample(store_.path(), batch_.clock_samples.size(), sample);
  if (sample.session_id != batch_.session_id)
    core::throw_data_error({store_.path(), 0},
                           fmt::format("clock sample: field 'session_id' is {}, the writer's session is {}",
                                       sample.session_id, batch_.session_id));
  batch_.clock_samples.push_back(sample);
  buffered();
}

void EventWriter::add(const RateBlock& block) {
  validate::rate_block(store_.path(), batch_.rate_blocks.size(), block);
  if (block.session_id != batch_.session_id)
    core::throw_data_error({store_.path(), 0},
                           fmt::format("rate block: field 'session_id' is {}, the writer's session is {}",
                                       block.session_id, batch_.session_id));
  batch_.rate_blocks.push_back(block);
  buffered();
}

bool EventWriter::poll() {
  if (pending() == 0 || !due()) return false;
  flush();
  return true;
}

AppendResult EventWriter::flush() {
  if (pending() == 0) return {};
  const AppendResult result = store_.append(batch_);  // throws: the batch stays for a retry
  if (result.last_seq != 0) last_committed_seq_ = result.last_seq;
  committed_events_ += batch_.events.size();
  if (options_.on_commit) options_.on_commit(batch_, result);
  batch_.events.clear();
  batch_.losses.clear();
  batch_.clock_samples.clear();
  batch_.rate_blocks.clear();
  return result;
}

std::size_t EventWriter::pending() const {
  return batch_.events.size() + batch_.losses.size() + batch_.clock_samples.size() + batch_.rate_blocks.size();
}

void EventWriter::buffered() {
  const auto n = pending();
  if (n == 1) oldest_ = now();
  if (n >= options_.max_batch || (options_.age_on_add && now() - oldest_ >= options_.max_age)) flush();
}

bool EventWriter::due() const {
  return pending() >= options_.max_batch || now() - oldest_ >= options_.max_age;
}

core::Duration EventWriter::now() const {
  if (options_.now) return options_.now();
  return std::chrono::duration_cast<core::Duration>(std::chrono::steady_clock::now().time_since_epoch());
}

}  // namespace m2mlat::store
