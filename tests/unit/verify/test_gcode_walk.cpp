// The G-code reader's number parsing (verify/gcode_walk.h, read_number): the same value, end and
// error as std::from_chars on every string the tokenizer can hand it, and on the numbers a
// program is made of.
#include <gtest/gtest.h>

#include <bit>
#include <charconv>
#include <cstring>
#include <random>
#include <string>

#include "verify/gcode_walk.h"

namespace polyaxis::verify::detail {
namespace {

void expect_as_from_chars(const std::string& s) {
  double mine = 12345.0, theirs = 12345.0;
  const auto a = read_number(s.data(), s.data() + s.size(), mine);
  const auto b = std::from_chars(s.data(), s.data() + s.size(), theirs);
  ASSERT_EQ(a.ec, b.ec) << "'" << s << "'";
  ASSERT_EQ(a.ptr, b.ptr) << "'" << s << "'";
  ASSERT_EQ(std::bit_cast<std::uint64_t>(mine), std::bit_cast<std::uint64_t>(theirs)) << "'" << s << "': " << mine << " against " << theirs;
}

TEST(ReadNumber, AgreesWithFromCharsOnRandomText) {
  std::mt19937 rng(5);
  const std::string alphabet = "-0123456789.";
  std::uniform_int_distribution<std::size_t> length(0, 26), pick(0, alphabet.size() - 1), digit(1, 10);
  for (int n = 0; n < 300000; ++n) {
    std::string s;
    const std::size_t len = length(rng);
    // Mostly digit strings with a point, as a program writes them; some with any character anywhere.
    const bool wild = n % 4 == 0;
    for (std::size_t k = 0; k < len; ++k) s += wild ? alphabet[pick(rng)] : alphabet[digit(rng)];
    if (!wild && len > 2) {
      s[std::uniform_int_distribution<std::size_t>(0, len - 1)(rng)] = '.';
      if (n % 3 == 0) s[0] = '-';
    }
    expect_as_from_chars(s);
  }
}

TEST(ReadNumber, AgreesWithFromCharsOnProgramNumbers) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-2000.0, 2000.0);
  char buf[64];
  for (int n = 0; n < 200000; ++n) {
    const double v = u(rng);
    for (const int decimals : {0, 1, 3, 6, 9, 12, 15, 17}) {
      const int len = std::snprintf(buf, sizeof buf, "%.*f", decimals, n % 5 == 0 ? v * 1e-6 : v);
      expect_as_from_chars(std::string(buf, static_cast<std::size_t>(len)));
    }
  }
  for (const char* s : {"0", "-0", "0.", ".0", ".", "-", "-.", "00012.50", "1.7976931348623157", "999999999999999", "9999999999999999",
                        "0.0000000000000000000001", "0.00000000000000000000001", "123456789012345.6", "1..2", "-1-2", "4503599627370497"}) {
    expect_as_from_chars(s);
  }
}

}  // namespace
}  // namespace polyaxis::verify::detail
