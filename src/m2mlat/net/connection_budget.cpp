// The connection table's bookkeeping and the thread-per-connection task queue.
#include "m2mlat/net/connection_budget.hpp"

#include <sys/socket.h>

#include <algorithm>
#include <system_error>

namespace m2mlat::net {

namespace {
thread_local bool t_refusing = false;
}  // namespace

bool refusing_connection() { return t_refusing; }

bool ConnectionTable::admit() {
  std::lock_guard lock(mutex_);
  if (closing_) return false;
  if (places_ >= budget_ && !evict_oldest_waiting()) return false;
  ++places_;
  ++counts_.accepted;
  return true;
}

void ConnectionTable::cancel_admit() {
  std::lock_guard lock(mutex_);
  --places_;
  --counts_.accepted;
}

bool ConnectionTable::evict_oldest_waiting() {
  Entry* oldest = nullptr;
  for (auto& [id, e] : entries_)
    if (!e.serving && !e.evicted && (oldest == nullptr || e.since < oldest->since)) oldest = &e;
  if (oldest == nullptr) return false;
  // Its thread wakes from poll() or recv() at once and ends the connection; its place is the new one's.
  ::shutdown(oldest->socket, SHUT_RDWR);
  oldest->evicted = true;
  --places_;
  ++counts_.evicted;
  return true;
}

ConnectionTable::Id ConnectionTable::add(int socket) {
  std::lock_guard lock(mutex_);
  const auto id = next_++;
  entries_.emplace(id, Entry{socket, false, false, std::chrono::steady_clock::now()});
  return id;
}

bool ConnectionTable::waiting(Id id) {
  std::lock_guard lock(mutex_);
  auto& e = entries_.at(id);
  if (closing_ || e.evicted) return false;
  e.serving = false;
  e.since = std::chrono::steady_clock::now();
  return true;
}

void ConnectionTable::serving(Id id) {
  std::lock_guard lock(mutex_);
  entries_.at(id).serving = true;
}

void ConnectionTable::remove(Id id) {
  std::lock_guard lock(mutex_);
  const auto it = entries_.find(id);
  if (!it->second.evicted) --places_;
  entries_.erase(it);
}

void ConnectionTable::count_refused() {
  std::lock_guard lock(mutex_);
  ++counts_.refused;
}

void ConnectionTable::count_timed_out() {
  std::lock_guard lock(mutex_);
  ++counts_.timed_out;
}

void ConnectionTable::count_idle() {
  std::lock_guard lock(mutex_);
  ++counts_.idle;
}

void ConnectionTable::close() {
  std::lock_guard lock(mutex_);
  closing_ = true;
  for (auto& [id, e] : entries_)
    if (!e.serving) ::shutdown(e.socket, SHUT_RDWR);
}

ConnectionCounts ConnectionTable::counts() const {
  std::lock_guard lock(mutex_);
  auto c = counts_;
  c.open = entries_.size();
  return c;
}

BudgetQueue::~BudgetQueue() { shutdown(); }

void BudgetQueue::enqueue(std::function<void()> task) {
  reap();
  const auto refuse = [&] {
    t_refusing = true;
    task();
    t_refusing = false;
  };
  if (!table_.admit()) return refuse();
  try {
    std::lock_guard lock(mutex_);
    // A copy: if no thread can be made, the task is still here to refuse the connection.
    threads_.emplace_back([this, task]() mutable {
      task();
      task = nullptr;
      std::lock_guard done(mutex_);
      finished_.push_back(std::this_thread::get_id());
    });
  } catch (const std::system_error&) {  // no thread to be had: refused like a full budget
    table_.cancel_admit();
    refuse();
  }
}

void BudgetQueue::reap() {
  std::list<std::thread> done;
  {
    std::lock_guard lock(mutex_);
    for (const auto id : finished_) {
      const auto it = std::find_if(threads_.begin(), threads_.end(),
                                   [id](const std::thread& t) { return t.get_id() == id; });
      if (it != threads_.end()) done.splice(done.end(), threads_, it);
    }
    finished_.clear();
  }
  for (auto& t : done) t.join();
}

void BudgetQueue::shutdown() {
  table_.close();
  std::list<std::thread> all;
  {
    std::lock_guard lock(mutex_);
    all.swap(threads_);
    finished_.clear();
  }
  for (auto& t : all)
    if (t.joinable()) t.join();
}

}  // namespace m2mlat::net
