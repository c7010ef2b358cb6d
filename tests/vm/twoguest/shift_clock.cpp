// m2mlat-2g-shift-clock: moves this guest's CLOCK_REALTIME by an exact number of nanoseconds, for the
// two-guest test's autonomous phase (tests/vm/twoguest.sh): the vehicle's clock is put a known offset X
// ahead of the operator's, and the measurement must show X.
//
// clock_adjtime(ADJ_SETOFFSET | ADJ_NANO) adds the offset inside the kernel, under its timekeeping
// lock: unlike reading the time and setting it again (clock_settime), nothing elapses between the read
// and the write, so the step is exactly the one asked for. The frequency correction chronyd left in the
// kernel is kept, so the clock runs on at the rate it had while synchronised.
//
//   m2mlat-2g-shift-clock OFFSET_NS      (positive: the clock jumps ahead)
// Prints "shifted OFFSET_NS" and CLOCK_REALTIME - CLOCK_MONOTONIC_RAW before and after (ns), whose
// difference is the step plus the few us between the reads.
#include <sys/timex.h>

#include <cerrno>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>

namespace {

std::int64_t ns(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

std::int64_t realtime_minus_raw() { return ns(CLOCK_REALTIME) - ns(CLOCK_MONOTONIC_RAW); }

}  // namespace

int main(int argc, char** argv) {
  char* end = nullptr;
  errno = 0;
  const long long offset = argc == 2 ? std::strtoll(argv[1], &end, 10) : 0;
  if (argc != 2 || errno != 0 || end == argv[1] || *end != '\0') {
    std::fprintf(stderr, "usage: m2mlat-2g-shift-clock OFFSET_NS\n");
    return 2;
  }
  // ADJ_SETOFFSET takes seconds and a non-negative nanosecond part (with ADJ_NANO): -1.5 ms is
  // {-1 s, 998,500,000 ns}.
  timex tx{};
  tx.modes = ADJ_SETOFFSET | ADJ_NANO;
  tx.time.tv_sec = offset / 1'000'000'000;
  tx.time.tv_usec = offset % 1'000'000'000;
  if (tx.time.tv_usec < 0) {
    tx.time.tv_sec -= 1;
    tx.time.tv_usec += 1'000'000'000;
  }
  const std::int64_t before = realtime_minus_raw();
  if (clock_adjtime(CLOCK_REALTIME, &tx) < 0) {
    std::fprintf(stderr, "m2mlat-2g-shift-clock: clock_adjtime: %s\n", std::strerror(errno));
    return 1;
  }
  const std::int64_t after = realtime_minus_raw();
  std::printf("shifted %lld before %" PRId64 " after %" PRId64 "\n", offset, before, after);
  return 0;
}
