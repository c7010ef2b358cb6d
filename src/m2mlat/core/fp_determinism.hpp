// Floating-point rules the simulator and the bootstrap rely on to give the same output on every
// platform.
//
// The simulator uses doubles for rates, angles and random variates (never for timestamps), the
// bootstrap for the order statistics it draws (stats/order_statistics.cpp). Their output is
// identical everywhere only if every double operation is a single IEEE-754 binary64 operation
// rounded to nearest: no x87 excess precision, and no a * b + c contracted into a fused
// multiply-add, which GCC and Clang both do by default wherever the CPU has one (aarch64 always;
// x86-64 with -march=haswell and later), giving different bits from a CPU without. The pragmas
// below turn contraction off from the include to the end of the translation unit. Include this in
// every such .cpp that does double arithmetic, before its own code. Transcendental functions come
// from portable_math.hpp, not <cmath>, for the same reason.
#pragma once

#include <cfloat>
#include <limits>

static_assert(std::numeric_limits<double>::is_iec559,
              "the simulator and the bootstrap need IEEE-754 doubles");
static_assert(FLT_EVAL_METHOD == 0,
              "the simulator and the bootstrap need doubles evaluated in double precision (SSE2, not x87)");

#if defined(__clang__)
#pragma clang fp contract(off)
#elif defined(__GNUC__)
#pragma GCC optimize("fp-contract=off")
#endif
