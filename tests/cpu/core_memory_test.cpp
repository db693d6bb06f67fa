// core/memory.h: the resident size the soak reads, and returnFreeHeapPages,
// which the walk calls at every keyframe step and before each 500-frame
// resident sample (docs/results/2026-12-03/soak/README.md).
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <vector>

#include "core/memory.h"

namespace hw {
namespace {

TEST(Memory, ResidentKiBIsPositiveOnLinux) {
#if defined(__linux__)
  EXPECT_GT(residentKiB(), 0);
#else
  GTEST_SKIP() << "no /proc/self/statm";
#endif
}

// glibc's allocator is what this tests: under AddressSanitizer malloc is
// ASan's and malloc_trim returns nothing, so the sanitizer build leaves the
// test out (the release build in CI runs it).
#if defined(__SANITIZE_ADDRESS__)
#define HW_GLIBC_MALLOC 0
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define HW_GLIBC_MALLOC 0
#endif
#endif
#ifndef HW_GLIBC_MALLOC
#define HW_GLIBC_MALLOC 1
#endif

#if HW_GLIBC_MALLOC
// Freed blocks in the middle of the heap (a live block above them, so glibc's
// automatic trim of the heap top cannot return them) stay resident until
// returnFreeHeapPages: the frame-end excursions the soak saw.
TEST(Memory, ReturnFreeHeapPagesGivesBackFreedPagesInsideTheHeap) {
#if !defined(__GLIBC__) || !defined(__linux__)
  GTEST_SKIP() << "glibc malloc_trim and /proc/self/statm only";
#else
  fixMallocMmapThreshold();  // as the program: blocks below 128 KiB come from the heap
  constexpr std::size_t kBlock = 32 * 1024, kBlocks = 512;  // 16 MiB
  std::vector<void*> blocks;
  blocks.reserve(kBlocks);
  for (std::size_t i = 0; i < kBlocks; ++i) {
    void* p = std::malloc(kBlock);
    ASSERT_NE(p, nullptr);
    std::memset(p, static_cast<int>(i & 0xff) | 1, kBlock);  // resident now
    blocks.push_back(p);
  }
  // Live, above the blocks: as large as one, so no free chunk below can hold
  // it and it comes from the heap top.
  void* pin = std::malloc(kBlock);
  ASSERT_NE(pin, nullptr);
  std::memset(pin, 1, kBlock);
  volatile unsigned sum = 0;
  for (void* p : blocks) sum = sum + static_cast<unsigned char*>(p)[kBlock / 2];
  EXPECT_NE(sum, 0u);
  const long long live = residentKiB();
  for (void* p : blocks) std::free(p);
  const long long freed = residentKiB();
  returnFreeHeapPages();
  const long long trimmed = residentKiB();
  std::free(pin);
  ASSERT_GT(live, 0);
  // Freeing alone returns little (the free space is not at the heap top);
  // the trim returns most of the 16 MiB.
  EXPECT_GT(freed, live - 4 * 1024) << "live " << live << " KiB, after free " << freed;
  EXPECT_LT(trimmed, freed - 12 * 1024) << "after free " << freed << " KiB, after trim " << trimmed;
#endif
}
#endif  // HW_GLIBC_MALLOC

}  // namespace
}  // namespace hw
