#!/usr/bin/env bash
# The architecture assumptions under the capture code, on amd64 and on arm64: the layout of the GPIO
# uAPI v2 structs m2mlat passes to the kernel unchanged (capture/gpio_device.hpp, gpio_linux.cpp), the
# ioctl numbers (they encode the struct sizes), and 64-bit time_t/timespec (timestamps are int64 ns
# and the kernel's are u64). The program is compiled with each compiler against that architecture's
# <linux/gpio.h>, checked at compile time (static_assert on the kernel ABI's documented sizes and
# offsets) and run (arm64 under qemu-aarch64); both must print the same table.
#
#   tests/packaging/abi_layout.sh [CROSS_CXX [EMULATOR...]]
# Default: aarch64-linux-gnu-g++, qemu-aarch64.
set -euo pipefail
CROSS_CXX=${1:-aarch64-linux-gnu-g++}
shift || true
if [ $# -gt 0 ]; then EMU=("$@"); else EMU=(qemu-aarch64); fi
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

cat >"$WORK/layout.cpp" <<'CPP'
// Sizes and offsets of the GPIO uAPI v2 structs, the ioctl numbers and the time types.
#include <linux/gpio.h>
#include <sys/ioctl.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <ctime>

#define ROW(expr) std::printf("%-48s %lu\n", #expr, static_cast<unsigned long>(expr))

// The kernel ABI (include/uapi/linux/gpio.h): identical on every 64-bit and 32-bit architecture,
// which is why its 64-bit fields are __aligned_u64.
static_assert(sizeof(gpio_v2_line_event) == 48);
static_assert(offsetof(gpio_v2_line_event, timestamp_ns) == 0);
static_assert(offsetof(gpio_v2_line_event, id) == 8);
static_assert(offsetof(gpio_v2_line_event, offset) == 12);
static_assert(offsetof(gpio_v2_line_event, seqno) == 16);
static_assert(offsetof(gpio_v2_line_event, line_seqno) == 20);
static_assert(sizeof(gpio_v2_line_attribute) == 16);
static_assert(sizeof(gpio_v2_line_config_attribute) == 24);
static_assert(sizeof(gpio_v2_line_config) == 272);
static_assert(offsetof(gpio_v2_line_config, attrs) == 32);
static_assert(sizeof(gpio_v2_line_request) == 592);
static_assert(offsetof(gpio_v2_line_request, consumer) == 256);
static_assert(offsetof(gpio_v2_line_request, config) == 288);
static_assert(offsetof(gpio_v2_line_request, num_lines) == 560);
static_assert(offsetof(gpio_v2_line_request, event_buffer_size) == 564);
static_assert(offsetof(gpio_v2_line_request, fd) == 588);
static_assert(sizeof(gpio_v2_line_info) == 256);
static_assert(sizeof(gpio_v2_line_values) == 16);
static_assert(sizeof(gpiochip_info) == 68);
// Timestamps: int64 nanoseconds everywhere; time_t must not be the 32-bit one.
static_assert(sizeof(std::time_t) == 8);
static_assert(sizeof(timespec) == 16);
static_assert(alignof(std::int64_t) == 8);

int main() {
  ROW(sizeof(gpio_v2_line_event));
  ROW(offsetof(gpio_v2_line_event, timestamp_ns));
  ROW(offsetof(gpio_v2_line_event, id));
  ROW(offsetof(gpio_v2_line_event, offset));
  ROW(offsetof(gpio_v2_line_event, seqno));
  ROW(offsetof(gpio_v2_line_event, line_seqno));
  ROW(offsetof(gpio_v2_line_event, padding));
  ROW(sizeof(gpio_v2_line_attribute));
  ROW(offsetof(gpio_v2_line_attribute, flags));
  ROW(sizeof(gpio_v2_line_config_attribute));
  ROW(offsetof(gpio_v2_line_config_attribute, mask));
  ROW(sizeof(gpio_v2_line_config));
  ROW(offsetof(gpio_v2_line_config, num_attrs));
  ROW(offsetof(gpio_v2_line_config, attrs));
  ROW(sizeof(gpio_v2_line_request));
  ROW(offsetof(gpio_v2_line_request, consumer));
  ROW(offsetof(gpio_v2_line_request, config));
  ROW(offsetof(gpio_v2_line_request, num_lines));
  ROW(offsetof(gpio_v2_line_request, event_buffer_size));
  ROW(offsetof(gpio_v2_line_request, fd));
  ROW(sizeof(gpio_v2_line_info));
  ROW(offsetof(gpio_v2_line_info, offset));
  ROW(offsetof(gpio_v2_line_info, flags));
  ROW(offsetof(gpio_v2_line_info, attrs));
  ROW(sizeof(gpio_v2_line_values));
  ROW(sizeof(gpiochip_info));
  ROW(GPIO_GET_CHIPINFO_IOCTL);
  ROW(GPIO_V2_GET_LINEINFO_IOCTL);
  ROW(GPIO_V2_GET_LINE_IOCTL);
  ROW(GPIO_V2_LINE_SET_VALUES_IOCTL);
  ROW(GPIO_V2_LINES_MAX);
  ROW(GPIO_V2_LINE_NUM_ATTRS_MAX);
  ROW(GPIO_MAX_NAME_SIZE);
  ROW(sizeof(std::time_t));
  ROW(sizeof(timespec));
  ROW(alignof(std::int64_t));
  return 0;
}
CPP

g++ -std=c++20 -Wall -Wextra -Werror -o "$WORK/layout-amd64" "$WORK/layout.cpp" || fail "native compile"
"$CROSS_CXX" -std=c++20 -Wall -Wextra -Werror -o "$WORK/layout-arm64" "$WORK/layout.cpp" || fail "cross compile"
file -L "$WORK/layout-arm64" | grep -q 'ARM aarch64' || fail "$CROSS_CXX did not build an arm64 program"
"$WORK/layout-amd64" >"$WORK/amd64.txt"
"${EMU[@]}" "$WORK/layout-arm64" >"$WORK/arm64.txt" || fail "running the arm64 program under ${EMU[*]}"

# GPIO_V2_GET_LINE_IOCTL = _IOWR(0xB4, 0x07, struct gpio_v2_line_request): direction 3 (read|write)
# in bits 30-31, the struct size (592) in bits 16-29, the type 0xB4 and the number 7.
want=$(( (3 << 30) | (592 << 16) | (0xB4 << 8) | 0x07 ))
grep -q "^GPIO_V2_GET_LINE_IOCTL  *$want\$" "$WORK/arm64.txt" ||
  fail "arm64 GPIO_V2_GET_LINE_IOCTL is not $want: $(grep GPIO_V2_GET_LINE_IOCTL "$WORK/arm64.txt")"
diff -u "$WORK/amd64.txt" "$WORK/arm64.txt" >"$WORK/diff.txt" ||
  { cat "$WORK/diff.txt" >&2; fail "the uAPI layout differs between amd64 and arm64"; }
echo "abi_layout: $(wc -l <"$WORK/arm64.txt") sizes, offsets and ioctl numbers equal on amd64 and arm64"
