// The benchmarks' shared input: the simulated recording and its files in every importable format.
#include "workload.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <memory>
#include <stdexcept>
#include <system_error>
#include <utility>

#include "m2mlat/sim/generator.hpp"
#include "m2mlat/sim/presets.hpp"

namespace m2mlat::bench {

namespace {

constexpr std::int64_t kNsPerSecond = 1'000'000'000;

Settings g_settings;
std::unique_ptr<TempDir> g_dir;
std::unique_ptr<Recording> g_recording;
std::unique_ptr<InputFiles> g_files;

// Appends text to a file through a 1 MiB buffer; throws on any write error.
class FileWriter {
 public:
  explicit FileWriter(const std::string& path) : path_(path), file_(std::fopen(path.c_str(), "wb")) {
    if (file_ == nullptr) throw std::system_error(errno, std::generic_category(), "cannot create " + path);
  }
  FileWriter(const FileWriter&) = delete;
  FileWriter& operator=(const FileWriter&) = delete;
  ~FileWriter() {
    if (file_ != nullptr) std::fclose(file_);
  }

  template <typename... Args>
  void print(fmt::format_string<Args...> format, Args&&... args) {
    fmt::format_to(std::back_inserter(buffer_), format, std::forward<Args>(args)...);
    if (buffer_.size() >= (1u << 20)) drain();
  }
  void close() {
    drain();
    const int rc = std::fclose(file_);
    file_ = nullptr;
    if (rc != 0) throw std::system_error(errno, std::generic_category(), "cannot write " + path_);
  }

 private:
  void drain() {
    if (std::fwrite(buffer_.data(), 1, buffer_.size(), file_) != buffer_.size())
      throw std::system_error(errno, std::generic_category(), "cannot write " + path_);
    buffer_.clear();
  }

  std::string path_;
  std::FILE* file_;
  fmt::memory_buffer buffer_;
};

// Seconds (floor) and nanoseconds in [0, 10^9) of a CLOCK_REALTIME timestamp.
struct SecondsNs {
  std::int64_t s;
  std::int64_t ns;
};
SecondsNs split(std::int64_t t) {
  std::int64_t s = t / kNsPerSecond, ns = t % kNsPerSecond;
  if (ns < 0) {
    ns += kNsPerSecond;
    --s;
  }
  return {s, ns};
}

Recording simulate(std::size_t per_side) {
  auto config = sim::preset("static_5g");
  config.seed = 1;
  config.magnets_deg = {0, 20, 40};
  // ~3.2 edges per side and manoeuvre: this bound is never what ends the loop below.
  config.manoeuvres = static_cast<std::int64_t>(std::max<std::size_t>(per_side, 1000));
  sim::Generator generator(config);
  sim::Chunk chunk;
  Recording r;
  r.cause_ns.reserve(per_side + (1u << 16));
  r.effect_ns.reserve(per_side + (1u << 16));
  while ((r.cause_ns.size() < per_side || r.effect_ns.size() < per_side) && generator.next(chunk, 1u << 16)) {
    for (const auto& e : chunk.cause_events) r.cause_ns.push_back(e.time.ns());
    for (const auto& e : chunk.effect_events) r.effect_ns.push_back(e.time.ns());
    for (const auto& p : chunk.pairs)
      r.truth.push_back({static_cast<std::size_t>(p.cause_index), static_cast<std::size_t>(p.effect_index)});
  }
  if (r.cause_ns.size() < per_side || r.effect_ns.size() < per_side)
    throw std::runtime_error("the simulated run ended before reaching the requested size");
  r.cause_ns.resize(per_side);
  r.effect_ns.resize(per_side);
  std::erase_if(r.truth, [&](const TrueIndexPair& p) { return p.cause >= per_side || p.effect >= per_side; });
  return r;
}

InputFiles write_files(const Recording& r, const std::filesystem::path& dir) {
  InputFiles f;
  f.kernel_log = (dir / "operator.log").string();
  f.rig_export_csv = (dir / "rig_export.csv").string();
  f.rig_paired_csv = (dir / "rig_paired.csv").string();
  f.events_csv = (dir / "events.csv").string();

  f.kernel_log_effect = (dir / "vehicle.log").string();
  for (const auto& [path, column] :
       {std::pair{f.kernel_log, &r.cause_ns}, std::pair{f.kernel_log_effect, &r.effect_ns}}) {
    FileWriter log(path);
    for (auto t : *column) log.print("GPIO_16_IRQ:{}\n", t);
    log.close();
  }
  f.kernel_log_lines = r.cause_ns.size();

  FileWriter rig(f.rig_export_csv);
  rig.print("Line,Seconds,Nanoseconds\n");
  for (auto t : r.cause_ns) {
    const auto [s, ns] = split(t);
    rig.print("16,{},{}\n", s, ns);
  }
  rig.close();
  f.rig_export_lines = r.cause_ns.size();

  // The rig's latency column: exact milliseconds with 6 decimals, as the rig wrote it.
  FileWriter paired(f.rig_paired_csv);
  paired.print("remote_station_s,remote_station_ns,vehicle_s,vehicle_ns,,m2m_latency_ms\n");
  for (const auto& p : r.truth) {
    const auto c = split(r.cause_ns[p.cause]), e = split(r.effect_ns[p.effect]);
    const auto latency_ns = r.effect_ns[p.effect] - r.cause_ns[p.cause];
    paired.print("{},{},{},{},,{}.{:06}\n", c.s, c.ns, e.s, e.ns, latency_ns / 1'000'000,
                 latency_ns % 1'000'000);
  }
  paired.close();
  f.rig_paired_lines = r.truth.size();

  FileWriter events(f.events_csv);
  events.print("# format: m2mlat-events/1\nnode,channel,edge,clock,time_ns,seqno,line_seqno,flags\n");
  for (std::size_t i = 0; i < r.cause_ns.size(); ++i)
    events.print("operator,wheel,falling,realtime,{},{},{},1\n", r.cause_ns[i], i + 1, i + 1);
  events.close();
  f.events_csv_lines = r.cause_ns.size();
  return f;
}

}  // namespace

TempDir::TempDir() {
  const char* base = std::getenv("TMPDIR");
  std::string pattern =
      std::string(base != nullptr && *base != '\0' ? base : "/tmp") + "/m2mlat-bench-XXXXXX";
  if (::mkdtemp(pattern.data()) == nullptr)
    throw std::system_error(errno, std::generic_category(), "cannot create a directory like " + pattern);
  path_ = pattern;
}

TempDir::~TempDir() {
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
}

void configure(const Settings& settings) { g_settings = settings; }
const Settings& settings() { return g_settings; }

const Recording& recording() {
  if (!g_recording) g_recording = std::make_unique<Recording>(simulate(g_settings.events));
  return *g_recording;
}

const std::filesystem::path& scratch_dir() {
  if (!g_dir) g_dir = std::make_unique<TempDir>();
  return g_dir->path();
}

const InputFiles& input_files() {
  if (!g_files) g_files = std::make_unique<InputFiles>(write_files(recording(), scratch_dir()));
  return *g_files;
}

void release_workload() {
  g_files.reset();
  g_recording.reset();
  g_dir.reset();
}

Prefix prefix(std::size_t n, std::int64_t window_ns) {
  const auto& r = recording();
  n = std::min(n, r.cause_ns.size());
  std::size_t effects = 0;
  if (n > 0) {
    const auto end = r.cause_ns[n - 1] + window_ns;
    effects = static_cast<std::size_t>(std::upper_bound(r.effect_ns.begin(), r.effect_ns.end(), end) -
                                       r.effect_ns.begin());
  }
  return {std::span(r.cause_ns).first(n), std::span(r.effect_ns).first(effects)};
}

std::vector<std::size_t> ladder() {
  std::vector<std::size_t> sizes;
  for (std::size_t n : {100'000u, 1'000'000u, 10'000'000u})
    if (n < g_settings.events) sizes.push_back(n);
  sizes.push_back(g_settings.events);
  return sizes;
}

}  // namespace m2mlat::bench
