// Chip and line lookup over GpioDevices, and the errno -> advice table.
#include "m2mlat/capture/chip_lookup.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <vector>

#include "m2mlat/core/number.hpp"

namespace m2mlat::capture {

namespace {

std::string basename(const std::string& path) {
  const auto slash = path.rfind('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

bool parse_offset(std::string_view text, std::uint32_t& offset) { return core::parse_integer(text, offset); }

}  // namespace

std::string permission_advice(const std::string& path) {
  return fmt::format(
      "permission denied opening {}: add your user to the group that owns the GPIO chips (a udev rule "
      "`SUBSYSTEM==\"gpio\", KERNEL==\"gpiochip*\", GROUP=\"gpio\", MODE=\"0660\"`, then `usermod -aG gpio "
      "$USER` "
      "and log in again; see docs/hardware.md), or run as root",
      path);
}

core::Error explain_gpio_error(const std::system_error& error, const GpioDevices& devices,
                               const ChipInfo& chip, std::int64_t offset) {
  const int err = error.code().value();
  const std::string where = offset >= 0 ? fmt::format("line {} of {} ({})", offset, chip.name, chip.label)
                                        : fmt::format("{} ({})", chip.path, chip.label);
  switch (err) {
    case ENOENT:
    case ENODEV:
      return {core::ErrorKind::no_input,
              fmt::format("{}: no such GPIO chip (`m2mlat doctor` lists the chips there are)", chip.path)};
    case EACCES:
    case EPERM: return {core::ErrorKind::io, permission_advice(chip.path)};
    case EBUSY: {
      std::string consumer = "another consumer";
      if (offset >= 0) {
        try {
          const auto info = devices.line_info(chip.path, static_cast<std::uint32_t>(offset));
          if (!info.consumer.empty()) consumer = "'" + info.consumer + "'";
        } catch (const std::system_error&) {  // the line's holder stays unnamed
        }
      }
      return {
          core::ErrorKind::io,
          fmt::format("{} is already in use by {}: stop the program holding it (gpiomon, a kernel driver or "
                      "overlay, another m2mlat) or choose another line; `m2mlat doctor` shows who holds "
                      "which line",
                      where, consumer)};
    }
    case EINVAL:
    case EOPNOTSUPP:
      return {
          core::ErrorKind::usage,
          fmt::format("{}: the kernel refused the line settings ({}): realtime event timestamps need Linux "
                      "5.11, --clock hte a hardware timestamp engine; or the chip cannot set that bias "
                      "or debounce",
                      where, error.code().message())};
    default: return {core::ErrorKind::io, fmt::format("{}: {}", where, error.what())};
  }
}

ChipInfo find_chip(const GpioDevices& devices, std::string_view spec) {
  if (spec.empty()) throw core::Error(core::ErrorKind::usage, "empty chip: give a path, name or label");
  const std::string wanted(spec);
  const auto open = [&](const std::string& path) {
    try {
      return devices.chip_info(path);
    } catch (const std::system_error& e) {
      ChipInfo chip;
      chip.path = path;
      chip.name = basename(path);
      throw explain_gpio_error(e, devices, chip);
    }
  };
  if (wanted.front() == '/') return open(wanted);

  const auto paths = devices.chip_paths();
  for (const auto& path : paths)
    if (basename(path) == wanted) return open(path);
  std::vector<std::string> seen, denied;
  for (const auto& path : paths) {
    try {
      const auto info = devices.chip_info(path);
      if (info.label == wanted) return info;
      seen.push_back(fmt::format("{} ({})", info.name, info.label));
    } catch (const std::system_error& e) {
      denied.push_back(path);
      if (e.code().value() != EACCES && e.code().value() != EPERM) continue;
    }
  }
  if (paths.empty())
    throw core::Error(
        core::ErrorKind::no_input,
        fmt::format("no GPIO chip '{}': this machine has no GPIO chips at all (no /dev/gpiochip*)", wanted));
  std::string message = fmt::format("no GPIO chip with the path, name or label '{}'", wanted);
  if (!seen.empty()) message += fmt::format("; the chips are: {}", fmt::join(seen, ", "));
  if (!denied.empty())
    message += fmt::format("; could not open {} to read its label: {}", fmt::join(denied, ", "),
                           permission_advice(denied.front()));
  throw core::Error(core::ErrorKind::no_input, message);
}

std::uint32_t find_line(const GpioDevices& devices, const ChipInfo& chip, std::string_view spec) {
  std::uint32_t offset = 0;
  if (parse_offset(spec, offset)) {
    if (offset >= chip.lines)
      throw core::Error(core::ErrorKind::no_input,
                        fmt::format("{} ({}) has lines 0..{}: there is no line {}", chip.name, chip.label,
                                    chip.lines - 1, offset));
    return offset;
  }
  for (std::uint32_t i = 0; i < chip.lines; ++i) {
    try {
      if (devices.line_info(chip.path, i).name == spec) return i;
    } catch (const std::system_error& e) {
      throw explain_gpio_error(e, devices, chip, i);
    }
  }
  throw core::Error(
      core::ErrorKind::no_input,
      fmt::format("{} ({}) has no line named '{}' (`m2mlat doctor` lists the line names; an offset "
                  "works too)",
                  chip.name, chip.label, spec));
}

}  // namespace m2mlat::capture
