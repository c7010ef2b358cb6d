// Fixing glibc's mmap threshold (heap.hpp).
#include "m2mlat/core/heap.hpp"

#include <cstdlib>  // defines __GLIBC__ with the GNU C library

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace m2mlat::core {

void return_large_blocks_when_freed() {
#if defined(__GLIBC__)
  constexpr int kMmapThreshold = 1 << 20;  // bytes; setting it also turns the dynamic raise off
  mallopt(M_MMAP_THRESHOLD, kMmapThreshold);
#endif
}

}  // namespace m2mlat::core
