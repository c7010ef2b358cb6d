// m2mlat-vm-gyro: the stimulus and judge of the real-kernel gyroscope tests, run inside the QEMU guest.
//
// i2c-stub (chip_addr=0x68) is a register file on a real SMBus adapter, reached through i2c-dev as
// /dev/i2c-N, like an MPU-6050 on a board's bus. This program plays the chip's motion: it writes the
// gyro output registers (GYRO_XOUT_H..GYRO_ZOUT_L, 0x43..0x48) in one I2C block write per step and
// logs CLOCK_REALTIME just before and just after each write. The adapter's lock makes each 6-byte
// write and each 6-byte read whole, so a reader sees the old values or the new ones, never half.
//
//   set DEV ADDR REG VALUE                 writes one register (SMBus write byte data)
//   wait-reg DEV ADDR REG VALUE TIMEOUT_MS  waits until a register reads VALUE (the recorder has
//                                          configured the chip); exit 1 on timeout
//   steps --device DEV --address ADDR --from K --count N --gap-us G --log OUT [--append]
//       writes the rates of steps K..K+N-1, G us apart; logs "k before_ns after_ns x y z" per step
//   motion --device DEV --address ADDR --count N --rate COUNTS --rest-ms R --move-ms M --log OUT
//       rest (all rates 0) for R ms, then a rotation about x at COUNTS for M ms, N times, and rest
//       again; logs "k before_ns after_ns" of each rotation's first write (its onset)
//   verify --log LOG --trace CSV
//       holds an m2mlat-gyro/1 trace against the steps: every sample one of the steps' values, in
//       step order; every step after the first seen; the change to each step bracketed by the trace
//       where the write happened: the last read of the old value began before the write ended
//       (t - bound <= after) and the first read of the new value ended after it began
//       (t + bound >= before). Prints key=value figures (us); exit 0 pass, 1 fail, 2 usage.
//
// Built fully static (the guest has no C library): g++ -std=c++20 -O2 -static.
#include <fcntl.h>
#include <linux/i2c-dev.h>
#include <linux/i2c.h>
#include <sys/ioctl.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace {

constexpr std::int64_t kNsPerS = 1000000000;
constexpr std::uint8_t kGyroXoutH = 0x43;

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::int64_t clock_ns(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return std::int64_t{ts.tv_sec} * kNsPerS + ts.tv_nsec;
}

std::int64_t parse_int(std::string_view text, std::string_view what) {
  int base = 10;
  if (text.starts_with("0x")) {
    text.remove_prefix(2);
    base = 16;
  }
  std::int64_t value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value, base);
  if (text.empty() || ec != std::errc{} || end != text.data() + text.size())
    throw UsageError("bad " + std::string(what) + " '" + std::string(text) + "' (expected an integer)");
  return value;
}

std::map<std::string, std::string> parse_options(int argc, char** argv, int first) {
  std::map<std::string, std::string> options;
  for (int i = first; i < argc; ++i) {
    const std::string name = argv[i];
    if (name.rfind("--", 0) != 0) throw UsageError("unexpected argument '" + name + "'");
    if (name == "--append") {
      options["append"] = "1";
    } else {
      if (i + 1 >= argc) throw UsageError(name + " needs a value");
      options[name.substr(2)] = argv[++i];
    }
  }
  return options;
}

std::string required(const std::map<std::string, std::string>& options, const std::string& name) {
  const auto it = options.find(name);
  if (it == options.end()) throw UsageError("--" + name + " is required");
  return it->second;
}

// The rates of step k, counts: both signs and both bytes of each axis change from step to step.
std::array<std::int16_t, 3> step_rates(std::int64_t k) {
  return {static_cast<std::int16_t>(1000 * k - 9000), static_cast<std::int16_t>(-(311 * k + 7)),
          static_cast<std::int16_t>(1237 * k)};
}

class Chip {
 public:
  Chip(const std::string& device, std::int64_t address) : device_(device) {
    fd_ = open(device.c_str(), O_RDWR | O_CLOEXEC);
    if (fd_ < 0) throw std::runtime_error("cannot open " + device + ": " + std::strerror(errno));
    if (ioctl(fd_, I2C_SLAVE, static_cast<unsigned long>(address)) != 0)
      throw std::runtime_error("I2C_SLAVE on " + device + ": " + std::strerror(errno));
  }
  ~Chip() { close(fd_); }
  Chip(const Chip&) = delete;
  Chip& operator=(const Chip&) = delete;

  void transfer(std::uint8_t read_write, std::uint8_t reg, std::uint32_t size, i2c_smbus_data& data) {
    i2c_smbus_ioctl_data args{read_write, reg, size, &data};
    if (ioctl(fd_, I2C_SMBUS, &args) != 0)
      throw std::runtime_error("I2C_SMBUS on " + device_ + " register " + std::to_string(reg) + ": " +
                               std::strerror(errno));
  }
  std::uint8_t read_byte(std::uint8_t reg) {
    i2c_smbus_data data{};
    transfer(I2C_SMBUS_READ, reg, I2C_SMBUS_BYTE_DATA, data);
    return data.byte;
  }
  void write_byte(std::uint8_t reg, std::uint8_t value) {
    i2c_smbus_data data{};
    data.byte = value;
    transfer(I2C_SMBUS_WRITE, reg, I2C_SMBUS_BYTE_DATA, data);
  }
  void write_rates(const std::array<std::int16_t, 3>& rates) {
    i2c_smbus_data data{};
    data.block[0] = 6;
    for (std::size_t i = 0; i < 3; ++i) {
      const auto u = static_cast<std::uint16_t>(rates[i]);
      data.block[1 + 2 * i] = static_cast<std::uint8_t>(u >> 8);  // big-endian, as the chip
      data.block[2 + 2 * i] = static_cast<std::uint8_t>(u & 0xff);
    }
    transfer(I2C_SMBUS_WRITE, kGyroXoutH, I2C_SMBUS_I2C_BLOCK_DATA, data);
  }

 private:
  std::string device_;
  int fd_ = -1;
};

int cmd_wait_reg(Chip& chip, std::uint8_t reg, std::uint8_t value, std::int64_t timeout_ms) {
  const std::int64_t deadline = clock_ns(CLOCK_MONOTONIC) + timeout_ms * 1000000;
  for (;;) {
    const std::uint8_t now = chip.read_byte(reg);
    if (now == value) return 0;
    if (clock_ns(CLOCK_MONOTONIC) > deadline) {
      std::fprintf(stderr, "register 0x%02x still 0x%02x after %lld ms\n", reg, now,
                   static_cast<long long>(timeout_ms));
      return 1;
    }
    usleep(10000);
  }
}

int cmd_steps(const std::map<std::string, std::string>& o) {
  Chip chip(required(o, "device"), parse_int(required(o, "address"), "--address"));
  const std::int64_t from = parse_int(required(o, "from"), "--from");
  const std::int64_t count = parse_int(required(o, "count"), "--count");
  const std::int64_t gap_ns = parse_int(required(o, "gap-us"), "--gap-us") * 1000;
  std::vector<std::array<std::int64_t, 2>> times;
  std::int64_t next = clock_ns(CLOCK_MONOTONIC);
  for (std::int64_t k = from; k < from + count; ++k) {
    if (k > from) {
      next += gap_ns;
      const timespec ts{static_cast<time_t>(next / kNsPerS), static_cast<long>(next % kNsPerS)};
      while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
      }
    }
    const std::int64_t before = clock_ns(CLOCK_REALTIME);
    chip.write_rates(step_rates(k));
    const std::int64_t after = clock_ns(CLOCK_REALTIME);
    times.push_back({before, after});
  }
  std::ofstream log(required(o, "log"), o.count("append") ? std::ios::app : std::ios::trunc);
  for (std::int64_t i = 0; i < count; ++i) {
    const auto r = step_rates(from + i);
    log << from + i << ' ' << times[i][0] << ' ' << times[i][1] << ' ' << r[0] << ' ' << r[1] << ' ' << r[2]
        << '\n';
  }
  return log ? 0 : 1;
}

void sleep_until(std::int64_t monotonic_ns) {
  const timespec ts{static_cast<time_t>(monotonic_ns / kNsPerS), static_cast<long>(monotonic_ns % kNsPerS)};
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

int cmd_motion(const std::map<std::string, std::string>& o) {
  Chip chip(required(o, "device"), parse_int(required(o, "address"), "--address"));
  const std::int64_t count = parse_int(required(o, "count"), "--count");
  const auto rate = static_cast<std::int16_t>(parse_int(required(o, "rate"), "--rate"));
  const std::int64_t rest_ns = parse_int(required(o, "rest-ms"), "--rest-ms") * 1000000;
  const std::int64_t move_ns = parse_int(required(o, "move-ms"), "--move-ms") * 1000000;
  std::vector<std::array<std::int64_t, 2>> onsets;
  chip.write_rates({0, 0, 0});
  std::int64_t next = clock_ns(CLOCK_MONOTONIC);
  for (std::int64_t k = 0; k < count; ++k) {
    sleep_until(next += rest_ns);
    const std::int64_t before = clock_ns(CLOCK_REALTIME);
    chip.write_rates({rate, 0, 0});
    onsets.push_back({before, clock_ns(CLOCK_REALTIME)});
    sleep_until(next += move_ns);
    chip.write_rates({0, 0, 0});
  }
  std::ofstream log(required(o, "log"));
  for (std::size_t k = 0; k < onsets.size(); ++k) log << k << ' ' << onsets[k][0] << ' ' << onsets[k][1] << '\n';
  return log ? 0 : 1;
}

struct Sample {
  std::int64_t time = 0, bound = 0;
  std::array<std::int64_t, 3> raw{};
};

std::int64_t percentile(std::vector<std::int64_t> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(p * static_cast<double>(v.size() - 1))];
}

int cmd_verify(const std::map<std::string, std::string>& o) {
  struct Step {
    std::int64_t k, before, after;
    std::array<std::int64_t, 3> raw;
  };
  std::vector<Step> steps;
  {
    std::ifstream in(required(o, "log"));
    Step s{};
    while (in >> s.k >> s.before >> s.after >> s.raw[0] >> s.raw[1] >> s.raw[2]) steps.push_back(s);
  }
  std::vector<Sample> samples;
  {
    std::ifstream in(required(o, "trace"));
    std::string line;
    bool header = false;
    while (std::getline(in, line)) {
      if (!header) {
        header = line == "time_ns,bound_ns,x,y,z";
        continue;
      }
      std::replace(line.begin(), line.end(), ',', ' ');
      std::istringstream fields(line);
      Sample s;
      if (!(fields >> s.time >> s.bound >> s.raw[0] >> s.raw[1] >> s.raw[2]))
        throw std::runtime_error("trace line not understood: " + line);
      samples.push_back(s);
    }
  }
  if (steps.size() < 2 || samples.empty()) {
    std::fprintf(stderr, "nothing to verify: %zu steps, %zu samples\n", steps.size(), samples.size());
    return 1;
  }
  int failures = 0;
  auto fail = [&](const std::string& what) {
    if (++failures <= 10) std::fprintf(stderr, "%s\n", what.c_str());
  };
  // Which step each sample shows.
  std::vector<std::size_t> index(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const auto it =
        std::find_if(steps.begin(), steps.end(), [&](const Step& s) { return s.raw == samples[i].raw; });
    if (it == steps.end()) {
      fail("sample " + std::to_string(i) + " shows rates no step wrote (a torn or corrupt read)");
      index[i] = 0;
      continue;
    }
    index[i] = static_cast<std::size_t>(it - steps.begin());
    if (i > 0 && index[i] < index[i - 1])
      fail("sample " + std::to_string(i) + " shows an older step than the one before");
    if (i > 0 && samples[i].time < samples[i - 1].time)
      fail("sample " + std::to_string(i) + " is stamped before the one before");
  }
  std::vector<std::int64_t> windows, delays, reads;
  for (const auto& s : samples) reads.push_back(2 * s.bound);  // the width of each stamp's interval
  for (std::size_t k = 1; k < steps.size(); ++k) {
    const auto first = std::find(index.begin(), index.end(), k);
    if (first == index.end()) {
      fail("step " + std::to_string(k) + " was never seen");
      continue;
    }
    const std::size_t i = static_cast<std::size_t>(first - index.begin());
    const Sample& now = samples[i];
    if (now.time + now.bound < steps[k].before)
      fail("step " + std::to_string(k) + ": first seen by a read that ended " +
           std::to_string(steps[k].before - now.time - now.bound) + " ns before the write began");
    delays.push_back(now.time - steps[k].after);
    if (i == 0) continue;
    const Sample& old = samples[i - 1];
    if (old.time - old.bound > steps[k].after)
      fail("step " + std::to_string(k) + ": the last read of the old value began " +
           std::to_string(old.time - old.bound - steps[k].after) + " ns after the write ended");
    windows.push_back(now.time + now.bound - (old.time - old.bound));
  }
  std::printf(
      "steps=%zu samples=%zu failures=%d change_window_p50_us=%lld change_window_max_us=%lld "
      "delay_p50_us=%lld delay_max_us=%lld interval_p50_us=%lld interval_p99_us=%lld interval_max_us=%lld\n",
      steps.size(), samples.size(), failures, static_cast<long long>(percentile(windows, 0.5) / 1000),
      static_cast<long long>(percentile(windows, 1.0) / 1000),
      static_cast<long long>(percentile(delays, 0.5) / 1000),
      static_cast<long long>(percentile(delays, 1.0) / 1000),
      static_cast<long long>(percentile(reads, 0.5) / 1000),
      static_cast<long long>(percentile(reads, 0.99) / 1000),
      static_cast<long long>(percentile(reads, 1.0) / 1000));
  return failures == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc < 2) throw UsageError("usage: m2mlat-vm-gyro set|wait-reg|steps|motion|verify ...");
    const std::string command = argv[1];
    if (command == "set" || command == "wait-reg") {
      if (argc != (command == "set" ? 6 : 7))
        throw UsageError("usage: m2mlat-vm-gyro " + command + " DEV ADDR REG VALUE ...");
      Chip chip(argv[2], parse_int(argv[3], "ADDR"));
      const auto reg = static_cast<std::uint8_t>(parse_int(argv[4], "REG"));
      const auto value = static_cast<std::uint8_t>(parse_int(argv[5], "VALUE"));
      if (command == "set") {
        chip.write_byte(reg, value);
        return 0;
      }
      return cmd_wait_reg(chip, reg, value, parse_int(argv[6], "TIMEOUT_MS"));
    }
    if (command == "steps") return cmd_steps(parse_options(argc, argv, 2));
    if (command == "verify") return cmd_verify(parse_options(argc, argv, 2));
    if (command == "motion") return cmd_motion(parse_options(argc, argv, 2));
    throw UsageError("unknown command '" + command + "'");
  } catch (const UsageError& e) {
    std::fprintf(stderr, "m2mlat-vm-gyro: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "m2mlat-vm-gyro: %s\n", e.what());
    return 1;
  }
}
