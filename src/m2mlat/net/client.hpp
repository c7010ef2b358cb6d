// The coordinator's side of the agent HTTP API (docs/api.md, version 1): one AgentClient per agent
// base URL ("http://10.0.0.2:8470" or "https://..."), decoding answers with the wire format
// (wire.hpp). Every failure is a core::Error naming the URL: io for the network, a timeout or an
// HTTP error status; data for an answer that is not what the API promises.
//
// An AgentClient is used by one thread at a time, except cancel(), which any thread may call to
// break a request in progress (e.g. a stream waiting for events) so that its owner can stop.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "m2mlat/net/wire.hpp"
#include "m2mlat/store/records.hpp"

namespace httplib {
class Client;
}

namespace m2mlat::net {

struct ClientOptions {
  std::string token;    // bearer token sent with every request; empty = none
  std::string ca_file;  // PEM file of the CAs trusted for https:// URLs; empty = the system's
  std::chrono::milliseconds connect_timeout{2000};
  // The longest wait for any read (a response, or the next chunk of a stream: the agent pings
  // every second while idle, so a stream silent for longer than this means a frozen agent).
  std::chrono::milliseconds read_timeout{5000};
  std::chrono::milliseconds write_timeout{5000};
};

// The node and role of the session an event names: events carry only their session's id on the
// wire. Returns nullptr for a session it does not know (the event is then refused as data error).
using SessionLookup = std::function<const store::Session*(std::int64_t session_id)>;

// One page of /v1/events: the events (seq order, all > after) and the agent's last committed seq.
struct EventPage {
  std::vector<store::StoredEvent> events;
  std::int64_t last_seq = 0;  // X-M2mlat-Last-Seq (the page's last seq if the header is absent)
};

// A page of /v1/events as received, not yet decoded: so that a caller can fetch the next page
// while it decodes and stores this one.
struct RawEventPage {
  std::int64_t after = 0;
  std::size_t limit = 0;
  std::string body;                      // NDJSON
  std::optional<std::int64_t> last_seq;  // X-M2mlat-Last-Seq, checked to be a number
  std::size_t lines() const;             // newline-terminated lines in the body
  // The seq of the body's last event, read from its last line alone; nullopt if the body is empty
  // or that line is not an event (decode_events then says what is wrong).
  std::optional<std::int64_t> last_event_seq() const;
};

// Called for each event of the stream, in seq order (decoded like events_after). Return false to stop.
using StreamEventHandler = std::function<bool(store::StoredEvent&& event)>;
// Called after every piece of the stream that arrived (events or a keep-alive ping) was handled:
// the place to commit what the events built up. Return false to stop.
using StreamChunkHandler = std::function<bool()>;

class AgentClient {
 public:
  explicit AgentClient(std::string base_url, ClientOptions options = {});
  ~AgentClient();
  AgentClient(const AgentClient&) = delete;
  AgentClient& operator=(const AgentClient&) = delete;

  const std::string& url() const { return url_; }

  Status status();
  std::vector<store::Session> sessions();
  // limit: 1 .. 10000 (the API's maximum).
  EventPage events_after(std::int64_t after, std::size_t limit, const SessionLookup& lookup);
  // events_after in two steps: the request, and the decoding (which calls lookup, and so may
  // use this client again).
  RawEventPage fetch_events(std::int64_t after, std::size_t limit);
  EventPage decode_events(const RawEventPage& page, const SessionLookup& lookup) const;
  std::vector<store::StoredClockSample> clock_samples_after(std::int64_t after, std::size_t limit);
  std::vector<store::StoredLoss> losses_after(std::int64_t after, std::size_t limit);
  // GET /v1/rate-blocks: at most kMaxRateBlocksPerPage blocks whatever the limit (1 .. 10000).
  std::vector<store::StoredRateBlock> rate_blocks_after(std::int64_t after, std::size_t limit);
  // GET /v1/markers (limit 1 .. 10000).
  std::vector<store::StoredMarker> markers_after(std::int64_t after, std::size_t limit);
  // POST /v1/sessions: ends the agent's open session and begins a new one; returns it.
  store::Session start_session(const std::string& label, const std::string& scenario);
  // POST /v1/sessions/current/stop: returns the ended session; std::nullopt if none was open (409).
  std::optional<store::Session> stop_session();

  // GET /v1/events/stream?after=SEQ: blocks, calling on_event per event (seq order, each > after)
  // and on_chunk after each arrival, until a handler returns false or cancel() is called (both
  // return normally) or the stream fails (throws). The agent pings every second while idle, so a
  // stream silent for longer than read_timeout fails; one the agent ends by itself fails too.
  void stream_events(std::int64_t after, const SessionLookup& lookup, const StreamEventHandler& on_event,
                     const StreamChunkHandler& on_chunk);

  // Breaks the request in progress, from any thread, and makes stream_events return at once from
  // now on (the client is being shut down). Other requests keep working.
  void cancel();

 private:
  std::string get_body(const std::string& path, const char* content_type);
  template <class T, class Decode>
  std::vector<T> ndjson(const std::string& path, Decode decode);

  std::string url_;
  ClientOptions options_;
  std::unique_ptr<httplib::Client> http_;
  std::atomic<bool> cancelled_{false};
};

}  // namespace m2mlat::net
