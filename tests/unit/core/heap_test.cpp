// core::return_large_blocks_when_freed: after a large block was freed, a block of a few MiB is still
// mmapped (and so goes back to the system when freed), as glibc's dynamic threshold would not have it.
#include "m2mlat/core/heap.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace m2mlat::core {
namespace {

#if defined(__SANITIZE_ADDRESS__)
constexpr bool kOwnAllocator = true;  // the sanitizer's malloc: no glibc statistics to read
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kOwnAllocator = true;
#else
constexpr bool kOwnAllocator = false;
#endif
#else
constexpr bool kOwnAllocator = false;
#endif

TEST(Heap, BlocksOfAMebibyteOrMoreAreMmappedAfterALargeFree) {
#if defined(__GLIBC__)
  if (kOwnAllocator) GTEST_SKIP() << "another allocator than glibc's";
  return_large_blocks_when_freed();
  // A 16 MiB block freed: glibc alone would raise its threshold to 16 MiB here.
  void* large = std::malloc(16u << 20);
  ASSERT_NE(large, nullptr);
  std::memset(large, 1, 16u << 20);
  std::free(large);
  const auto mmapped_before = mallinfo2().hblkhd;  // bytes in mmapped blocks
  void* block = std::malloc(4u << 20);
  ASSERT_NE(block, nullptr);
  EXPECT_GE(mallinfo2().hblkhd, mmapped_before + (4u << 20));
  std::free(block);
  EXPECT_EQ(mallinfo2().hblkhd, mmapped_before);  // returned when freed
#else
  GTEST_SKIP() << "not the GNU C library";
#endif
}

}  // namespace
}  // namespace m2mlat::core
