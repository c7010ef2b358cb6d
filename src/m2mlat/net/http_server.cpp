// The guarded server: httplib::Server with its connection loop replaced (process_and_close_socket),
// its task queue replaced by the connection budget, SO_REUSEPORT left off, and TLS through OpenSSL.
#include "m2mlat/net/http_server.hpp"

#include <fmt/format.h>
#include <httplib.h>
#include <openssl/pem.h>
#include <openssl/ssl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <mutex>
#include <thread>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/fd.hpp"
#include "m2mlat/net/connection_budget.hpp"
#include "m2mlat/net/connection_stream.hpp"
#include "m2mlat/net/secret_file.hpp"
#include "m2mlat/net/wire.hpp"

namespace m2mlat::net {

namespace {

using Steady = std::chrono::steady_clock;

std::string_view reason_phrase(int status) {
  switch (status) {
    case 400: return "bad request";
    case 401: return "a bearer token is required";
    case 404: return "no such path";
    case 405: return "method not allowed";
    case 408: return "request timeout";
    case 409: return "conflict";
    case 413: return "request body too large";
    case 414: return "request line too long";
    case 415: return "unsupported media type";
    case 431: return "too many or too large header fields";
    case 500: return "internal error";
    case 503: return "service unavailable";
    default: return status >= 500 ? "server error" : "client error";
  }
}

struct SslContextFree {
  void operator()(SSL_CTX* ctx) const { SSL_CTX_free(ctx); }
};
struct SslFree {
  void operator()(SSL* ssl) const { SSL_free(ssl); }
};
using SslContext = std::unique_ptr<SSL_CTX, SslContextFree>;

// Never asks for a passphrase on the terminal: an encrypted key simply does not load.
int no_passphrase(char*, int, int, void*) { return 0; }

SslContext load_tls(const std::string& cert, const std::string& key) {
  const auto refuse = [&](std::string_view why) {
    return core::Error(core::ErrorKind::usage,
                       fmt::format("--tls-cert {} / --tls-key {}: {}", cert, key, why));
  };
  SslContext ctx(SSL_CTX_new(TLS_server_method()));
  if (!ctx) throw refuse("cannot make a TLS context");
  SSL_CTX_set_min_proto_version(ctx.get(), TLS1_2_VERSION);
  SSL_CTX_set_options(ctx.get(), SSL_OP_NO_COMPRESSION | SSL_OP_NO_RENEGOTIATION);
  if (SSL_CTX_use_certificate_chain_file(ctx.get(), cert.c_str()) != 1)
    throw refuse("cannot load the certificate");
  auto pem = read_secret_file(key, "--tls-key");
  EVP_PKEY* pkey = nullptr;
  if (BIO* bio = BIO_new_mem_buf(pem.data(), static_cast<int>(pem.size()))) {
    pkey = PEM_read_bio_PrivateKey(bio, nullptr, no_passphrase, nullptr);
    BIO_free(bio);
  }
  OPENSSL_cleanse(pem.data(), pem.size());
  const bool ok = pkey != nullptr && SSL_CTX_use_PrivateKey(ctx.get(), pkey) == 1 &&
                  SSL_CTX_check_private_key(ctx.get()) == 1;
  EVP_PKEY_free(pkey);
  if (!ok) throw refuse("cannot load the certificate and key (not PEM, encrypted, or not a pair)");
  return ctx;
}

// httplib's server with the connections handled here (see the header).
class GuardedServer final : public httplib::Server {
 public:
  GuardedServer(const HttpServerOptions& options, SSL_CTX* tls)
      : options_(options), tls_(tls), table_(options.max_connections) {}

  ConnectionTable& table() { return table_; }
  // httplib listens with a backlog of 5; a burst of connections would have their SYNs dropped and
  // wait a second to retry. Linux takes a second listen() as a new backlog.
  void widen_backlog() { ::listen(svr_sock_, SOMAXCONN); }

 private:
  bool process_and_close_socket(socket_t sock) override {
    const core::Fd owned(sock);  // closed on every way out, after the shutdown below
    if (refusing_connection()) {
      refuse(sock);
      return false;
    }
    const auto id = table_.add(sock);
    const bool ok = set_non_blocking(sock) && serve(sock, id);
    table_.remove(id);
    ::shutdown(sock, SHUT_RDWR);
    return ok;
  }

  // Every place is taken by a connection being served: say so at once and shut the connection (its
  // descriptor is closed by the caller).
  void refuse(socket_t sock) {
    table_.count_refused();
    if (tls_ == nullptr) {
      const auto body =
          error_body(503, fmt::format("{} has {} connections open, all of them serving; try again",
                                      options_.what, options_.max_connections));
      const auto response = fmt::format(
          "HTTP/1.1 503 Service Unavailable\r\nContent-Type: application/json\r\nContent-Length: {}\r\n"
          "Retry-After: 1\r\nConnection: close\r\n\r\n{}",
          body.size(), body);
      [[maybe_unused]] const auto n =
          ::send(sock, response.data(), response.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
    }
    ::shutdown(sock, SHUT_RDWR);
  }

  // The keep-alive loop: wait for a request (idle timeout), read and serve it (request deadline).
  bool serve(socket_t sock, ConnectionTable::Id id) {
    std::unique_ptr<SSL, SslFree> ssl;
    if (tls_ != nullptr) {
      ssl.reset(SSL_new(tls_));
      if (!ssl || SSL_set_fd(ssl.get(), sock) != 1) return false;
      const auto deadline = Steady::now() + options_.request_timeout;
      if (!tls_accept(ssl.get(), sock, deadline)) {
        if (Steady::now() >= deadline) table_.count_timed_out();
        return false;
      }
    }
    ConnectionStream stream(sock, ssl.get(), options_.write_timeout);
    bool ok = false;
    for (auto left = std::max<std::size_t>(options_.keep_alive_max, 1); left > 0; --left) {
      if (!table_.waiting(id)) break;
      const auto idle_until = Steady::now() + options_.idle_timeout;
      if (!stream.wait_for_request(idle_until)) {
        if (Steady::now() >= idle_until) table_.count_idle();
        break;
      }
      stream.set_read_deadline(Steady::now() + options_.request_timeout);
      stream.set_read_limit(options_.max_head);
      bool closed = false;
      ok = process_request(stream, left == 1, closed, [&](httplib::Request&) {
        table_.serving(id);        // a complete head: no longer evicted
        stream.set_read_limit(0);  // the body is httplib's to bound (max_body)
      });
      if (stream.timed_out()) {
        table_.count_timed_out();
        break;
      }
      if (!ok || closed) break;
    }
    if (ssl && ok) SSL_shutdown(ssl.get());  // one try at close_notify; the socket does not block
    return ok;
  }

  const HttpServerOptions& options_;
  SSL_CTX* tls_;
  ConnectionTable table_;
};

}  // namespace

class HttpServer::StreamSlot {
 public:
  explicit StreamSlot(HttpServer::Impl& owner);
  ~StreamSlot();
  StreamSlot(const StreamSlot&) = delete;
  StreamSlot& operator=(const StreamSlot&) = delete;

 private:
  HttpServer::Impl& owner_;
};

struct HttpServer::Impl {
  HttpServerOptions options;
  SslContext tls;
  std::unique_ptr<GuardedServer> server;
  std::thread thread;
  std::atomic<bool> listen_returned{false};
  int port = 0;
  std::mutex streams_mutex;
  std::size_t streams = 0;
};

HttpServer::StreamSlot::StreamSlot(HttpServer::Impl& owner) : owner_(owner) {}

HttpServer::StreamSlot::~StreamSlot() {
  std::lock_guard lock(owner_.streams_mutex);
  --owner_.streams;
}

HttpServer::HttpServer(HttpServerOptions options) : impl_(std::make_unique<Impl>()) {
  auto& i = *impl_;
  i.options = std::move(options);
  auto& o = i.options;
  if (o.host.size() >= 2 && o.host.front() == '[' && o.host.back() == ']')
    o.host = o.host.substr(1, o.host.size() - 2);
  if (o.port < 0 || o.port > 65535)
    throw core::Error(core::ErrorKind::usage, fmt::format("port {}: use 0 to 65535", o.port));
  if (o.tls_cert.empty() != o.tls_key.empty())
    throw core::Error(core::ErrorKind::usage, "TLS needs both --tls-cert and --tls-key");
  if (!o.tls_cert.empty()) i.tls = load_tls(o.tls_cert, o.tls_key);
  i.server = std::make_unique<GuardedServer>(o, i.tls.get());
  auto& s = *i.server;
  auto& table = s.table();
  s.new_task_queue = [&table] { return new BudgetQueue(table); };
  s.set_payload_max_length(o.max_body);
  // SO_REUSEADDR only: see the header on SO_REUSEPORT.
  s.set_socket_options([](socket_t sock) {
    int yes = 1;
    ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  // Errors httplib makes itself (400 malformed request, 413, 414, ...) get the JSON error body.
  s.set_error_handler(
      httplib::Server::HandlerWithResponse([](const httplib::Request&, httplib::Response& res) {
        if (!res.body.empty()) return httplib::Server::HandlerResponse::Unhandled;
        res.set_content(error_body(res.status, reason_phrase(res.status)), "application/json");
        return httplib::Server::HandlerResponse::Handled;
      }));
  s.set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr) {
    res.status = 500;
    res.set_content(error_body(500, "internal error"), "application/json");
  });
}

HttpServer::~HttpServer() { stop(); }

httplib::Server& HttpServer::routes() { return *impl_->server; }

void HttpServer::start() {
  auto& i = *impl_;
  auto& s = *i.server;
  if (i.options.port == 0) {
    i.port = s.bind_to_any_port(i.options.host);
    if (i.port < 0) i.port = 0;
  } else if (s.bind_to_port(i.options.host, i.options.port)) {
    i.port = i.options.port;
  }
  if (i.port == 0)
    throw core::Error(
        core::ErrorKind::io,
        fmt::format("{} cannot listen on {} port {} (in use, or not an address of this machine)",
                    i.options.what, i.options.host, i.options.port));
  s.widen_backlog();
  i.thread = std::thread([&i] {
    i.server->listen_after_bind();
    i.listen_returned = true;
  });
  // httplib's stop() does nothing until the listening loop runs: wait for it, so that a stop right
  // after start cannot be lost (and leave join() waiting forever).
  while (!s.is_running() && !i.listen_returned) std::this_thread::sleep_for(std::chrono::milliseconds(1));
}

void HttpServer::stop() {
  auto& i = *impl_;
  if (!i.thread.joinable()) return;
  i.server->stop();  // the listening loop ends, and the budget's shutdown() closes the connections
  i.thread.join();
}

int HttpServer::port() const { return impl_->port; }

bool HttpServer::tls() const { return impl_->tls != nullptr; }

std::string HttpServer::address() const {
  const auto& host = impl_->options.host;
  if (host.find(':') != std::string::npos) return fmt::format("[{}]:{}", host, impl_->port);
  return fmt::format("{}:{}", host, impl_->port);
}

ConnectionCounts HttpServer::counts() const { return impl_->server->table().counts(); }

std::shared_ptr<HttpServer::StreamSlot> HttpServer::stream_slot() {
  auto& i = *impl_;
  std::lock_guard lock(i.streams_mutex);
  if (i.streams >= i.options.max_streams) return nullptr;
  ++i.streams;
  return std::make_shared<StreamSlot>(i);
}

std::size_t HttpServer::max_streams() const { return impl_->options.max_streams; }

}  // namespace m2mlat::net
