#include "stages/import/text_scan.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace sylva::import::text {
namespace {

std::vector<std::string_view> split(std::string_view line, Separator sep) {
  std::vector<std::string_view> out;
  split_fields(line, sep, out);
  return out;
}

// CRLF endings, a UTF-8 BOM and a missing final newline are all plain lines.
TEST(TextScan, LineReaderStripsBomAndCr) {
  LineReader r(
      "\xEF\xBB\xBF"
      "a\r\nb\n\nc");
  std::string_view line;
  std::vector<std::string> got;
  while (r.next(line)) got.emplace_back(line);
  EXPECT_EQ(got, (std::vector<std::string>{"a", "b", "", "c"}));
  EXPECT_EQ(r.line_number(), 4);
}

// The separator follows the first significant line: tab beats comma beats semicolon.
TEST(TextScan, DetectSeparator) {
  EXPECT_EQ(detect_separator("radius (m)\tlength, x"), Separator::kTab);
  EXPECT_EQ(detect_separator("ID, parentID"), Separator::kComma);
  EXPECT_EQ(detect_separator("a;b"), Separator::kSemicolon);
  EXPECT_EQ(detect_separator("1 2  3"), Separator::kWhitespace);
}

// Comma fields are trimmed and unquoted (R's write.csv quotes names); empty fields survive.
TEST(TextScan, SplitFields) {
  EXPECT_EQ(split("\"ID\", parentID ,,x", Separator::kComma),
            (std::vector<std::string_view>{"ID", "parentID", "", "x"}));
  EXPECT_EQ(split("  1 \t 2   3 ", Separator::kWhitespace), (std::vector<std::string_view>{"1", "2", "3"}));
  EXPECT_EQ(split("radius (m)\t2", Separator::kTab), (std::vector<std::string_view>{"radius (m)", "2"}));
}

TEST(TextScan, ParseReal) {
  double v = 0;
  EXPECT_EQ(parse_real("-2.5e-3", v), NumberStatus::kOk);
  EXPECT_EQ(v, -2.5e-3);
  EXPECT_EQ(parse_real("+1", v), NumberStatus::kOk);
  EXPECT_EQ(v, 1.0);
  EXPECT_EQ(parse_real("", v), NumberStatus::kEmpty);
  EXPECT_EQ(parse_real("nan", v), NumberStatus::kNotFinite);
  EXPECT_EQ(parse_real("NaN", v), NumberStatus::kNotFinite);
  EXPECT_EQ(parse_real("-inf", v), NumberStatus::kNotFinite);
  EXPECT_EQ(parse_real("1e999", v), NumberStatus::kNotFinite);
  EXPECT_EQ(parse_real("NA", v), NumberStatus::kNotNumber);
  EXPECT_EQ(parse_real("1.5x", v), NumberStatus::kNotNumber);
  EXPECT_EQ(parse_real("++1", v), NumberStatus::kNotNumber);
  EXPECT_EQ(parse_real("1,5", v), NumberStatus::kNotNumber);
}

// Ids may be written as reals by R ("1e+05") but must be integral.
TEST(TextScan, ParseInteger) {
  std::int64_t v = 0;
  EXPECT_EQ(parse_integer("1e+05", v), NumberStatus::kOk);
  EXPECT_EQ(v, 100000);
  EXPECT_EQ(parse_integer("-1", v), NumberStatus::kOk);
  EXPECT_EQ(v, -1);
  EXPECT_EQ(parse_integer("3.5", v), NumberStatus::kNotNumber);
  EXPECT_EQ(parse_integer("1e300", v), NumberStatus::kNotNumber);
}

TEST(TextScan, QuotedEscapesAndCuts) {
  EXPECT_EQ(text::quoted("ab\x01"), "'ab\\x01'");
  EXPECT_EQ(text::quoted(std::string(50, 'x')), "'" + std::string(40, 'x') + "...'");
}

TEST(TextScan, FormatRealRoundTrips) {
  for (double v : {0.1, 1.0, -3e-7, 253.88724, 1.0 / 3.0, std::numeric_limits<double>::max()}) {
    double back = 0;
    ASSERT_EQ(parse_real(format_real(v), back), NumberStatus::kOk);
    EXPECT_EQ(back, v);
  }
  EXPECT_EQ(format_real(1.0), "1");
  EXPECT_EQ(format_real(0.25), "0.25");
}

}  // namespace
}  // namespace sylva::import::text
