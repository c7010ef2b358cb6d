// Generating chrony.conf and the chronyd CPU drop-in.
#include "m2mlat/sync/chrony_config.hpp"

#include <fmt/format.h>

#include "m2mlat/core/error.hpp"

namespace m2mlat::sync {

namespace {

[[noreturn]] void usage(const std::string& message) { throw core::Error(core::ErrorKind::usage, message); }

// A value written into the configuration must be one word: no spaces, newlines or '#'.
void check_word(std::string_view what, const std::string& value) {
  if (value.empty() || value.find_first_of(" \t\r\n#") != std::string::npos)
    usage(fmt::format("{} '{}' must be one word", what, value));
}

void common_tail(std::string& out, const ChronyConfigOptions& o) {
  check_word("makestep", o.makestep.substr(0, o.makestep.find(' ')));
  if (o.makestep.find_first_of("\r\n#") != std::string::npos) usage("makestep must be one line");
  out += fmt::format(
      "\n# Step the clock only while starting (the default: when off by more than 5 ms in the first 3\n"
      "# updates): a board boots from its RTC or the last shutdown's time, seconds to hours off, and\n"
      "# slewed at 500 ppm (below) 5 ms take 10 s, 50 ms 100 s; a residual under the threshold is\n"
      "# slewed away in seconds. A later step would land inside a measurement; m2mlat records every\n"
      "# step it sees as a clock sample and corrects or flags the pairs around it.\n"
      "makestep {}\n"
      "# Slew at most 500 ppm (chrony's default is 83333): a kernel log's own printk stamps then\n"
      "# tell a step of the clock from its slewing, and m2mlat corrects the steps it finds there.\n"
      "maxslewrate 500\n"
      "# Keep the RTC close, so the next boot starts near the right time.\n"
      "rtcsync\n"
      "driftfile {}\n",
      o.makestep, o.driftfile);
  if (!o.hwtimestamp.empty()) {
    check_word("hwtimestamp interface", o.hwtimestamp);
    out += fmt::format(
        "# NIC hardware timestamps of NTP packets (needs a NIC and driver that support them).\n"
        "hwtimestamp {}\n",
        o.hwtimestamp);
  }
  out +=
      "# The tracking log shows offsets over time (chronyc tracking shows the current one).\n"
      "logdir /var/log/chrony\n"
      "log tracking measurements statistics\n";
}

}  // namespace

SyncMode parse_sync_mode(std::string_view text) {
  if (text == "co-referenced") return SyncMode::co_referenced;
  if (text == "autonomous") return SyncMode::autonomous;
  if (text == "gnss-pps") return SyncMode::gnss_pps;
  usage(fmt::format("unknown synchronisation mode '{}' (co-referenced, autonomous, gnss-pps)", text));
}

SyncRole parse_sync_role(std::string_view text) {
  if (text == "reference") return SyncRole::reference;
  if (text == "peer") return SyncRole::peer;
  usage(fmt::format("unknown role '{}' (reference, peer)", text));
}

std::string_view to_string(SyncMode mode) {
  switch (mode) {
    case SyncMode::co_referenced: return "co-referenced";
    case SyncMode::autonomous: return "autonomous";
    case SyncMode::gnss_pps: return "gnss-pps";
  }
  return "?";
}

std::string_view to_string(SyncRole role) { return role == SyncRole::reference ? "reference" : "peer"; }

std::string chrony_config(const ChronyConfigOptions& o) {
  std::string out =
      fmt::format("# chrony.conf written by m2mlat setup chrony (mode {}{}).\n", to_string(o.mode),
                  o.mode == SyncMode::co_referenced ? fmt::format(", role {}", to_string(o.role)) : "");
  switch (o.mode) {
    case SyncMode::co_referenced:
      if (o.role == SyncRole::reference) {
        if (o.allow.empty()) usage("the reference needs --allow (the peer's address or the board network)");
        if (o.local_stratum < 1 || o.local_stratum > 15) usage("--local-stratum must be 1..15");
        out += fmt::format(
            "# The reference board: serves its own clock to the peer on the board network. Only the\n"
            "# two boards' agreement matters for M2M latency, not their distance to UTC.\n"
            "local stratum {}\n",
            o.local_stratum);
        for (const auto& a : o.allow) {
          check_word("allow", a);
          out += fmt::format("allow {}\n", a);
        }
      } else {
        if (o.reference.empty()) usage("the peer needs --reference (the reference board's address)");
        check_word("reference", o.reference);
        if (o.minpoll < -6 || o.minpoll > 24 || o.maxpoll < o.minpoll || o.maxpoll > 24)
          usage("--minpoll/--maxpoll must be in -6..24 with minpoll <= maxpoll");
        out += fmt::format(
            "# The peer board: follows the reference board, polling every 2^{} s (the reference rig\n"
            "# polled every 4 s: a short poll keeps the two clocks within a few microseconds).\n"
            "server {}{} minpoll {} maxpoll {} iburst prefer\n",
            o.minpoll, o.reference, o.reference_port > 0 ? fmt::format(" port {}", o.reference_port) : "",
            o.minpoll, o.maxpoll);
      }
      break;
    case SyncMode::autonomous: {
      out +=
          "# Each board follows public time servers on its own; the two clocks then agree only as\n"
          "# well as each one follows UTC (typically 0.1-1 ms over the internet).\n";
      for (const auto& s : o.servers) {
        check_word("server", s);
        out += fmt::format("server {} iburst\n", s);
      }
      const std::vector<std::string> default_pool{"2.debian.pool.ntp.org"};
      for (const auto& p : o.pools.empty() && o.servers.empty() ? default_pool : o.pools) {
        check_word("pool", p);
        out += fmt::format("pool {} iburst\n", p);
      }
      break;
    }
    case SyncMode::gnss_pps: {
      check_word("PPS device", o.pps_device);
      out +=
          "# Each board follows its own GNSS receiver: NMEA sentences (through gpsd) give the\n"
          "# seconds, the PPS edge gives the phase. On a Raspberry Pi the PPS wire needs the\n"
          "# pps-gpio overlay, e.g. in /boot/firmware/config.txt: dtoverlay=pps-gpio,gpiopin=18\n"
          "# (then /dev/pps0 appears; check it with ppstest from pps-tools). gpsd must run with -n.\n";
      if (o.nmea == "shm") {
        out += "refclock SHM 0 refid NMEA offset 0.0 delay 0.2 noselect\n";
      } else {
        check_word("gpsd socket", o.nmea);
        out += fmt::format("refclock SOCK {} refid NMEA offset 0.0 delay 0.2 noselect\n", o.nmea);
      }
      out += fmt::format("refclock PPS {} lock NMEA refid PPS prefer\n", o.pps_device);
      break;
    }
  }
  common_tail(out, o);
  return out;
}

std::string chrony_cpu_dropin(int cpu) {
  if (cpu < 0) usage("the CPU must be >= 0");
  return fmt::format(
      "# Written by m2mlat setup chrony: keep chronyd on CPU {} so that it does not run on the\n"
      "# capture thread's core. Apply with: systemctl daemon-reload && systemctl restart chrony\n"
      "[Service]\n"
      "CPUAffinity={}\n",
      cpu, cpu);
}

}  // namespace m2mlat::sync
