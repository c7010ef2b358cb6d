// A mutex-protected queue with an eventfd to wake the recorder's poll(2) and a condition variable
// to wake the requester.
#include "m2mlat/capture/session_control.hpp"

#include <fmt/format.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "m2mlat/core/error.hpp"

namespace m2mlat::capture {

SessionControl::SessionControl() : fd_(::eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK)) {
  if (!fd_) throw core::Error(core::ErrorKind::io, fmt::format("eventfd: {}", std::strerror(errno)));
}

SessionControl::~SessionControl() = default;

std::uint64_t SessionControl::enqueue(std::optional<store::Session> begin) {
  std::lock_guard lock(mutex_);
  const auto ticket = next_ticket_++;
  pending_.push_back({ticket, std::move(begin)});
  const std::uint64_t one = 1;
  [[maybe_unused]] const auto written = ::write(fd_.get(), &one, sizeof one);  // a full counter is still readable
  return ticket;
}

std::uint64_t SessionControl::request_begin(store::Session next) { return enqueue(std::move(next)); }

std::uint64_t SessionControl::request_stop() { return enqueue(std::nullopt); }

std::optional<SessionControl::Outcome> SessionControl::wait(std::uint64_t ticket, core::Duration timeout) {
  std::unique_lock lock(mutex_);
  done_.wait_for(lock, timeout, [&] { return outcomes_.count(ticket) > 0 || closed_; });
  const auto it = outcomes_.find(ticket);
  if (it == outcomes_.end()) return std::nullopt;
  auto outcome = std::move(it->second);
  outcomes_.erase(it);
  return outcome;
}

std::optional<SessionControl::Request> SessionControl::next() {
  std::lock_guard lock(mutex_);
  if (pending_.empty()) {
    std::uint64_t count = 0;
    [[maybe_unused]] const auto got = ::read(fd_.get(), &count, sizeof count);  // drain: nothing pending
    return std::nullopt;
  }
  auto request = std::move(pending_.front());
  pending_.pop_front();
  return request;
}

void SessionControl::complete(std::uint64_t ticket, Outcome outcome) {
  {
    std::lock_guard lock(mutex_);
    outcomes_[ticket] = std::move(outcome);
  }
  done_.notify_all();
}

void SessionControl::close() {
  {
    std::lock_guard lock(mutex_);
    closed_ = true;
    pending_.clear();
  }
  done_.notify_all();
}

}  // namespace m2mlat::capture
