// `m2mlat doctor`: checks this board for capture (GPIO chips and lines, permissions, kernel,
// real-time privileges, interrupt routing, clock synchronisation) and says what to fix. Exits 0 when
// nothing needs fixing, 1 otherwise; on a machine without GPIO it says so and checks the rest.
#include <fmt/format.h>

#include <memory>
#include <nlohmann/json.hpp>

#include "m2mlat/capture/gpio_device.hpp"
#include "m2mlat/cli/command.hpp"
#include "m2mlat/cli/output.hpp"
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

int run_doctor(bool json) {
  const auto devices = capture::linux_gpio_devices();
  const auto report = setup::run_doctor(setup::machine_inputs(*devices));
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
  sub.add_flag("--json", *json, "Print the findings as JSON");
  return [json] { return run_doctor(*json); };
}

}  // namespace m2mlat::cli
