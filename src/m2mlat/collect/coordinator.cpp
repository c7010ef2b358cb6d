// The coordinator's start-up and shutdown around the pullers.
#include "m2mlat/collect/coordinator.hpp"

#include <fmt/format.h>

#include <exception>
#include <future>
#include <set>

#include "m2mlat/core/clock_read.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::collect {

Coordinator::Coordinator(CoordinatorOptions options, ErrorSink on_error)
    : options_(std::move(options)), on_error_(std::move(on_error)) {
  if (options_.agents.empty())
    throw core::Error(core::ErrorKind::usage,
                      "say which agents to collect from: --agent URL (one per agent)");
  if (options_.store_path.empty())
    throw core::Error(core::ErrorKind::usage, "say where the campaign goes: --store FILE");
  std::set<std::string> seen;
  for (const auto& url : options_.agents) {
    PullerOptions po;
    po.url = url;
    po.client = options_.client;
    po.store_path = options_.store_path;
    po.durability = options_.durability;
    po.poll_interval = options_.poll_interval;
    po.page = options_.page;
    if (options_.start_session) po.run_session = std::pair{options_.start_session->label, options_.start_session->scenario};
    auto tracker = std::make_shared<NodeTracker>(url, options_.stale_after);
    auto puller = std::make_unique<Puller>(po, tracker, on_error_);
    if (!seen.insert(puller->url()).second)
      throw core::Error(core::ErrorKind::usage, fmt::format("agent {} is given twice", puller->url()));
    trackers_.push_back(std::move(tracker));
    pullers_.push_back(std::move(puller));
  }
}

Coordinator::~Coordinator() {
  try {
    stop();
  } catch (const std::exception& e) {
    if (on_error_) on_error_("", e.what());
  }
}

namespace {

// Created (and migrated) here, once, before the pullers open it from their threads.
void create_store(const std::string& path, store::Durability durability) {
  store::Options so;
  so.durability = durability;
  auto store = store::Store::open(path, so);
  (void)store;
}

}  // namespace

void Coordinator::collect_once() {
  if (running_) throw core::Error(core::ErrorKind::internal, "collect_once while the pullers run");
  create_store(options_.store_path, options_.durability);
  std::vector<std::future<void>> calls;
  for (auto& puller : pullers_)
    calls.push_back(std::async(std::launch::async, [&puller] { puller->catch_up_once(); }));
  std::exception_ptr failure;
  for (std::size_t i = 0; i < calls.size(); ++i) {
    try {
      calls[i].get();
    } catch (const std::exception& e) {
      trackers_[i]->failed(e.what(), core::now_ns(CLOCK_REALTIME));
      if (!failure) failure = std::current_exception();
    }
  }
  if (failure) std::rethrow_exception(failure);
}

std::vector<store::Session> Coordinator::start() {
  if (running_) return {};
  create_store(options_.store_path, options_.durability);
  std::vector<store::Session> begun;
  if (options_.start_session) {
    // All agents at once: one request each, in parallel, so the sessions start together.
    std::vector<std::future<store::Session>> calls;
    for (const auto& url : options_.agents)
      calls.push_back(std::async(std::launch::async, [&, url] {
        net::AgentClient client(url, options_.client);
        return client.start_session(options_.start_session->label, options_.start_session->scenario);
      }));
    std::exception_ptr failure;
    for (auto& call : calls) {
      try {
        begun.push_back(call.get());
      } catch (...) {
        if (!failure) failure = std::current_exception();
      }
    }
    if (failure) std::rethrow_exception(failure);
  }
  for (auto& puller : pullers_) puller->start();
  running_ = true;
  return begun;
}

void Coordinator::stop() {
  if (!running_) return;
  running_ = false;
  // No puller may begin the run's session again once it is stopped.
  for (auto& puller : pullers_) puller->end_run();
  if (options_.stop_session) {
    for (std::size_t i = 0; i < options_.agents.size(); ++i) {
      try {
        net::AgentClient client(options_.agents[i], options_.client);
        client.stop_session();
      } catch (const std::exception& e) {
        if (on_error_) on_error_(pullers_[i]->url(), e.what());
      }
    }
  }
  // In parallel: each takes what its agent has left.
  std::vector<std::future<void>> stops;
  for (auto& puller : pullers_)
    stops.push_back(std::async(std::launch::async, [&puller] { puller->stop(true); }));
  for (auto& s : stops) s.get();
}

std::vector<NodeHealth> Coordinator::health() const {
  const auto now = core::now_ns(CLOCK_REALTIME);
  std::vector<NodeHealth> out;
  out.reserve(trackers_.size());
  for (const auto& tracker : trackers_) out.push_back(tracker->snapshot(now));
  return out;
}

}  // namespace m2mlat::collect
