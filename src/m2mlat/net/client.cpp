// AgentClient: GET/POST over cpp-httplib, NDJSON pages, and the server-sent-events stream parsed
// by hand (a line buffer: fields "id", "event", "data", comments ":", a blank line ends a message).
#include "m2mlat/net/client.hpp"

#include <fmt/format.h>
#include <httplib.h>

#include <algorithm>
#include <atomic>
#include <exception>
#include <regex>
#include <string_view>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/number.hpp"
#include "m2mlat/net/query.hpp"  // kMaxLimit: the agent's largest page

namespace m2mlat::net {

namespace {

constexpr std::size_t kMaxErrorBody = 4096;      // bytes of an error answer kept for the message
constexpr std::size_t kMaxStreamLine = 1 << 20;  // a longer SSE line is not an agent's

[[noreturn]] void fail(core::ErrorKind kind, const std::string& what, const std::string& message) {
  throw core::Error(kind, fmt::format("{}: {}", what, message));
}

// "http://host:port" from what the user gave ("http://host:port/" or "https://[::1]:8470"): the
// scheme and port are required, a path is not allowed (the API's paths are fixed).
std::string normalise_url(const std::string& url) {
  static const std::regex re(R"(^(https?)://(\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9._-]+):([0-9]{1,5})/?$)");
  std::smatch m;
  if (!std::regex_match(url, m, re))
    throw core::Error(core::ErrorKind::usage,
                      fmt::format("agent URL '{}': expected http://HOST:PORT or https://HOST:PORT", url));
  int port = 0;
  if (!core::parse_integer(m[3].str(), port) || port < 1 || port > 65535)
    throw core::Error(core::ErrorKind::usage, fmt::format("agent URL '{}': port out of range", url));
  return fmt::format("{}://{}:{}", m[1].str(), m[2].str(), port);
}

// The error message of an {"error":{"status":N,"message":"..."}} body, or the start of the body.
std::string error_message(const std::string& body) {
  try {
    const auto json = nlohmann::json::parse(body);
    if (json.is_object() && json.contains("error") && json["error"].is_object() &&
        json["error"].contains("message") && json["error"]["message"].is_string())
      return json["error"]["message"].get<std::string>();
  } catch (const nlohmann::json::exception&) {
  }
  std::string text = body.substr(0, 200);
  for (auto& c : text)
    if (c == '\n' || c == '\r') c = ' ';
  return text.empty() ? "(no body)" : text;
}

std::string http_error_text(httplib::Error err) {
  switch (err) {
    case httplib::Error::Connection: return "cannot connect";
    case httplib::Error::ConnectionTimeout: return "connection timed out";
    case httplib::Error::Read: return "read failed or timed out (connection dropped or agent frozen)";
    case httplib::Error::Write: return "write failed";
    case httplib::Error::Canceled: return "cancelled";
    case httplib::Error::SSLConnection: return "TLS handshake failed";
    case httplib::Error::SSLLoadingCerts: return "cannot load the CA certificates";
    case httplib::Error::SSLServerVerification: return "the agent's TLS certificate is not trusted";
    default: return httplib::to_string(err);
  }
}

// Checks a successful answer: status, API version header, content type.
void check_answer(const httplib::Result& res, const std::string& what, const char* content_type) {
  if (!res) fail(core::ErrorKind::io, what, http_error_text(res.error()));
  if (res->status < 200 || res->status > 299)
    fail(core::ErrorKind::io, what, fmt::format("HTTP {}: {}", res->status, error_message(res->body)));
  if (res->get_header_value(std::string(kApiHeader)) != "1")
    fail(core::ErrorKind::data, what,
         fmt::format("not an m2mlat agent of API version 1 (header {}: '{}')", kApiHeader,
                     res->get_header_value(std::string(kApiHeader))));
  if (content_type != nullptr) {
    const auto type = res->get_header_value("Content-Type");
    if (type.rfind(content_type, 0) != 0)
      fail(core::ErrorKind::data, what, fmt::format("Content-Type '{}', expected {}", type, content_type));
  }
}

nlohmann::json parse_json(const std::string& text, const std::string& where) {
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw core::Error(core::ErrorKind::data, fmt::format("{}: not JSON ({})", where, e.what()));
  }
}

void check_limit(std::size_t limit, const std::string& url) {
  if (limit < 1 || limit > kMaxLimit)
    throw core::Error(core::ErrorKind::usage,
                      fmt::format("{}: page limit {} out of 1..{}", url, limit, kMaxLimit));
}

// Calls `line` for each line of an NDJSON body (1-based numbers; blank lines are skipped).
template <class F>
void for_each_line(const std::string& body, F line) {
  std::size_t start = 0;
  long number = 0;
  while (start < body.size()) {
    auto end = body.find('\n', start);
    if (end == std::string::npos) end = body.size();
    ++number;
    std::string_view text(body.data() + start, end - start);
    if (!text.empty() && text.back() == '\r') text.remove_suffix(1);
    if (!text.empty()) line(text, number);
    start = end + 1;
  }
}

// Decodes one event with its session's node and role.
store::StoredEvent decode_event(const nlohmann::json& json, const std::string& where,
                                const SessionLookup& lookup) {
  if (!json.is_object() || !json.contains("session") || !json["session"].is_number_integer())
    throw core::Error(core::ErrorKind::data,
                      fmt::format("{}: field 'session': missing or not an integer", where));
  const auto id = json["session"].get<std::int64_t>();
  const store::Session* session = lookup ? lookup(id) : nullptr;
  if (session == nullptr)
    throw core::Error(core::ErrorKind::data,
                      fmt::format("{}: field 'session': unknown session {}", where, id));
  return event_from_json(json, where, session->node, session->role);
}

// One event line: the agent's own text without a JSON value (parse_canonical_event), anything else
// through the JSON library, whose decoder names what is wrong. `where` makes the error's place.
template <class Where>
store::StoredEvent decode_event_text(std::string_view text, const Where& where, const SessionLookup& lookup) {
  if (auto fast = parse_canonical_event(text)) {
    if (const store::Session* session = lookup ? lookup(fast->session_id) : nullptr) {
      fast->event.node = session->node;
      return std::move(*fast);
    }
  }
  const std::string place = where();
  return decode_event(parse_json(std::string(text), place), place, lookup);
}

}  // namespace

AgentClient::AgentClient(std::string base_url, ClientOptions options)
    : url_(normalise_url(base_url)), options_(std::move(options)) {
  try {
    http_ = std::make_unique<httplib::Client>(url_);
  } catch (const std::exception& e) {
    throw core::Error(core::ErrorKind::usage, fmt::format("agent URL '{}': {}", url_, e.what()));
  }
  if (!http_->is_valid())
    throw core::Error(core::ErrorKind::usage, fmt::format("agent URL '{}': not usable", url_));
  http_->set_connection_timeout(options_.connect_timeout);
  http_->set_read_timeout(options_.read_timeout);
  http_->set_write_timeout(options_.write_timeout);
  http_->set_keep_alive(true);
  http_->set_follow_location(false);
  http_->set_default_headers({{"Accept-Encoding", "identity"}});
  if (!options_.token.empty()) http_->set_bearer_token_auth(options_.token);
  if (!options_.ca_file.empty()) http_->set_ca_cert_path(options_.ca_file);
}

AgentClient::~AgentClient() = default;

void AgentClient::cancel() {
  cancelled_ = true;
  http_->stop();
}

std::string AgentClient::get_body(const std::string& path, const char* content_type) {
  const auto what = fmt::format("GET {}{}", url_, path);
  auto res = http_->Get(path);
  check_answer(res, what, content_type);
  return std::move(res->body);
}

template <class T, class Decode>
std::vector<T> AgentClient::ndjson(const std::string& path, Decode decode) {
  const auto body = get_body(path, "application/x-ndjson");
  std::vector<T> out;
  for_each_line(body, [&](std::string_view text, long number) {
    const auto where = fmt::format("{}{} line {}", url_, path, number);
    out.push_back(decode(parse_json(std::string(text), where), where));
  });
  return out;
}

Status AgentClient::status() {
  const auto path = std::string("/v1/status");
  const auto body = get_body(path, "application/json");
  return status_from_json(parse_json(body, url_ + path), url_ + path);
}

std::vector<store::Session> AgentClient::sessions() {
  const auto path = std::string("/v1/sessions");
  const auto where = url_ + path;
  const auto json = parse_json(get_body(path, "application/json"), where);
  if (!json.is_object() || !json.contains("sessions") || !json["sessions"].is_array())
    throw core::Error(core::ErrorKind::data,
                      fmt::format("{}: field 'sessions': missing or not an array", where));
  std::vector<store::Session> out;
  for (std::size_t i = 0; i < json["sessions"].size(); ++i)
    out.push_back(session_from_json(json["sessions"][i], fmt::format("{} sessions[{}]", where, i)));
  return out;
}

EventPage AgentClient::events_after(std::int64_t after, std::size_t limit, const SessionLookup& lookup) {
  return decode_events(fetch_events(after, limit), lookup);
}

RawEventPage AgentClient::fetch_events(std::int64_t after, std::size_t limit) {
  check_limit(limit, url_);
  const auto path = fmt::format("/v1/events?after={}&limit={}", after, limit);
  const auto what = fmt::format("GET {}{}", url_, path);
  auto res = http_->Get(path);
  check_answer(res, what, "application/x-ndjson");
  RawEventPage page;
  page.after = after;
  page.limit = limit;
  page.body = std::move(res->body);
  if (res->has_header(std::string(kLastSeqHeader))) {
    std::int64_t last = 0;
    if (!core::parse_integer(res->get_header_value(std::string(kLastSeqHeader)), last))
      throw core::Error(core::ErrorKind::data,
                        fmt::format("{}: header {}: '{}' is not a number", what, kLastSeqHeader,
                                    res->get_header_value(std::string(kLastSeqHeader))));
    page.last_seq = last;
  }
  return page;
}

std::size_t RawEventPage::lines() const {
  return static_cast<std::size_t>(std::count(body.begin(), body.end(), '\n'));
}

std::optional<std::int64_t> RawEventPage::last_event_seq() const {
  auto end = body.size();
  while (end > 0 && (body[end - 1] == '\n' || body[end - 1] == '\r')) --end;
  if (end == 0) return std::nullopt;
  const auto start = body.rfind('\n', end - 1);
  const auto first = start == std::string::npos ? 0 : start + 1;
  const auto json = nlohmann::json::parse(body.begin() + static_cast<std::ptrdiff_t>(first),
                                          body.begin() + static_cast<std::ptrdiff_t>(end), nullptr, false);
  if (!json.is_object()) return std::nullopt;
  const auto it = json.find("seq");
  if (it == json.end() || !it->is_number_integer()) return std::nullopt;
  return it->get<std::int64_t>();
}

EventPage AgentClient::decode_events(const RawEventPage& raw, const SessionLookup& lookup) const {
  const auto path = fmt::format("/v1/events?after={}&limit={}", raw.after, raw.limit);
  EventPage page;
  std::int64_t previous = raw.after;
  std::int64_t number = 0;
  const auto where = [&] { return fmt::format("{}{} line {}", url_, path, number); };
  for_each_line(raw.body, [&](std::string_view text, long line) {
    number = line;
    auto event = decode_event_text(text, where, lookup);
    if (event.seq <= previous)
      throw core::Error(core::ErrorKind::data,
                        fmt::format("{}: field 'seq': {} does not follow {}", where(), event.seq, previous));
    previous = event.seq;
    page.events.push_back(std::move(event));
  });
  if (page.events.size() > raw.limit)
    throw core::Error(core::ErrorKind::data, fmt::format("GET {}{}: {} events for a limit of {}", url_, path,
                                                         page.events.size(), raw.limit));
  page.last_seq = previous;
  if (raw.last_seq) {
    if (*raw.last_seq < previous)
      throw core::Error(core::ErrorKind::data,
                        fmt::format("GET {}{}: header {}: {} is before the page's last seq {}", url_, path,
                                    kLastSeqHeader, *raw.last_seq, previous));
    page.last_seq = *raw.last_seq;
  }
  return page;
}

std::vector<store::StoredClockSample> AgentClient::clock_samples_after(std::int64_t after,
                                                                       std::size_t limit) {
  check_limit(limit, url_);
  auto out =
      ndjson<store::StoredClockSample>(fmt::format("/v1/clock-samples?after={}&limit={}", after, limit),
                                       [](const nlohmann::json& json, const std::string& where) {
                                         return clock_sample_from_json(json, where);
                                       });
  std::int64_t previous = after;
  for (const auto& s : out) {
    if (s.id <= previous)
      throw core::Error(core::ErrorKind::data,
                        fmt::format("{}/v1/clock-samples: id {} does not follow {}", url_, s.id, previous));
    previous = s.id;
  }
  return out;
}

std::vector<store::StoredLoss> AgentClient::losses_after(std::int64_t after, std::size_t limit) {
  check_limit(limit, url_);
  auto out = ndjson<store::StoredLoss>(
      fmt::format("/v1/losses?after={}&limit={}", after, limit),
      [](const nlohmann::json& json, const std::string& where) { return loss_from_json(json, where); });
  std::int64_t previous = after;
  for (const auto& l : out) {
    if (l.id <= previous)
      throw core::Error(core::ErrorKind::data,
                        fmt::format("{}/v1/losses: id {} does not follow {}", url_, l.id, previous));
    previous = l.id;
  }
  return out;
}

std::vector<store::StoredMarker> AgentClient::markers_after(std::int64_t after, std::size_t limit) {
  check_limit(limit, url_);
  auto out = ndjson<store::StoredMarker>(
      fmt::format("/v1/markers?after={}&limit={}", after, limit),
      [](const nlohmann::json& json, const std::string& where) { return marker_from_json(json, where); });
  std::int64_t previous = after;
  for (const auto& m : out) {
    if (m.id <= previous)
      throw core::Error(core::ErrorKind::data,
                        fmt::format("{}/v1/markers: id {} does not follow {}", url_, m.id, previous));
    previous = m.id;
  }
  return out;
}

std::vector<store::StoredRateBlock> AgentClient::rate_blocks_after(std::int64_t after, std::size_t limit) {
  check_limit(limit, url_);
  auto out = ndjson<store::StoredRateBlock>(
      fmt::format("/v1/rate-blocks?after={}&limit={}", after, limit),
      [](const nlohmann::json& json, const std::string& where) { return rate_block_from_json(json, where); });
  std::int64_t previous = after;
  for (const auto& b : out) {
    if (b.id <= previous)
      throw core::Error(core::ErrorKind::data,
                        fmt::format("{}/v1/rate-blocks: id {} does not follow {}", url_, b.id, previous));
    previous = b.id;
  }
  return out;
}

store::Session AgentClient::start_session(const std::string& label, const std::string& scenario) {
  const std::string path = "/v1/sessions";
  const auto what = fmt::format("POST {}{}", url_, path);
  const nlohmann::json body{{"label", label}, {"scenario", scenario}};
  auto res = http_->Post(path, body.dump(), "application/json");
  check_answer(res, what, "application/json");
  const auto json = parse_json(res->body, what);
  if (!json.is_object() || !json.contains("session"))
    throw core::Error(core::ErrorKind::data, fmt::format("{}: field 'session': missing", what));
  return session_from_json(json["session"], what);
}

std::optional<store::Session> AgentClient::stop_session() {
  const std::string path = "/v1/sessions/current/stop";
  const auto what = fmt::format("POST {}{}", url_, path);
  auto res = http_->Post(path, std::string(), "application/json");
  if (res && res->status == 409) return std::nullopt;
  check_answer(res, what, "application/json");
  const auto json = parse_json(res->body, what);
  if (!json.is_object() || !json.contains("session"))
    throw core::Error(core::ErrorKind::data, fmt::format("{}: field 'session': missing", what));
  return session_from_json(json["session"], what);
}

void AgentClient::stream_events(std::int64_t after, const SessionLookup& lookup,
                                const StreamEventHandler& on_event, const StreamChunkHandler& on_chunk) {
  if (cancelled_) return;
  const auto path = fmt::format("/v1/events/stream?after={}", after);
  const auto what = fmt::format("GET {}{}", url_, path);

  const httplib::Response* head = nullptr;  // the response's status line and headers
  std::string error_body;                   // the body of an error answer
  bool stopped = false;                     // a handler said stop
  std::string line;                         // the incomplete line carried between chunks
  std::string id, type, data;               // the message being read
  std::int64_t previous = after;

  // One complete SSE message: an "event" with data is an event; other types are ignored.
  const auto dispatch = [&]() -> bool {
    bool keep_going = true;
    if (!data.empty() && (type.empty() || type == "event")) {
      std::int64_t seq = 0;
      if (!core::parse_integer(id, seq))
        throw core::Error(core::ErrorKind::data,
                          fmt::format("{}: event without a numeric id ('{}')", what, id));
      const auto where = fmt::format("{} id {}", what, seq);
      auto event = decode_event_text(
          data, [&] { return where; }, lookup);
      if (event.seq != seq || seq <= previous)
        throw core::Error(core::ErrorKind::data,
                          fmt::format("{}: field 'seq': {} (after {}) breaks the stream's order", where,
                                      event.seq, previous));
      previous = seq;
      keep_going = on_event(std::move(event));
    }
    id.clear();
    type.clear();
    data.clear();
    return keep_going;
  };
  // One line of the stream (without its end of line).
  const auto field = [&](std::string_view text) -> bool {
    if (text.empty()) return dispatch();
    if (text.front() == ':') return true;  // a comment: the keep-alive ping
    const auto colon = text.find(':');
    const auto name = text.substr(0, colon);
    std::string_view value = colon == std::string_view::npos ? std::string_view() : text.substr(colon + 1);
    if (!value.empty() && value.front() == ' ') value.remove_prefix(1);
    if (name == "id")
      id = value;
    else if (name == "event")
      type = value;
    else if (name == "data") {
      if (!data.empty()) data += '\n';
      data += value;
    }
    return true;
  };

  // Exceptions do not cross the HTTP library: a handler's is kept and thrown after the request.
  std::exception_ptr failure;
  bool not_agent = false;
  const auto on_response = [&](const httplib::Response& response) {
    head = &response;
    if (response.status == 200 && response.get_header_value(std::string(kApiHeader)) != "1") {
      not_agent = true;
      return false;
    }
    return !cancelled_;
  };
  const auto on_content = [&](const char* bytes, std::size_t size) -> bool {
    if (cancelled_) return false;
    if (head->status != 200) {
      error_body.append(bytes, std::min(size, kMaxErrorBody - std::min(kMaxErrorBody, error_body.size())));
      return true;
    }
    try {
      std::size_t start = 0;
      for (std::size_t i = 0; i < size; ++i) {
        if (bytes[i] != '\n') continue;
        line.append(bytes + start, i - start);
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (!field(line)) {
          stopped = true;
          return false;
        }
        line.clear();
        start = i + 1;
      }
      line.append(bytes + start, size - start);
      if (line.size() > kMaxStreamLine)
        throw core::Error(core::ErrorKind::data,
                          fmt::format("{}: a stream line longer than {} bytes", what, kMaxStreamLine));
      if (!on_chunk()) {
        stopped = true;
        return false;
      }
      return true;
    } catch (...) {
      failure = std::current_exception();
      return false;
    }
  };

  httplib::Headers headers{{"Accept", "text/event-stream"}};
  auto res = http_->Get(path, headers, on_response, on_content);
  if (failure) std::rethrow_exception(failure);
  if (not_agent)
    fail(core::ErrorKind::data, what,
         fmt::format("not an m2mlat agent of API version 1 (no {}: 1)", kApiHeader));
  if (stopped || cancelled_) return;
  if (!res) fail(core::ErrorKind::io, what, http_error_text(res.error()));
  if (res->status != 200)
    fail(core::ErrorKind::io, what, fmt::format("HTTP {}: {}", res->status, error_message(error_body)));
  fail(core::ErrorKind::io, what, "the agent ended the stream");
}

}  // namespace m2mlat::net
