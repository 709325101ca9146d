#include <gtest/gtest.h>

#include "polyaxis/core/check.h"
#include "polyaxis/core/result.h"

namespace polyaxis::core {
namespace {

Result<int> half(int x) {
  if (x % 2 != 0) return make_error(ErrorCode::kUsage, "odd");
  return x / 2;
}

TEST(Result, HoldsValueOrError) {
  auto a = half(4);
  ASSERT_TRUE(a.ok());
  EXPECT_EQ(a.value(), 2);
  auto b = half(3);
  ASSERT_FALSE(b.ok());
  EXPECT_EQ(b.error().code, ErrorCode::kUsage);
  EXPECT_EQ(b.error().message, "odd");
}

TEST(Result, ErrorCodesAreTheExitCodes) {
  EXPECT_EQ(static_cast<int>(ErrorCode::kInternal), 1);
  EXPECT_EQ(static_cast<int>(ErrorCode::kUsage), 2);
  EXPECT_EQ(static_cast<int>(ErrorCode::kInvalidInput), 3);
  EXPECT_EQ(static_cast<int>(ErrorCode::kInfeasible), 4);
  EXPECT_EQ(static_cast<int>(ErrorCode::kMachineLimit), 5);
  EXPECT_EQ(static_cast<int>(ErrorCode::kOutput), 6);
}

TEST(Check, ThrowsWithFileAndLine) {
  try {
    POLYAXIS_CHECK(1 + 1 == 3, "arithmetic");
    FAIL() << "no throw";
  } catch (const InvariantError& e) {
    EXPECT_NE(std::string(e.what()).find("test_result.cpp"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("arithmetic"), std::string::npos);
  }
}

}  // namespace
}  // namespace polyaxis::core
