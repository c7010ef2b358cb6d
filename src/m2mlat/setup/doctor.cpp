// The doctor's checks, each a Finding with its fix.
#include "m2mlat/setup/doctor.hpp"

#include <fmt/format.h>
#include <sys/utsname.h>
#include <unistd.h>

#include <charconv>
#include <fstream>
#include <sstream>
#include <system_error>

#include "m2mlat/capture/chip_lookup.hpp"
#include "m2mlat/rt/irq.hpp"

namespace m2mlat::setup {

std::string_view to_string(Status status) {
  switch (status) {
    case Status::ok: return "ok";
    case Status::warn: return "warn";
    case Status::fail: return "FIX";
  }
  return "?";
}

bool parse_kernel_version(std::string_view release, int& major, int& minor) {
  const auto* p = release.data();
  const auto* end = p + release.size();
  auto r1 = std::from_chars(p, end, major);
  if (r1.ec != std::errc{} || r1.ptr == end || *r1.ptr != '.') return false;
  auto r2 = std::from_chars(r1.ptr + 1, end, minor);
  return r2.ec == std::errc{};
}

DoctorInputs machine_inputs(const capture::GpioDevices& devices) {
  DoctorInputs in;
  in.devices = &devices;
  utsname u{};
  if (uname(&u) == 0) in.kernel_release = u.release;
  in.privileges = rt::current_privileges();
  in.clock = sync::read_kernel_clock();
  std::ifstream interrupts("/proc/interrupts");
  std::ostringstream text;
  text << interrupts.rdbuf();
  in.interrupts_text = text.str();
  in.irq_affinity = [](int irq) { return rt::irq_affinity(irq); };
  in.irq_writable = ::geteuid() == 0;
  return in;
}

bool DoctorReport::needs_fixing() const {
  for (const auto& f : findings)
    if (f.status == Status::fail) return true;
  return false;
}

DoctorReport run_doctor(const DoctorInputs& in) {
  DoctorReport report;
  auto add = [&](std::string check, Status status, std::string detail, std::string fix = {}) {
    report.findings.push_back({std::move(check), status, std::move(detail), std::move(fix)});
  };

  // GPIO chips and lines.
  const auto paths = in.devices->chip_paths();
  if (paths.empty())
    add("gpio", Status::warn, "no GPIO chips (/dev/gpiochip*): this machine cannot capture GPIO edges",
        "on a board, check that the kernel has CONFIG_GPIO_CDEV; here the kmsg and sim sources still work");
  bool any_denied = false;
  for (const auto& path : paths) {
    ChipReport chip;
    chip.chip.path = path;
    try {
      chip.chip = in.devices->chip_info(path);
      for (std::uint32_t i = 0; i < chip.chip.lines; ++i)
        chip.lines.push_back(in.devices->line_info(path, i));
    } catch (const std::system_error& e) {
      chip.error = capture::explain_gpio_error(e, *in.devices, chip.chip).what();
      const int err = e.code().value();
      if (err == EACCES || err == EPERM) any_denied = true;
    }
    report.chips.push_back(std::move(chip));
  }
  if (!paths.empty()) {
    if (any_denied)
      add("permissions", Status::fail, "some GPIO chips cannot be opened by this user",
          capture::permission_advice(paths.front()));
    else
      add("permissions", Status::ok, fmt::format("{} GPIO chip(s), all readable and writable", paths.size()));
  }

  // The kernel: CLOCK_REALTIME event stamps came with Linux 5.11, hardware timestamps with 5.19.
  int major = 0, minor = 0;
  if (!parse_kernel_version(in.kernel_release, major, minor))
    add("kernel", Status::warn, fmt::format("kernel release '{}' not understood", in.kernel_release));
  else if (major < 5 || (major == 5 && minor < 11))
    add("kernel", Status::fail,
        fmt::format("Linux {}.{} cannot stamp GPIO events with CLOCK_REALTIME (needs 5.11)", major, minor),
        "upgrade the kernel, or use --clock monotonic (timestamps then cannot be compared between boards)");
  else
    add("kernel", Status::ok,
        fmt::format("Linux {}.{}: CLOCK_REALTIME event timestamps supported", major, minor));

  // Real-time privileges.
  const auto& p = in.privileges;
  if (p.can_fifo())
    add("realtime", Status::ok,
        fmt::format("SCHED_FIFO allowed ({})",
                    p.cap_sys_nice ? "CAP_SYS_NICE" : fmt::format("RLIMIT_RTPRIO {}", p.rtprio_limit)));
  else
    add("realtime", Status::warn, "SCHED_FIFO not allowed (--rt-priority will be refused)",
        "grant CAP_SYS_NICE (`setcap cap_sys_nice+ep $(command -v m2mlat)`) or add `@gpio - rtprio 99` to "
        "/etc/security/limits.conf");
  if (p.can_mlock_all())
    add("realtime", Status::ok,
        fmt::format("mlockall allowed ({})", p.cap_ipc_lock ? "CAP_IPC_LOCK" : "RLIMIT_MEMLOCK unlimited"));
  else
    add("realtime", Status::warn,
        fmt::format("mlockall may be refused (RLIMIT_MEMLOCK {} bytes)", p.memlock_limit),
        "grant CAP_IPC_LOCK or add `@gpio - memlock unlimited` to /etc/security/limits.conf");

  // Interrupts of lines m2mlat holds now (a recorder running beside the doctor).
  bool any_irq = false;
  for (const auto& line : rt::parse_interrupts(in.interrupts_text)) {
    for (const auto& action : line.actions) {
      if (!action.starts_with("m2mlat-")) continue;
      any_irq = true;
      const auto affinity = in.irq_affinity ? in.irq_affinity(line.irq) : std::nullopt;
      add("irq", Status::ok,
          fmt::format("IRQ {} ({}) is routed to CPU(s) {}", line.irq, action, affinity.value_or("?")));
    }
  }
  if (!in.irq_writable)
    add("irq", Status::warn,
        "interrupt routing (--irq-cpu) needs root: /proc/irq/*/smp_affinity_list is root's",
        "run the recorder as root for --irq-cpu, or route the IRQ once as root");
  else if (!any_irq)
    add("irq", Status::ok, "interrupt routing allowed; no m2mlat line is held now");

  // Clock synchronisation.
  if (!in.clock.available)
    add("clock", Status::warn, "adjtimex failed: the clock's synchronisation state is unknown");
  else if (!in.clock.synchronised)
    add("clock", Status::fail, "the kernel clock is not synchronised (adjtimex: STA_UNSYNC)",
        "run chrony (or ptp4l/phc2sys, or gpsd with PPS) on both boards, so that their CLOCK_REALTIME agree");
  else
    add("clock", Status::ok,
        fmt::format("clock synchronised: estimated error {} us, maximum error {} us",
                    in.clock.est_error_ns / 1000, in.clock.max_error_ns / 1000));
  return report;
}

}  // namespace m2mlat::setup
