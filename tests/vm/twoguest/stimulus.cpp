// m2mlat-2g-stimulus: the guest's end of the two-guest test's stimulus channel (tests/vm/twoguest.sh).
//
// The host, which is the one clock both guests share (physical time), writes one trigger byte to each
// guest's serial port (QEMU: a TCP chardev on the host, an isa-serial in the guest) at the moment an
// edge should happen there. This program waits for those bytes and turns each into a gpio-sim edge:
//   'A'  flips line 0 (the latency line: the operator's "wheel", or the vehicle's answer to it)
//   'B'  flips line 1 (the shared pulse of the synchronisation test, sent to both guests at once)
// Each line alternates pull-up / pull-down, starting at gpio-sim's default (pull-down), so both guests'
// n-th edge of a line has the same type. After the write the byte is echoed back, so the host can
// measure the round trip (its spread bounds the delivery jitter the test must tolerate).
//
// It runs SCHED_FIFO with its memory locked, so that the guest's other work (the agent, chronyd) does
// not sit between the byte's arrival and the write: the edge is then late by the serial path's delivery
// only, which is the jitter the host measures.
//
//   m2mlat-2g-stimulus TTY SIM_FOLDER     (SIM_FOLDER = /sys/devices/platform/gpio-sim.N/gpiochipM)
// It prints "ready" once the port is raw and open, and exits at end of file or on 'Q'.
#include <fcntl.h>
#include <sched.h>
#include <sys/mman.h>
#include <termios.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>

namespace {

int fail(const char* what) {
  std::fprintf(stderr, "m2mlat-2g-stimulus: %s: %s\n", what, std::strerror(errno));
  return 1;
}

// A raw serial line: every byte handed over as it arrives (VMIN 1, VTIME 0), no echo, no translation.
bool make_raw(int fd) {
  termios t{};
  if (tcgetattr(fd, &t) != 0) return false;
  cfmakeraw(&t);
  cfsetspeed(&t, B115200);  // QEMU's UART emulates the character time: 87 us a byte at 115200 baud
  t.c_cc[VMIN] = 1;
  t.c_cc[VTIME] = 0;
  return tcsetattr(fd, TCSANOW, &t) == 0;
}

struct Line {
  int fd = -1;
  bool high = false;  // gpio-sim's lines start pulled down
};

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: m2mlat-2g-stimulus TTY SIM_FOLDER\n");
    return 2;
  }
  const std::string sim = argv[2];
  std::array<Line, 2> lines;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::string path = sim + "/sim_gpio" + std::to_string(i) + "/pull";
    lines[i].fd = open(path.c_str(), O_WRONLY | O_CLOEXEC);
    if (lines[i].fd < 0) return fail(path.c_str());
  }
  const int tty = open(argv[1], O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (tty < 0) return fail(argv[1]);
  if (!make_raw(tty)) return fail("tcsetattr");
  tcflush(tty, TCIOFLUSH);
  // Priority 60: above everything else in the guest's user space (the agent runs without real-time
  // settings here). gpio-sim stamps the edge inside the write itself, so nothing after it matters.
  sched_param p{};
  p.sched_priority = 60;
  if (sched_setscheduler(0, SCHED_FIFO, &p) != 0) return fail("sched_setscheduler");
  if (mlockall(MCL_CURRENT | MCL_FUTURE) != 0) return fail("mlockall");
  std::printf("ready\n");
  std::fflush(stdout);

  for (;;) {
    char c = 0;
    const ssize_t n = read(tty, &c, 1);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return fail("read");
    if (n == 0 || c == 'Q') return 0;
    if (c != 'A' && c != 'B') continue;  // line noise; the host sends nothing else
    Line& line = lines[c == 'A' ? 0 : 1];
    line.high = !line.high;
    const char* value = line.high ? "pull-up" : "pull-down";
    if (pwrite(line.fd, value, std::strlen(value), 0) < 0) return fail("write pull");
    if (write(tty, &c, 1) != 1) return fail("echo");
  }
}
