// chrony configuration for the three ways m2mlat's boards keep time (docs/sync.md):
//   co-referenced: one board (the reference) serves its own clock on the board network
//                  (`local stratum`, `allow`); the other (the peer) follows it with a short poll
//                  (`server <reference> minpoll 2 maxpoll 2 iburst`, as in the reference rig). What
//                  matters for M2M is the two clocks' agreement, not their distance to UTC.
//   autonomous:    each board follows public servers or pools on its own.
//   gnss-pps:      each board follows a GNSS receiver: NMEA time (gpsd's SHM or SOCK) for the
//                  seconds, the PPS edge on /dev/pps0 (pps-gpio) for the phase.
// Plus the systemd drop-in that pins chronyd to one core (CPUAffinity=) so that it does not share
// one with the capture thread. Pure text generation: writing the files is the CLI's job.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace m2mlat::sync {

enum class SyncMode { co_referenced, autonomous, gnss_pps };
enum class SyncRole { reference, peer };

SyncMode parse_sync_mode(std::string_view text);  // "co-referenced" | "autonomous" | "gnss-pps"
SyncRole parse_sync_role(std::string_view text);  // "reference" | "peer"
std::string_view to_string(SyncMode mode);
std::string_view to_string(SyncRole role);

struct ChronyConfigOptions {
  SyncMode mode = SyncMode::co_referenced;
  SyncRole role = SyncRole::reference;
  std::string reference;             // peer: the reference board's address
  int reference_port = 0;            // peer: the reference's NTP port; 0 = 123
  std::vector<std::string> allow;    // reference: who may synchronise to it (addresses or subnets)
  int local_stratum = 1;             // reference: the stratum it serves its own clock at
  std::vector<std::string> servers;  // autonomous: servers ...
  std::vector<std::string> pools;    // ... and pools (default: 2.debian.pool.ntp.org)
  int minpoll = 2, maxpoll = 2;      // co-referenced peer: log2 of the polling interval, s
  // Step when off by more than 5 ms, in the first 3 clock updates only (docs/sync.md: a start offset
  // is stepped, not slewed for minutes at maxslewrate 500; a later step would land in a measurement).
  std::string makestep = "0.005 3";
  std::string pps_device = "/dev/pps0";
  std::string nmea = "shm";  // gnss-pps: "shm" (gpsd SHM 0) or a gpsd socket path
  std::string hwtimestamp;   // an interface for NIC hardware timestamping ("*" = all)
  std::string driftfile = "/var/lib/chrony/chrony.drift";
};

// The whole chrony.conf. Throws core::Error(usage) for missing or contradictory options.
std::string chrony_config(const ChronyConfigOptions& options);

// The systemd drop-in ([Service] CPUAffinity=<cpu>) for chrony.service, and where it goes.
std::string chrony_cpu_dropin(int cpu);
inline constexpr std::string_view kChronyDropinPath = "/etc/systemd/system/chrony.service.d/m2mlat-cpu.conf";

}  // namespace m2mlat::sync
