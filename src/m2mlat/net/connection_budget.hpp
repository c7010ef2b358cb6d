// The connection budget of the HTTP server (http_server.hpp): every accepted connection gets a
// thread of its own, up to a budget; when the budget is full, the connection that has waited longest
// without having delivered a complete request head (idle between requests, or still trickling one
// in) is closed to make room, so a new client is never queued behind slow or idle ones. Only when
// every connection is busy serving a request is the new one refused at once.
//
// The table knows each connection's state (waiting for a request, or serving one) and socket, so it
// can shut down the one it evicts; the queue is cpp-httplib's TaskQueue hook, given each accepted
// connection's task by httplib's listening loop.
#pragma once

#include <httplib.h>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <list>
#include <map>
#include <mutex>
#include <thread>
#include <vector>

#include "m2mlat/net/http_server.hpp"

namespace m2mlat::net {

class ConnectionTable {
 public:
  using Id = std::uint64_t;
  explicit ConnectionTable(std::size_t budget) : budget_(budget < 1 ? 1 : budget) {}

  // For the accepting thread: reserves a place for a new connection, evicting the longest-waiting
  // connection if the budget is full. False if every place is taken by a connection serving a
  // request (or the table is closing): the new connection is to be refused.
  bool admit();
  // Gives back a place admit() reserved whose connection never started (no thread could be made).
  void cancel_admit();

  // From the connection's own thread. add() registers its socket (in the waiting state).
  Id add(int socket);
  // The connection waits for (or reads) a request: it may be evicted from now on. False when the
  // table is closing or the connection was evicted: the connection is to end.
  bool waiting(Id id);
  // The connection has delivered a request head and is being served: it is not evicted.
  void serving(Id id);
  void remove(Id id);  // before the socket is closed, so that eviction never touches a reused fd

  void count_refused();
  void count_timed_out();
  void count_idle();

  // Stop: refuse new connections and shut down every waiting one (serving ones finish their
  // request first and then find waiting() false).
  void close();
  ConnectionCounts counts() const;

 private:
  struct Entry {
    int socket;
    bool serving = false;
    bool evicted = false;
    std::chrono::steady_clock::time_point since;  // when it began waiting for its current request
  };
  bool evict_oldest_waiting();  // with mutex_ held

  const std::size_t budget_;
  mutable std::mutex mutex_;
  std::map<Id, Entry> entries_;
  std::size_t places_ = 0;  // admitted connections not yet removed, not counting evicted ones
  Id next_ = 1;
  bool closing_ = false;
  ConnectionCounts counts_;
};

// True while the current thread runs a connection's task only to refuse it (BudgetQueue below runs
// such a task on the accepting thread itself; the server then answers 503 and closes at once).
bool refusing_connection();

// httplib's TaskQueue: a thread per admitted connection; a refused one runs on the caller's thread.
class BudgetQueue final : public httplib::TaskQueue {
 public:
  explicit BudgetQueue(ConnectionTable& table) : table_(table) {}
  ~BudgetQueue() override;
  void enqueue(std::function<void()> task) override;
  void shutdown() override;  // closes the table, then joins every connection's thread

 private:
  void reap();  // joins the threads that have finished

  ConnectionTable& table_;
  std::mutex mutex_;
  std::list<std::thread> threads_;
  std::vector<std::thread::id> finished_;
};

}  // namespace m2mlat::net
