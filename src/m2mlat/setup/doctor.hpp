// `m2mlat doctor`'s checks: what a board needs to capture well, and what to fix when it does not.
// A board check, beside the plans that prepare the board (`m2mlat setup`): it uses capture's GPIO
// devices and rt's privileges, and reads the kernel clock with sync's one adjtimex reader.
// GPIO chips and their lines (with consumers) and whether this user may open them; whether the
// kernel can stamp events with CLOCK_REALTIME; real-time privileges (SCHED_FIFO, mlock); where the
// interrupts of lines m2mlat holds are routed, and whether they may be moved; and the kernel's
// clock-synchronisation state (adjtimex), without which two boards' timestamps cannot be compared.
// Everything it reads is passed in, so that the checks run in tests on made-up machines.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "m2mlat/capture/gpio_device.hpp"
#include "m2mlat/rt/scheduling.hpp"
#include "m2mlat/sync/kernel_clock.hpp"

namespace m2mlat::setup {

enum class Status { ok, warn, fail };  // fail: something needs fixing (doctor exits 1)
std::string_view to_string(Status status);

struct Finding {
  std::string check;  // "gpio", "permissions", "kernel", "realtime", "irq", "clock"
  Status status = Status::ok;
  std::string detail;  // what was found
  std::string fix;     // what to do (empty when nothing)
};

struct ChipReport {
  capture::ChipInfo chip;
  std::string error;                     // why it could not be opened (empty if it could)
  std::vector<capture::LineInfo> lines;  // every line, when it could be opened
};

struct DoctorInputs {
  const capture::GpioDevices* devices = nullptr;
  std::string kernel_release;  // uname -r
  rt::Privileges privileges;
  sync::KernelClockState clock;  // the kernel's clock discipline (adjtimex)
  std::string interrupts_text;   // /proc/interrupts
  std::function<std::optional<std::string>(int irq)> irq_affinity;
  bool irq_writable = false;  // may this process write /proc/irq/*/smp_affinity_list
};
// The inputs of this machine.
DoctorInputs machine_inputs(const capture::GpioDevices& devices);

struct DoctorReport {
  std::vector<ChipReport> chips;
  std::vector<Finding> findings;
  bool needs_fixing() const;
};

DoctorReport run_doctor(const DoctorInputs& inputs);

// "6.1.0-56-amd64" -> {6, 1}; false if it does not start with two numbers.
bool parse_kernel_version(std::string_view release, int& major, int& minor);

}  // namespace m2mlat::setup
