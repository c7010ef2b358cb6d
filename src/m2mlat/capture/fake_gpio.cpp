// The twin's chips, lines and requests; an eventfd stands in for the request's descriptor, readable
// while the request's buffer holds events.
#include "m2mlat/capture/fake_gpio.hpp"

#include <sys/eventfd.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <deque>
#include <system_error>

#include "m2mlat/core/fd.hpp"

namespace m2mlat::capture {

namespace {
class FakeLineRequest;
}

struct FakeGpio::State {
  struct Line {
    std::string name;
    std::string consumer;
    std::uint64_t flags = 0;  // the requested flags while held
    std::uint32_t debounce_us = 0;
    std::uint64_t line_seqno = 0;
    FakeLineRequest* request = nullptr;  // the twin's request holding it, if any
    bool held_elsewhere = false;
  };
  struct Chip {
    ChipInfo info;
    std::vector<Line> lines;
    bool denied = false;
  };
  std::map<std::string, Chip> chips;  // by path
  std::vector<std::string> order;
  std::vector<OutputChange> outputs;
  std::uint64_t generated = 0;
  std::uint64_t dropped = 0;

  Chip& chip(const std::string& path) {
    const auto it = chips.find(path);
    if (it == chips.end()) throw std::system_error(ENOENT, std::generic_category(), path);
    if (it->second.denied) throw std::system_error(EACCES, std::generic_category(), path);
    return it->second;
  }
};

namespace {

class FakeLineRequest final : public LineRequest {
 public:
  FakeLineRequest(std::shared_ptr<FakeGpio::State> state, std::string path,
                  const gpio_v2_line_request& request)
      : state_(std::move(state)), path_(std::move(path)) {
    fd_.reset(::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC));
    if (!fd_) throw std::system_error(errno, std::generic_category(), "eventfd");
    offsets_.assign(request.offsets, request.offsets + request.num_lines);
    capacity_ = request.event_buffer_size == 0 ? 16 * request.num_lines
                                               : std::min(request.event_buffer_size, kMaxEventBufferSize);
  }
  ~FakeLineRequest() override {
    auto& chip = state_->chips.at(path_);
    for (auto offset : offsets_) {
      auto& line = chip.lines[offset];
      line.request = nullptr;
      line.consumer.clear();
      line.flags = 0;
      line.debounce_us = 0;
    }
  }

  int fd() const override { return fd_.get(); }

  std::size_t read_events(std::span<gpio_v2_line_event> out) override {
    std::size_t n = 0;
    while (n < out.size() && !buffer_.empty()) {
      out[n++] = buffer_.front();
      buffer_.pop_front();
    }
    if (buffer_.empty()) {
      std::uint64_t drain = 0;
      [[maybe_unused]] const auto r = ::read(fd_.get(), &drain, sizeof drain);
    }
    return n;
  }

  void set_values(std::uint64_t bits, std::uint64_t mask) override {
    for (std::size_t i = 0; i < offsets_.size(); ++i)
      if ((mask >> i) & 1u) state_->outputs.push_back({path_, offsets_[i], ((bits >> i) & 1u) != 0});
  }

  // The kernel's edge handler: stamp, number, buffer (dropping the oldest when full).
  int edge(std::uint32_t offset, bool physical_rising, std::uint64_t timestamp_ns) {
    auto& line = state_->chips.at(path_).lines[offset];
    const bool logical_rising =
        (line.flags & GPIO_V2_LINE_FLAG_ACTIVE_LOW) ? !physical_rising : physical_rising;
    const auto wanted = logical_rising ? GPIO_V2_LINE_FLAG_EDGE_RISING : GPIO_V2_LINE_FLAG_EDGE_FALLING;
    if ((line.flags & wanted) == 0) return 0;
    gpio_v2_line_event event{};
    event.timestamp_ns = timestamp_ns;
    event.id = logical_rising ? GPIO_V2_LINE_EVENT_RISING_EDGE : GPIO_V2_LINE_EVENT_FALLING_EDGE;
    event.offset = offset;
    event.seqno = ++seqno_;
    event.line_seqno = static_cast<std::uint32_t>(++line.line_seqno);
    if (buffer_.size() >= capacity_) {
      buffer_.pop_front();
      ++state_->dropped;
    }
    buffer_.push_back(event);
    ++state_->generated;
    const std::uint64_t one = 1;
    [[maybe_unused]] const auto w = ::write(fd_.get(), &one, sizeof one);
    return 1;
  }

 private:
  std::shared_ptr<FakeGpio::State> state_;
  std::string path_;
  std::vector<std::uint32_t> offsets_;
  std::size_t capacity_ = 16;
  std::deque<gpio_v2_line_event> buffer_;
  std::uint32_t seqno_ = 0;
  core::Fd fd_;  // eventfd
};

}  // namespace

FakeGpio::FakeGpio() : state_(std::make_shared<State>()) {}
FakeGpio::~FakeGpio() = default;

std::string FakeGpio::add_chip(const std::string& label, std::uint32_t lines,
                               std::vector<std::string> line_names) {
  const auto number = state_->order.size();
  State::Chip chip;
  chip.info.name = "gpiochip" + std::to_string(number);
  chip.info.path = "/dev/" + chip.info.name;
  chip.info.label = label;
  chip.info.lines = lines;
  chip.lines.resize(lines);
  for (std::size_t i = 0; i < lines && i < line_names.size(); ++i) chip.lines[i].name = line_names[i];
  const auto path = chip.info.path;
  state_->chips.emplace(path, std::move(chip));
  state_->order.push_back(path);
  return path;
}

void FakeGpio::deny_access(const std::string& path) { state_->chips.at(path).denied = true; }

void FakeGpio::hold_line(const std::string& path, std::uint32_t offset, const std::string& consumer) {
  auto& line = state_->chips.at(path).lines.at(offset);
  line.held_elsewhere = true;
  line.consumer = consumer;
  line.flags = GPIO_V2_LINE_FLAG_USED | GPIO_V2_LINE_FLAG_INPUT;
}

int FakeGpio::edge(const std::string& path, std::uint32_t offset, bool rising, std::uint64_t timestamp_ns) {
  auto& line = state_->chips.at(path).lines.at(offset);
  if (line.request == nullptr) return 0;
  return line.request->edge(offset, rising, timestamp_ns);
}

std::uint64_t FakeGpio::events_generated() const { return state_->generated; }
std::uint64_t FakeGpio::events_dropped() const { return state_->dropped; }
const std::vector<FakeGpio::OutputChange>& FakeGpio::output_changes() const { return state_->outputs; }

std::vector<std::string> FakeGpio::chip_paths() const { return state_->order; }

ChipInfo FakeGpio::chip_info(const std::string& path) const { return state_->chip(path).info; }

LineInfo FakeGpio::line_info(const std::string& path, std::uint32_t offset) const {
  auto& chip = state_->chip(path);
  if (offset >= chip.lines.size())
    throw std::system_error(EINVAL, std::generic_category(), path + ": line info");
  const auto& line = chip.lines[offset];
  LineInfo info;
  info.offset = offset;
  info.name = line.name;
  info.consumer = line.consumer;
  info.flags = line.flags;
  info.debounce_us = line.debounce_us;
  return info;
}

std::unique_ptr<LineRequest> FakeGpio::request_lines(const std::string& path, gpio_v2_line_request& request) {
  auto& chip = state_->chip(path);
  if (request.num_lines == 0 || request.num_lines > GPIO_V2_LINES_MAX)
    throw std::system_error(EINVAL, std::generic_category(), path + ": line request");
  for (std::uint32_t i = 0; i < request.num_lines; ++i) {
    const auto offset = request.offsets[i];
    if (offset >= chip.lines.size())
      throw std::system_error(EINVAL, std::generic_category(), path + ": line request");
    if (chip.lines[offset].held_elsewhere || chip.lines[offset].request != nullptr)
      throw std::system_error(EBUSY, std::generic_category(), path + ": line request");
  }
  auto granted = std::make_unique<FakeLineRequest>(state_, path, request);
  for (std::uint32_t i = 0; i < request.num_lines; ++i) {
    auto& line = chip.lines[request.offsets[i]];
    line.request = granted.get();
    line.consumer = std::string(request.consumer, strnlen(request.consumer, sizeof request.consumer));
    line.flags = request.config.flags | GPIO_V2_LINE_FLAG_USED;
    for (std::uint32_t a = 0; a < request.config.num_attrs; ++a) {
      const auto& attr = request.config.attrs[a];
      if (((attr.mask >> i) & 1u) == 0) continue;
      if (attr.attr.id == GPIO_V2_LINE_ATTR_ID_FLAGS) line.flags = attr.attr.flags | GPIO_V2_LINE_FLAG_USED;
      if (attr.attr.id == GPIO_V2_LINE_ATTR_ID_DEBOUNCE) line.debounce_us = attr.attr.debounce_period_us;
    }
  }
  request.fd = granted->fd();
  return granted;
}

}  // namespace m2mlat::capture
