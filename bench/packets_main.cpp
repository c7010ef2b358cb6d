// How fast a capture's commands are read: a generated raw-IP capture of N packets (default 10^7) of
// a teleoperation command stream (TCP, length-prefixed JSON commands with the sender's time in ms,
// some split over two segments and some joined two to a segment, and UDP datagrams of the same
// commands) is written with libpcap, then read back into markers (markers::read_file_markers: read,
// decode, reassemble, key). Prints packets per second against the target of 1 million.
//
//   m2mlat_packets_bench [--packets N]
#include <fmt/format.h>
#include <pcap/pcap.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <string>

#include "m2mlat/core/number.hpp"
#include "m2mlat/markers/capture_writer.hpp"
#include "m2mlat/markers/packet_markers.hpp"

namespace mk = m2mlat::markers;

int main(int argc, char** argv) {
  std::int64_t packets = 10'000'000;
  if (argc == 3 && std::string(argv[1]) == "--packets" && m2mlat::core::parse_integer(argv[2], packets) && packets >= 100) {
  } else if (argc != 1) {
    fmt::print(stderr, "usage: m2mlat_packets_bench [--packets N (>= 100)]\n");
    return 2;
  }
  const auto dir = std::filesystem::temp_directory_path() / fmt::format("m2mlat-packets-bench-{}", ::getpid());
  std::filesystem::create_directories(dir);
  const auto path = (dir / "commands.pcap").string();
  const auto tcp = mk::make_flow(mk::Transport::tcp, "192.168.10.2", 40000, "192.168.10.3", 7000);
  const auto udp = mk::make_flow(mk::Transport::udp, "192.168.10.2", 40001, "192.168.10.3", 7001);
  const std::int64_t t0 = 1'764'000'000'000'000'000;
  std::int64_t written = 0;
  std::int64_t commands = 0;
  {
    mk::CaptureWriter writer(path, DLT_RAW);
    std::uint32_t sequence = 1;
    writer.write(t0, mk::build_frame(DLT_RAW, tcp, {}, 0, mk::kTcpSyn));
    written = 1;
    const auto message = [&](std::int64_t k) {
      const std::int64_t ms = t0 / 1'000'000 + k * 10;
      return mk::length_prefixed(fmt::format(R"({{"seq":{},"stamp":{},"steer":0.125,"throttle":0.5}})", k, ms));
    };
    for (std::int64_t k = 0; written < packets; ++k) {
      const std::int64_t t = t0 + k * 10'000'000;
      auto bytes = message(k);
      if (k % 10 == 3) {  // joined: two commands in one segment
        const auto next = message(++k);
        bytes.insert(bytes.end(), next.begin(), next.end());
        ++commands;
      }
      if (k % 10 == 7 && written + 1 < packets) {  // split over two segments
        const std::size_t half = bytes.size() / 2;
        writer.write(t, mk::build_frame(DLT_RAW, tcp, std::span(bytes).first(half), sequence));
        writer.write(t + 1000, mk::build_frame(DLT_RAW, tcp, std::span(bytes).subspan(half),
                                               sequence + static_cast<std::uint32_t>(half)));
        written += 2;
      } else {
        writer.write(t, mk::build_frame(DLT_RAW, tcp, bytes, sequence));
        ++written;
      }
      sequence += static_cast<std::uint32_t>(bytes.size());
      ++commands;
      if (written < packets) {
        writer.write(t + 2000, mk::build_frame(DLT_RAW, udp, std::span(bytes).subspan(4)));
        ++written;
        ++commands;
      }
    }
  }
  mk::MarkerOptions options;
  options.rule.key = mk::parse_key_rule("json:seq");
  options.rule.sender_ms = "stamp";
  options.node = "vehicle";
  std::uint64_t markers = 0;
  const auto start = std::chrono::steady_clock::now();
  const std::clock_t cpu_start = std::clock();
  auto capture = mk::Capture::open_file(path);
  const auto counts = mk::read_markers(capture, options, [&](mk::Marker&&) { ++markers; });
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double cpu_seconds = static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;
  std::filesystem::remove_all(dir);
  // The target is judged on the process's CPU time: on a machine shared with other work (CI's two
  // cores) the wall time also counts the time others ran; both are printed.
  const double rate = static_cast<double>(counts.packets) / cpu_seconds;
  fmt::print("packets             {}\nmarkers             {} (of {} commands written)\n", counts.packets, markers, commands);
  fmt::print("read in             {:.3f} s CPU, {:.3f} s wall\n", cpu_seconds, seconds);
  fmt::print("rate                {:.0f} packets/s (CPU), {:.0f} packets/s (wall)\n", rate,
             static_cast<double>(counts.packets) / seconds);
  fmt::print("target >= 1,000,000 packets/s: {}\n", rate >= 1e6 ? "met" : "NOT MET");
  // Every packet read and every command found: a faster reader that loses commands is no faster.
  return counts.packets == static_cast<std::uint64_t>(written) && markers == static_cast<std::uint64_t>(commands) ? 0 : 1;
}
