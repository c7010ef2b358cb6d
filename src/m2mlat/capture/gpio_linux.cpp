// The real uAPI v2: open(2) the chip, ioctl(2) for chip and line info and for a line request, and
// read(2) of gpio_v2_line_event records from the request's descriptor.
#include <fcntl.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <system_error>
#include <utility>

#include "m2mlat/capture/gpio_device.hpp"
#include "m2mlat/core/fd.hpp"
#include "m2mlat/core/number.hpp"

namespace m2mlat::capture {

namespace {

[[noreturn]] void fail(const std::string& what) {
  throw std::system_error(errno, std::generic_category(), what);
}

core::Fd open_chip(const std::string& path) {
  core::Fd chip(::open(path.c_str(), O_RDWR | O_CLOEXEC));
  if (!chip) fail(path);
  return chip;
}

std::string text(const char* field, std::size_t size) { return std::string(field, strnlen(field, size)); }

class LinuxLineRequest final : public LineRequest {
 public:
  explicit LinuxLineRequest(core::Fd fd) : fd_(std::move(fd)) {
    const int flags = ::fcntl(fd_.get(), F_GETFL);
    if (flags < 0 || ::fcntl(fd_.get(), F_SETFL, flags | O_NONBLOCK) < 0) fail("line request: fcntl");
  }
  int fd() const override { return fd_.get(); }

  std::size_t read_events(std::span<gpio_v2_line_event> out) override {
    if (out.empty()) return 0;
    for (;;) {
      const ssize_t n = ::read(fd_.get(), out.data(), out.size_bytes());
      if (n >= 0) return static_cast<std::size_t>(n) / sizeof(gpio_v2_line_event);
      if (errno == EINTR) continue;
      if (errno == EAGAIN) return 0;
      fail("line request: read");
    }
  }

  void set_values(std::uint64_t bits, std::uint64_t mask) override {
    gpio_v2_line_values values{};
    values.bits = bits;
    values.mask = mask;
    if (::ioctl(fd_.get(), GPIO_V2_LINE_SET_VALUES_IOCTL, &values) < 0) fail("line request: set values");
  }

 private:
  core::Fd fd_;
};

class LinuxGpioDevices final : public GpioDevices {
 public:
  explicit LinuxGpioDevices(std::string dev_dir) : dev_dir_(std::move(dev_dir)) {}

  std::vector<std::string> chip_paths() const override {
    std::vector<std::pair<long, std::string>> found;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(dev_dir_, ec)) {
      const auto name = entry.path().filename().string();
      long number = 0;
      if (!name.starts_with("gpiochip") || !core::parse_integer(std::string_view(name).substr(8), number) ||
          number < 0)
        continue;
      found.emplace_back(number, entry.path().string());
    }
    std::sort(found.begin(), found.end());
    std::vector<std::string> paths;
    for (auto& f : found) paths.push_back(std::move(f.second));
    return paths;
  }

  ChipInfo chip_info(const std::string& path) const override {
    const auto chip = open_chip(path);
    gpiochip_info info{};
    if (::ioctl(chip.get(), GPIO_GET_CHIPINFO_IOCTL, &info) < 0) fail(path + ": chip info");
    return {path, text(info.name, sizeof info.name), text(info.label, sizeof info.label), info.lines};
  }

  LineInfo line_info(const std::string& path, std::uint32_t offset) const override {
    const auto chip = open_chip(path);
    gpio_v2_line_info info{};
    info.offset = offset;
    if (::ioctl(chip.get(), GPIO_V2_GET_LINEINFO_IOCTL, &info) < 0) fail(path + ": line info");
    LineInfo out;
    out.offset = info.offset;
    out.name = text(info.name, sizeof info.name);
    out.consumer = text(info.consumer, sizeof info.consumer);
    out.flags = info.flags;
    for (std::uint32_t i = 0; i < info.num_attrs && i < GPIO_V2_LINE_NUM_ATTRS_MAX; ++i)
      if (info.attrs[i].id == GPIO_V2_LINE_ATTR_ID_DEBOUNCE)
        out.debounce_us = info.attrs[i].debounce_period_us;
    return out;
  }

  std::unique_ptr<LineRequest> request_lines(const std::string& path,
                                             gpio_v2_line_request& request) override {
    const auto chip = open_chip(path);
    if (::ioctl(chip.get(), GPIO_V2_GET_LINE_IOCTL, &request) < 0) fail(path + ": line request");
    core::Fd line(request.fd);  // ours from here, whatever happens next
    return std::make_unique<LinuxLineRequest>(std::move(line));
  }

 private:
  std::string dev_dir_;
};

}  // namespace

std::unique_ptr<GpioDevices> linux_gpio_devices(const std::string& dev_dir) {
  return std::make_unique<LinuxGpioDevices>(dev_dir);
}

}  // namespace m2mlat::capture
