// The CSV and scene-file numbers and fields: the digits each caller asks for, empty cells for
// missing values, quoting only where a field needs it.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "tools/format.hpp"

namespace test_format {

using tagbench::csv_field;
using tagbench::exact_number;
using tagbench::format_cell;
using tagbench::format_number;

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
}  // namespace

TEST(Format, NumbersFollowTheCallersPrintfFormat) {
  EXPECT_EQ(format_number(0.1234567, "%.6g"), "0.123457");
  EXPECT_EQ(format_number(1234567.0, "%.6g"), "1.23457e+06");
  EXPECT_EQ(format_number(2.5, "%.4f"), "2.5000");
  EXPECT_EQ(format_number(0.125, "%.1f"), "0.1");  // printf's rounding: 0.125 is below 0.15 in binary
  EXPECT_EQ(format_number(12.0, "%.0f"), "12");
  EXPECT_EQ(format_number(3.5e-7, "%.6e"), "3.500000e-07");
  // Values that are not finite are printed as printf prints them.
  EXPECT_EQ(format_number(kNaN, "%.6g"), "nan");
  EXPECT_EQ(format_number(-kInf, "%.6g"), "-inf");
}

TEST(Format, ExactNumbersReadBackToTheSameDouble) {
  for (const double v : {0.1, 1.0 / 3, -2.0e-300, 123456789.123456789, 1.0}) {
    const std::string s = exact_number(v);
    EXPECT_EQ(std::stod(s), v) << s;
  }
  EXPECT_EQ(exact_number(0.1), "0.10000000000000001");
  EXPECT_EQ(exact_number(2.0), "2");
}

TEST(Format, CellsAreEmptyForMissingValues) {
  EXPECT_EQ(format_cell(kNaN, "%.6g"), "");
  EXPECT_EQ(format_cell(kInf, "%.4f"), "");
  EXPECT_EQ(format_cell(-kInf, "%.10g"), "");
  EXPECT_EQ(format_cell(0.0, "%.10g"), "0");
  EXPECT_EQ(format_cell(1.0 / 3, "%.10g"), "0.3333333333");
  EXPECT_EQ(format_cell(-0.5, "%.4f"), "-0.5000");
}

TEST(Format, CsvFieldsAreQuotedOnlyWhenTheyNeedIt) {
  EXPECT_EQ(csv_field(""), "");
  EXPECT_EQ(csv_field("frames/a.png"), "frames/a.png");
  EXPECT_EQ(csv_field("with space"), "with space");
  EXPECT_EQ(csv_field("a,b"), "\"a,b\"");
  EXPECT_EQ(csv_field("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(csv_field("two\nlines"), "\"two\nlines\"");
  EXPECT_EQ(csv_field("cr\rhere"), "\"cr\rhere\"");
  EXPECT_EQ(csv_field("\""), "\"\"\"\"");
}

}  // namespace test_format
