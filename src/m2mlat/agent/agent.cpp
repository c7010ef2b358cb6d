// The recorder thread, the live snapshot and the session requests.
#include "m2mlat/agent/agent.hpp"

#include <fmt/format.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <exception>
#include <thread>

#include "m2mlat/core/clock_read.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/core/fd.hpp"
#include "m2mlat/markers/mark_datagram.hpp"
#include "m2mlat/markers/stored_markers.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::agent {

Agent::Agent(AgentOptions options, capture::Source& source) : options_(std::move(options)), source_(source) {
  options_.server.store_path = options_.store_path;
  server_ = std::make_unique<net::AgentServer>(options_.server, *this);  // checks the address rule
}

Agent::~Agent() { server_->stop(); }

void Agent::start() {
  // The store must exist before the server's threads open it read-only.
  {
    auto store = store::Store::open(options_.store_path, options_.store_options);
    // A session of this node still open was cut when the agent was killed: the first session goes on
    // with its run (label and scenario) unless the configuration names a scenario.
    const auto& first = options_.recorder.session;
    const auto sessions = store.sessions();
    const bool named = !first.scenario.empty() && first.scenario != store::kUnnamedScenario;
    for (auto it = sessions.rbegin(); it != sessions.rend() && !named; ++it)
      if (it->node == first.node) {
        if (!it->end) resumed_ = net::SessionRequest{it->label, it->scenario};
        break;
      }
  }
  server_->start();
  if (options_.marks) {
    marks_ = std::make_unique<markers::MarkReceiver>(options_.marks->address, options_.marks->port);
    std::lock_guard lock(mutex_);
    mark_status_.address = marks_->address();
    mark_status_.stamps = marks_->kernel_stamps() ? "kernel" : "receiver";
  }
}

std::string Agent::mark_address() const { return marks_ ? marks_->address() : std::string(); }

void Agent::refuse_mark(std::string_view reason, const std::string& detail) {
  std::lock_guard lock(mutex_);
  auto& rejected = mark_status_.rejected;
  auto it = std::find_if(rejected.begin(), rejected.end(), [&](const auto& r) { return r.first == reason; });
  if (it == rejected.end()) {
    rejected.emplace_back(reason, 0);
    it = std::prev(rejected.end());
  }
  ++it->second;
  mark_status_.last_rejection = fmt::format("{}: {}", reason, detail);
}

void Agent::mark_loop(int wake_fd) {
  auto store = store::Store::open(options_.store_path, options_.store_options);
  // Datagrams read per commit at most: a burst is stored in few transactions, and a flood cannot
  // keep the thread from seeing the stop.
  constexpr std::size_t kMarksPerCommit = 256;
  for (;;) {
    std::array<pollfd, 2> fds{pollfd{marks_->fd(), POLLIN, 0}, pollfd{wake_fd, POLLIN, 0}};
    if (::poll(fds.data(), fds.size(), -1) < 0) {
      if (errno == EINTR) continue;
      throw core::Error(core::ErrorKind::io, fmt::format("marker port: poll: {}", std::strerror(errno)));
    }
    std::vector<store::MarkerRecord> rows;
    std::vector<std::string> senders;
    std::vector<markers::ReceivedMark> stored;  // acknowledged once committed
    bool drained = false;
    while (rows.size() < kMarksPerCommit) {
      auto got = marks_->receive();
      if (!got) {
        drained = true;
        break;
      }
      if (!got->marker) {
        refuse_mark(got->reason, got->detail);
        marks_->acknowledge(*got, fmt::format("refused {}: {}", got->reason, got->detail));
        continue;
      }
      std::optional<std::int64_t> session;
      {
        std::lock_guard lock(mutex_);
        if (open_) session = open_->id;
      }
      if (!session) {
        refuse_mark("session", fmt::format("{}: no session open", got->marker->origin));
        marks_->acknowledge(*got, "refused session: no session open");
        continue;
      }
      rows.push_back(markers::to_record(*got->marker, *session));
      senders.push_back(got->marker->origin);
      stored.push_back(std::move(*got));
    }
    if (!rows.empty()) {
      try {
        store.append_markers(rows);
        {
          std::lock_guard lock(mutex_);
          mark_status_.stored += rows.size();
        }
        for (std::size_t k = 0; k < stored.size(); ++k)
          marks_->acknowledge(stored[k], fmt::format("stored {}", rows[k].session_id));
      } catch (const core::Error& e) {
        // The session ended between the read and the commit, or the store refused: nothing of the
        // batch is stored, and each datagram is counted as refused.
        for (const auto& sender : senders) refuse_mark("store", fmt::format("{}: {}", sender, e.what()));
        for (const auto& m : stored) marks_->acknowledge(m, fmt::format("refused store: {}", e.what()));
      }
    }
    // Stopping: only once what had arrived is stored.
    if ((fds[1].revents & POLLIN) != 0 && drained) return;
  }
}

int Agent::port() const { return server_->port(); }
std::string Agent::address() const { return server_->address(); }
bool Agent::tls() const { return server_->tls(); }

void Agent::on_progress(const capture::RecordCounters& counters) {
  std::lock_guard lock(mutex_);
  counters_ = counters;
}

// Passed on; always set, so that the recorder takes a round every commit interval even without a
// clock monitor (the status's counters and clock stay fresh while no edge comes).
void Agent::before_commit(std::int64_t session_id, std::vector<store::ClockSample>& samples) {
  if (options_.recorder.before_commit) options_.recorder.before_commit(session_id, samples);
}

capture::RecordCounters Agent::run(int stop_fd, const std::function<std::string()>& stop_name) {
  auto store = store::Store::open(options_.store_path, options_.store_options);
  auto recorder_options = options_.recorder;
  recorder_options.control = &control_;
  recorder_options.start_session = false;
  recorder_options.on_progress = [this](const capture::RecordCounters& c) { on_progress(c); };
  recorder_options.on_commit = [this](std::int64_t seq) { server_->notify_commit(seq); };
  recorder_options.before_commit = [this](std::int64_t id, std::vector<store::ClockSample>& samples) {
    before_commit(id, samples);
  };
  capture::Recorder recorder(store, source_, recorder_options);

  capture::RecordCounters result;
  std::exception_ptr failure;
  {
    std::lock_guard lock(mutex_);
    started_ns_ = core::realtime_now().ns();
  }
  // The marker thread runs until the API stops (markers may come while the data is served).
  core::Fd wake(::eventfd(0, EFD_CLOEXEC));
  if (marks_ && !wake) throw core::Error(core::ErrorKind::io, fmt::format("eventfd: {}", std::strerror(errno)));
  std::thread thread([&] {
    try {
      result = recorder.run(stop_fd, stop_name);
    } catch (...) {
      failure = std::current_exception();
    }
  });
  std::exception_ptr mark_failure;
  std::thread mark_thread;
  if (marks_)
    mark_thread = std::thread([&] {
      try {
        mark_loop(wake.get());
      } catch (...) {
        mark_failure = std::current_exception();
      }
    });
  // The first session, through the same path as the API's.
  try {
    open_session(resumed_.value_or(net::SessionRequest{options_.recorder.session.label, options_.recorder.session.scenario}));
  } catch (
      const std::exception&) {  // NOLINT(bugprone-empty-catch): the recorder stopped first; run() reports why
  }
  {
    std::lock_guard lock(mutex_);
    first_done_ = true;
  }
  first_cv_.notify_all();
  thread.join();
  {
    std::lock_guard lock(mutex_);
    open_.reset();
    counters_ = result;
  }
  // A finished source (a simulated run's end): the data stays available until we are told to stop.
  if (!failure && result.stop_reason == "source finished" && stop_fd >= 0) {
    pollfd fd{stop_fd, POLLIN, 0};
    while (::poll(&fd, 1, -1) < 0 && errno == EINTR) {
    }
    if (stop_name) stop_name();
  }
  if (mark_thread.joinable()) {
    const std::uint64_t one = 1;
    if (::write(wake.get(), &one, sizeof one) < 0) {
      // An eventfd write fails only on overflow, impossible after one write; join anyway.
    }
    mark_thread.join();
  }
  server_->stop();
  if (failure) std::rethrow_exception(failure);
  if (mark_failure) std::rethrow_exception(mark_failure);
  return result;
}

net::Status Agent::live_status() {
  net::Status s;
  s.node = options_.recorder.session.node;
  s.role = options_.recorder.session.role;
  std::lock_guard lock(mutex_);
  s.session = open_;
  for (const auto& c : counters_.channels) {
    s.channels.push_back({c.channel, c.events, c.suppressed, c.lost,
                          c.last ? std::optional<std::int64_t>(c.last->ns()) : std::nullopt});
    s.lost += c.lost;
  }
  if (s.channels.empty())
    for (const auto& name : source_.channels()) s.channels.push_back({name, 0, 0, 0, std::nullopt});
  s.lost += counters_.node_lost;
  s.events = counters_.events;
  s.dropped = counters_.dropped;
  s.clock = counters_.last_clock;  // the monitor's or the source's own (a simulated board's)
  s.started_ns = started_ns_;
  if (marks_) s.marks = mark_status_;
  return s;
}

void Agent::await_first_session() {
  std::unique_lock lock(mutex_);
  if (!first_cv_.wait_for(lock, options_.server.session_timeout, [this] { return first_done_; }))
    throw net::RequestError(503, "the recorder has not begun its first session yet");
}

store::Session Agent::begin_session(const net::SessionRequest& request) {
  await_first_session();
  return open_session(request);
}

store::Session Agent::open_session(const net::SessionRequest& request) {
  std::lock_guard serial(request_mutex_);
  auto next = options_.recorder.session;
  next.label = request.label;
  next.scenario = request.scenario.empty() ? store::kUnnamedScenario : request.scenario;
  const auto ticket = control_.request_begin(next);
  const auto outcome = control_.wait(ticket, options_.server.session_timeout);
  if (!outcome || !outcome->begun)
    throw net::RequestError(503, "the recorder is not running: no session begun");
  std::lock_guard lock(mutex_);
  open_ = outcome->begun;
  return *outcome->begun;
}

std::optional<store::Session> Agent::stop_session() {
  await_first_session();
  std::lock_guard serial(request_mutex_);
  const auto ticket = control_.request_stop();
  const auto outcome = control_.wait(ticket, options_.server.session_timeout);
  if (!outcome) throw net::RequestError(503, "the recorder is not running");
  std::lock_guard lock(mutex_);
  open_.reset();
  return outcome->ended;
}

}  // namespace m2mlat::agent
