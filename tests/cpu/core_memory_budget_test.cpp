#include "core/memory_budget.h"

#include <gtest/gtest.h>

namespace hw {
namespace {

TEST(MemoryBudget, ParsesSizesWithBinaryUnits) {
  EXPECT_EQ(*parseMemorySize("4G"), 4ull << 30);
  EXPECT_EQ(*parseMemorySize("512M"), 512ull << 20);
  EXPECT_EQ(*parseMemorySize("1.5GiB"), 3ull << 29);
  EXPECT_EQ(*parseMemorySize("800mb"), 800ull << 20);
  EXPECT_EQ(*parseMemorySize("2T"), 2ull << 40);
  EXPECT_EQ(*parseMemorySize("65536K"), 64ull << 20);
}

TEST(MemoryBudget, RefusesSizesWithoutUnitOrOutOfRange) {
  for (const char* bad : {"", "4", "G", "-1G", "0G", "4X", "4 G", "nanG", "infG", "100K", "1e20T"}) {
    auto r = parseMemorySize(bad);
    EXPECT_FALSE(r) << bad;
    if (!r) {
      EXPECT_NE(r.error().message.find(bad), std::string::npos) << r.error().message;
    }
  }
}

TEST(MemoryBudget, DefaultIsFortyPercentOfTheLeastLimit) {
  MemoryLimits m;
  m.physicalBytes = 10ull << 30;
  EXPECT_EQ(defaultMemoryBudget(m), (10ull << 30) / 10 * 4);
  m.addressSpaceBytes = 4000000ull * 1024;  // ulimit -v 4000000
  EXPECT_EQ(defaultMemoryBudget(m), 4000000ull * 1024 / 10 * 4);
  m.cgroupBytes = 1ull << 30;
  EXPECT_EQ(defaultMemoryBudget(m), (1ull << 30) / 10 * 4);
  m.cgroupBytes = 100ull << 20;  // floor of 256 MiB
  EXPECT_EQ(defaultMemoryBudget(m), 256ull << 20);
}

TEST(MemoryBudget, RefusalNamesItemTotalAndBudget) {
  EXPECT_TRUE(checkMemoryCharge(1ull << 30, 1ull << 30, 2ull << 30, "x", "h"));
  auto r = checkMemoryCharge(1ull << 30, 3ull << 29, 2ull << 30, "t.png: texture 16384x16384 decoded",
                             "--max-memory");
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().message,
            "t.png: texture 16384x16384 decoded (1.5 GiB; 2.5 GiB with what the run holds "
            "already), over the 2.0 GiB memory budget; --max-memory");
  // No overflow when the item alone exceeds everything.
  EXPECT_FALSE(checkMemoryCharge(1, ~0ull, 2ull << 30, "x", ""));
}

TEST(MemoryBudget, ScopeHoldsChargesUntilTheReservationGoes) {
  setMemoryBudget(100ull << 20);
  const std::uint64_t before = memoryCharged();
  std::shared_ptr<MemoryReservation> kept;
  {
    MemoryScope scope;
    ASSERT_TRUE(chargeMemory(60ull << 20, "a", ""));
    EXPECT_FALSE(chargeMemory(60ull << 20, "b", ""));
    EXPECT_NE(scope.refused().find("b ("), std::string::npos);
    EXPECT_EQ(scope.charged(), 60ull << 20);
    kept = scope.keep();
  }
  EXPECT_EQ(memoryCharged(), before + (60ull << 20));
  kept.reset();
  EXPECT_EQ(memoryCharged(), before);
  {
    MemoryScope scope;
    ASSERT_TRUE(chargeMemory(90ull << 20, "c", ""));
  }  // not kept: given back
  EXPECT_EQ(memoryCharged(), before);
  setMemoryBudget(0);
}

}  // namespace
}  // namespace hw
