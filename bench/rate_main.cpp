// A high-rate stream through the store: gyroscope samples at 8 kHz for an hour on each of two boards
// (28.8 million samples a side), appended as a recorder appends them (one transaction a second, the
// second's samples split into rate blocks by store::rate_block::split), the store closed, reopened
// and each side's trace read back whole (Store::rate_trace) and compared with what was written.
// Prints bytes a sample on disk and CPU a sample for appending and reading.
//
//   m2mlat_rate_bench [--seconds S] [--rate HZ] [--json FILE]
//
// Each board gets its own store file (as each board's recorder writes its own), in a directory under
// $TMPDIR removed at the end (about 1.1 GB for the hour). The samples are a deterministic function of
// the board and the sample's number (a steering motion and noise, stamps with a few us of jitter), so
// the read-back is checked against the generator without keeping the written trace in memory.
// --json writes the figures for bench/report.py. Exit status 1 if a sample read back differs.
#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "m2mlat/core/number.hpp"
#include "m2mlat/core/rate_sample.hpp"
#include "m2mlat/store/rate_block.hpp"
#include "m2mlat/store/store.hpp"

namespace {

namespace store = m2mlat::store;
namespace core = m2mlat::core;

constexpr std::int64_t kStartNs = 1'780'304'400'000'000'000;  // 2026-06-01T09:00:00Z
constexpr double kCountsPerDegS = 131.0;                       // an MPU-6050 at +-250 deg/s

// Sample k of board `board` (0 or 1) at `rate_hz`: stamps on a period with up to +-4 us of jitter
// (a 64-bit mix of board and k, so no state is needed), a bound of 60 us (half an I2C read), and a
// steering motion of 0.3 Hz and up to 200 deg/s on z with a few counts of noise on every axis.
core::RateSample sample(int board, std::uint64_t k, std::int64_t rate_hz) {
  std::uint64_t h = k * 0x9E3779B97F4A7C15ULL + static_cast<std::uint64_t>(board + 1) * 0xBF58476D1CE4E5B9ULL;
  h ^= h >> 31;
  h *= 0x94D049BB133111EBULL;
  h ^= h >> 29;
  const auto noise = [&](int shift) { return static_cast<std::int16_t>(static_cast<int>((h >> shift) & 15) - 8); };
  const std::int64_t period = 1'000'000'000 / rate_hz;
  core::RateSample s;
  s.time_ns = kStartNs + static_cast<std::int64_t>(k) * period + static_cast<std::int64_t>(h % 8001) - 4000;
  s.bound_ns = 60'000;
  const double t = static_cast<double>(k) / static_cast<double>(rate_hz);
  const double z = 200.0 * kCountsPerDegS * std::sin(2 * M_PI * 0.3 * t + board * 0.5) / 2;
  s.raw = {noise(8), noise(12), static_cast<std::int16_t>(std::lround(z) + noise(16))};
  return s;
}

double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

double wall_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// CPU and wall time spent inside a region, summed over its visits.
struct Timer {
  double cpu = 0, wall = 0;
  template <typename Body>
  auto operator()(Body&& body) {
    const double c = cpu_seconds(), w = wall_seconds();
    struct Add {
      Timer& t;
      double c, w;
      ~Add() { t.cpu += cpu_seconds() - c, t.wall += wall_seconds() - w; }
    } add{*this, c, w};
    return body();
  }
};

std::uint64_t file_bytes(const std::string& path) {
  std::uint64_t total = 0;
  for (const char* suffix : {"", "-wal", "-shm"})
    if (std::filesystem::exists(path + suffix)) total += std::filesystem::file_size(path + suffix);
  return total;
}

}  // namespace

int main(int argc, char** argv) {
  std::int64_t seconds = 3600, rate = 8000;
  std::string json_path;
  for (int a = 1; a < argc; a += 2) {
    const std::string arg = argv[a];
    const bool has_value = a + 1 < argc;
    if (has_value && arg == "--seconds" && core::parse_integer(argv[a + 1], seconds) && seconds >= 1) continue;
    if (has_value && arg == "--rate" && core::parse_integer(argv[a + 1], rate) && rate >= 1 && rate <= 1'000'000)
      continue;
    if (has_value && arg == "--json") {
      json_path = argv[a + 1];
      continue;
    }
    fmt::print(stderr, "usage: m2mlat_rate_bench [--seconds S (>= 1)] [--rate HZ (1..10^6)] [--json FILE]\n");
    return 2;
  }
  const auto dir = std::filesystem::temp_directory_path() / fmt::format("m2mlat-rate-bench-{}", ::getpid());
  std::filesystem::create_directories(dir);
  const auto per_side = static_cast<std::uint64_t>(seconds * rate);
  const auto per_second = static_cast<std::uint64_t>(rate);
  Timer append, read;
  std::uint64_t bytes = 0, mismatches = 0, read_back = 0;
  for (int board = 0; board < 2; ++board) {
    const std::string path = (dir / fmt::format("board{}.db", board)).string();
    std::int64_t session_id = 0;
    {
      auto s = store::Store::open(path);
      store::Session session;
      session.label = "rate-bench";
      session.scenario = "rate-bench";
      session.node = board == 0 ? "operator" : "vehicle";
      session.start = core::TimePoint::from_ns(core::Clock::realtime, kStartNs - 1'000'000'000);
      session_id = s.begin_session(session);
      std::vector<core::RateSample> second;
      second.reserve(per_second);
      for (std::uint64_t first = 0; first < per_side; first += per_second) {
        second.clear();
        for (std::uint64_t k = first; k < std::min(per_side, first + per_second); ++k)
          second.push_back(sample(board, k, rate));
        append([&] {
          s.append_rate_blocks(
              store::rate_block::split(session_id, "gyro", core::Clock::realtime, kCountsPerDegS, second, first));
        });
      }
      append([&] {
        s.end_session(session_id, core::TimePoint::from_ns(core::Clock::realtime, sample(board, per_side - 1, rate).time_ns));
      });
    }  // closed: the WAL is checkpointed into the file
    bytes += file_bytes(path);
    auto s = store::Store::open(path);
    const auto trace = read([&] { return s.rate_trace(session_id, "gyro"); });
    read_back += trace.samples.size();
    for (std::uint64_t k = 0; k < trace.samples.size(); ++k) {
      const auto want = sample(board, k, rate);
      const auto& got = trace.samples[k];
      mismatches += got.time_ns != want.time_ns || got.bound_ns != want.bound_ns || got.raw != want.raw;
    }
  }
  std::filesystem::remove_all(dir);

  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const double samples = static_cast<double>(2 * per_side);
  const double bytes_per_sample = static_cast<double>(bytes) / samples;
  fmt::print("samples             {} a side ({} s at {} Hz), 2 boards\n", per_side, seconds, rate);
  fmt::print("on disk             {:.1f} MB, {:.2f} bytes a sample (the layout's record: {} bytes)\n",
             static_cast<double>(bytes) / 1e6, bytes_per_sample, store::rate_block::kSampleBytes);
  fmt::print("append              {:.2f} s CPU, {:.2f} s wall: {:.0f} ns CPU a sample, {:.2f} M samples/s\n", append.cpu,
             append.wall, append.cpu / samples * 1e9, samples / append.wall / 1e6);
  fmt::print("read back           {:.2f} s CPU, {:.2f} s wall: {:.0f} ns CPU a sample, {:.2f} M samples/s\n", read.cpu,
             read.wall, read.cpu / samples * 1e9, samples / read.wall / 1e6);
  fmt::print("peak memory         {} MiB\n", usage.ru_maxrss / 1024);
  fmt::print("read back equal     {}\n", mismatches == 0 && read_back == 2 * per_side ? "yes" : "NO");
  if (!json_path.empty()) {
    const nlohmann::json out = {{"samples_per_side", per_side}, {"seconds", seconds},   {"rate_hz", rate},
                                {"bytes", bytes},               {"append_cpu_s", append.cpu}, {"append_wall_s", append.wall},
                                {"read_cpu_s", read.cpu},       {"read_wall_s", read.wall},   {"peak_mib", usage.ru_maxrss / 1024}};
    std::ofstream(json_path) << out.dump() << '\n';
  }
  return mismatches == 0 && read_back == 2 * per_side ? 0 : 1;
}
