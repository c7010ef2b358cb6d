// The one server-sent-events writer on a real HttpServer over loopback: it writes what its source
// gives at once and byte for byte, pings after the ping interval without a write, wakes on a
// notify long before its poll interval, ends every stream at stop, and holds a stream slot.
#include "m2mlat/net/event_stream.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <httplib.h>

#include <atomic>
#include <chrono>
#include <future>
#include <iterator>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "m2mlat/net/query.hpp"

namespace m2mlat::net {
namespace {

using namespace std::chrono_literals;
using Steady = std::chrono::steady_clock;

// A server with one event stream, /s, whose events are the strings pushed so far ("id: N\nevent:
// item\ndata: TEXT\n\n", N counting from 1), each stream starting at the first.
class Streams {
 public:
  Streams(EventStreamOptions options, std::size_t max_streams = 4) {
    HttpServerOptions o;
    o.max_streams = max_streams;
    server_ = std::make_unique<HttpServer>(o);
    server_->routes().Get("/s", [this, options](const httplib::Request&, httplib::Response& res) {
      try {
        auto slot = take_stream_slot(*server_);
        serve_event_stream(res, std::move(slot), signal_, options,
                           [this, sent = std::size_t{0}](std::string& out) mutable {
                             std::lock_guard lock(mutex_);
                             for (; sent < items_.size(); ++sent)
                               fmt::format_to(std::back_inserter(out), "id: {}\nevent: item\ndata: {}\n\n",
                                              sent + 1, items_[sent]);
                           });
      } catch (const RequestError& e) {
        res.status = e.status();
        res.set_content(e.what(), "text/plain");
      }
    });
    server_->start();
  }
  ~Streams() { stop(); }

  void push(const std::string& text, bool notify = true) {
    {
      std::lock_guard lock(mutex_);
      items_.push_back(text);
    }
    if (notify) signal_.notify();
  }
  void stop() {
    signal_.stop();
    server_->stop();
  }
  int port() const { return server_->port(); }

 private:
  std::unique_ptr<HttpServer> server_;
  StreamSignal signal_;
  std::mutex mutex_;
  std::vector<std::string> items_;
};

// What a client of /s receives, as it arrives.
class Reader {
 public:
  explicit Reader(int port) {
    done_ = std::async(std::launch::async, [this, port] {
      httplib::Client c("127.0.0.1", port);
      c.set_read_timeout(30s);
      c.Get(
          "/s",
          [this](const httplib::Response& head) {
            std::lock_guard lock(mutex_);
            content_type_ = head.get_header_value("Content-Type");
            return true;
          },
          [this](const char* data, std::size_t n) {
            std::lock_guard lock(mutex_);
            text_.append(data, n);
            return !quit_;
          });
    });
  }
  ~Reader() {
    quit_ = true;
    done_.wait();
  }
  std::string text() {
    std::lock_guard lock(mutex_);
    return text_;
  }
  // Waits up to `limit` for the text received to contain `part`; the time it took.
  std::optional<Steady::duration> wait_for(const std::string& part, Steady::duration limit = 5s) {
    const auto start = Steady::now();
    while (Steady::now() - start < limit) {
      if (text().find(part) != std::string::npos) return Steady::now() - start;
      std::this_thread::sleep_for(2ms);
    }
    return std::nullopt;
  }
  bool ended_within(Steady::duration limit) { return done_.wait_for(limit) == std::future_status::ready; }
  std::string content_type() {
    std::lock_guard lock(mutex_);
    return content_type_;
  }

 private:
  std::mutex mutex_;
  std::string text_;
  std::string content_type_;
  std::atomic<bool> quit_{false};
  std::future<void> done_;
};

TEST(EventStream, WritesWhatTheSourceGivesThenPingsWhenIdle) {
  Streams streams({.ping_interval = 150ms, .poll_interval = 10s});
  streams.push("a");
  streams.push("b");
  Reader reader(streams.port());
  ASSERT_TRUE(reader.wait_for(": ping\n\n"));
  EXPECT_EQ(reader.text(), "id: 1\nevent: item\ndata: a\n\nid: 2\nevent: item\ndata: b\n\n: ping\n\n");
  streams.push("c");
  ASSERT_TRUE(reader.wait_for("data: c\n\n"));
  ASSERT_TRUE(reader.wait_for("data: c\n\n: ping\n\n: ping\n\n"));  // pings go on while idle
  streams.stop();
  const std::string head =
      "id: 1\nevent: item\ndata: a\n\nid: 2\nevent: item\ndata: b\n\n: ping\n\nid: 3\nevent: item\ndata: "
      "c\n\n";
  auto text = reader.text();
  ASSERT_EQ(text.substr(0, head.size()), head);
  for (text.erase(0, head.size()); text.starts_with(": ping\n\n");) text.erase(0, 8);
  EXPECT_EQ(text, "");  // nothing but pings after the last event
  EXPECT_TRUE(reader.ended_within(5s));
  EXPECT_EQ(reader.content_type(), "text/event-stream");
}

TEST(EventStream, ANotifyWakesTheStreamLongBeforeThePollInterval) {
  Streams streams({.ping_interval = 30s, .poll_interval = 30s});
  streams.push("first");
  Reader reader(streams.port());
  ASSERT_TRUE(reader.wait_for("data: first\n\n"));
  std::this_thread::sleep_for(50ms);  // the stream sleeps now
  streams.push("second");
  const auto took = reader.wait_for("data: second\n\n");
  ASSERT_TRUE(took);
  EXPECT_LT(*took, 2s);
  streams.stop();  // before the reader goes: it would wait for the next write
}

TEST(EventStream, WithoutANotifyTheSourceIsAskedAgainAfterThePollInterval) {
  Streams streams({.ping_interval = 30s, .poll_interval = 100ms});
  Reader reader(streams.port());
  std::this_thread::sleep_for(50ms);
  streams.push("quiet", false);  // as a store another process writes
  const auto took = reader.wait_for("data: quiet\n\n");
  ASSERT_TRUE(took);
  EXPECT_LT(*took, 2s);
  EXPECT_EQ(reader.text(), "id: 1\nevent: item\ndata: quiet\n\n");
  streams.stop();
}

TEST(EventStream, StopEndsEveryStream) {
  Streams streams({.ping_interval = 30s, .poll_interval = 30s});
  streams.push("x");
  Reader one(streams.port()), two(streams.port());
  ASSERT_TRUE(one.wait_for("data: x\n\n"));
  ASSERT_TRUE(two.wait_for("data: x\n\n"));
  const auto start = Steady::now();
  streams.stop();
  EXPECT_TRUE(one.ended_within(5s));
  EXPECT_TRUE(two.ended_within(5s));
  EXPECT_LT(Steady::now() - start, 5s);
}

TEST(EventStream, EachStreamHoldsASlotUntilItEnds) {
  Streams streams({.ping_interval = 100ms, .poll_interval = 100ms}, 1);
  streams.push("x");
  {
    Reader first(streams.port());
    ASSERT_TRUE(first.wait_for("data: x\n\n"));
    httplib::Client c("127.0.0.1", streams.port());
    const auto refused = c.Get("/s");
    ASSERT_TRUE(refused);
    EXPECT_EQ(refused->status, 503);
    EXPECT_EQ(refused->body, "too many event streams (at most 1)");
  }  // the client goes; the server sees it at its next write (a ping) and frees the slot
  std::string received;
  for (int i = 0; i < 50 && received.find("data: x") == std::string::npos; ++i) {
    std::this_thread::sleep_for(50ms);
    httplib::Client c("127.0.0.1", streams.port());
    c.Get("/s", [&](const char* data, std::size_t n) {
      received.append(data, n);
      return false;
    });
  }
  EXPECT_NE(received.find("id: 1\nevent: item\ndata: x\n\n"), std::string::npos) << received;
}

}  // namespace
}  // namespace m2mlat::net
