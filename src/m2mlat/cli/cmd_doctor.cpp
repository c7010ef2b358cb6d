// `m2mlat doctor`: checks this board for capture (GPIO chips and lines, permissions, kernel,
// real-time privileges, interrupt routing, clock synchronisation) and says what to fix. Exits 0 when
// nothing needs fixing, 1 otherwise; on a machine without GPIO it says so and checks the rest.
#include <fmt/format.h>

#include <memory>
#include <nlohmann/json.hpp>

#include "m2mlat/capture/gpio_device.hpp"
#include "m2mlat/capture/i2c_bus.hpp"
#include "m2mlat/capture/mpu6050.hpp"
#include "m2mlat/cli/command.hpp"
#include "m2mlat/cli/output.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/core/printable.hpp"
#include "m2mlat/setup/doctor.hpp"

namespace m2mlat::cli {

namespace {

std::string line_flags(const capture::LineInfo& line) {
  std::string out = (line.flags & GPIO_V2_LINE_FLAG_OUTPUT) ? "output" : "input";
  if (line.flags & GPIO_V2_LINE_FLAG_ACTIVE_LOW) out += " active-low";
  if (line.flags & GPIO_V2_LINE_FLAG_EDGE_RISING) out += " rising";
  if (line.flags & GPIO_V2_LINE_FLAG_EDGE_FALLING) out += " falling";
  if (line.flags & GPIO_V2_LINE_FLAG_BIAS_PULL_UP) out += " pull-up";
  if (line.flags & GPIO_V2_LINE_FLAG_BIAS_PULL_DOWN) out += " pull-down";
  if (line.debounce_us > 0) out += fmt::format(" debounce={}us", line.debounce_us);
  return out;
}

// The configured gyroscope: the device opens, a chip answers at the address, and it is an MPU-6050.
// Nothing is written to it.
setup::Finding check_gyro(const std::string& device, const std::string& address) {
  try {
    capture::I2cBus bus(device, capture::parse_i2c_address("--gyro-address", address));
    capture::Mpu6050 chip(bus);
    return {"gyro", setup::Status::ok, fmt::format("MPU-6050 at {} (WHO_AM_I 0x68)", bus.describe()), ""};
  } catch (const core::Error& e) {
    if (e.kind() == core::ErrorKind::usage) throw;
    return {"gyro", setup::Status::fail, e.what(),
            "wire and enable the gyroscope as docs/hardware.md says; `i2cdetect -y N` lists the addresses "
            "that answer"};
  }
}

int run_doctor(bool json, const std::string& gyro_device, const std::string& gyro_address) {
  const auto devices = capture::linux_gpio_devices();
  auto report = setup::run_doctor(setup::machine_inputs(*devices));
  if (!gyro_device.empty()) report.findings.push_back(check_gyro(gyro_device, gyro_address));
  if (json) {
    nlohmann::json j{{"needs_fixing", report.needs_fixing()},
                     {"chips", nlohmann::json::array()},
                     {"findings", nlohmann::json::array()}};
    for (const auto& chip : report.chips) {
      nlohmann::json c{{"path", chip.chip.path},   {"name", chip.chip.name},
                       {"label", chip.chip.label}, {"lines", chip.chip.lines},
                       {"error", chip.error},      {"line_info", nlohmann::json::array()}};
      for (const auto& line : chip.lines)
        c["line_info"].push_back({{"offset", line.offset},
                                  {"name", line.name},
                                  {"consumer", line.consumer},
                                  {"used", line.used()},
                                  {"flags", line.flags},
                                  {"debounce_us", line.debounce_us}});
      j["chips"].push_back(c);
    }
    for (const auto& f : report.findings)
      j["findings"].push_back(
          {{"check", f.check}, {"status", setup::to_string(f.status)}, {"detail", f.detail}, {"fix", f.fix}});
    print_json(j);
  } else {
    for (const auto& chip : report.chips) {
      if (!chip.error.empty()) {
        fmt::print("{}: {}\n", core::printable(chip.chip.path), core::printable(chip.error));
        continue;
      }
      fmt::print("{} [{}] ({} lines)\n", core::printable(chip.chip.name), core::printable(chip.chip.label),
                 chip.chip.lines);
      for (const auto& line : chip.lines) {
        if (line.name.empty() && !line.used()) continue;  // unnamed and free: nothing to say
        fmt::print("  line {:>3}: {:<16} {}\n", line.offset,
                   line.name.empty() ? "unnamed" : core::printable(line.name),
                   line.used()
                       ? fmt::format("used by '{}' ({})", core::printable(line.consumer), line_flags(line))
                       : "free");
      }
    }
    if (!report.chips.empty()) fmt::print("\n");
    for (const auto& f : report.findings) {
      fmt::print("[{:<4}] {:<11} {}\n", setup::to_string(f.status), f.check, core::printable(f.detail));
      if (!f.fix.empty() && f.status != setup::Status::ok) fmt::print("       {:<11} fix: {}\n", "", f.fix);
    }
    fmt::print("\n{}\n",
               report.needs_fixing() ? "Something needs fixing (see FIX above)." : "Nothing needs fixing.");
  }
  return report.needs_fixing() ? 1 : 0;
}

}  // namespace

Runner attach_doctor(CLI::App& sub) {
  auto json = std::make_shared<bool>(false);
  auto gyro_device = std::make_shared<std::string>();
  auto gyro_address = std::make_shared<std::string>("0x68");
  sub.add_flag("--json", *json, "Print the findings as JSON");
  sub.add_option("--gyro-device", *gyro_device,
                 "Also check the MPU-6050 gyroscope on this I2C device (/dev/i2c-N)");
  sub.add_option("--gyro-address", *gyro_address, "The gyroscope's address")->capture_default_str();
  return [json, gyro_device, gyro_address] { return run_doctor(*json, *gyro_device, *gyro_address); };
}

}  // namespace m2mlat::cli
