// The JSON pieces the tools write: any bytes a user's path holds still give a valid string literal.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "tools/json.hpp"

namespace test_json {

using tagbench::json_number;
using tagbench::json_numbers;
using tagbench::json_string;

TEST(Json, StringsEscapeWhatJsonForbids) {
  EXPECT_EQ(json_string(""), "\"\"");
  EXPECT_EQ(json_string("plain/path.png"), "\"plain/path.png\"");
  EXPECT_EQ(json_string("a\"b\\c"), "\"a\\\"b\\\\c\"");
  EXPECT_EQ(json_string("\n\t\r\b\f"), "\"\\n\\t\\r\\b\\f\"");
  EXPECT_EQ(json_string(std::string("\x01\x1f\x7f", 3)), "\"\\u0001\\u001f\\u007f\"");
  EXPECT_EQ(json_string(std::string("nul\0here", 8)), "\"nul\\u0000here\"");
}

TEST(Json, ValidUtf8StaysInvalidBytesBecomeReplacementCharacters) {
  EXPECT_EQ(json_string("caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80"), "\"caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80\"");
  const std::string fffd = "\xef\xbf\xbd";
  EXPECT_EQ(json_string("\xff"), "\"" + fffd + "\"");                 // never a lead byte
  EXPECT_EQ(json_string("a\xc3"), "\"a" + fffd + "\"");               // truncated sequence
  EXPECT_EQ(json_string("\xc0\xaf"), "\"" + fffd + fffd + "\"");      // overlong '/'
  EXPECT_EQ(json_string("\xed\xa0\x80"), "\"" + fffd + fffd + fffd + "\"");  // a UTF-16 surrogate
  EXPECT_EQ(json_string("\xf4\x90\x80\x80"), "\"" + fffd + fffd + fffd + fffd + "\"");  // past U+10FFFF
  EXPECT_EQ(json_string("\xe2\x28\xa1"), "\"" + fffd + "(" + fffd + "\"");  // bad continuation
}

TEST(Json, NumbersAreShortestRoundTripAndNullWhenNotFinite) {
  EXPECT_EQ(json_number(0.166), "0.166");
  EXPECT_EQ(json_number(1), "1");
  EXPECT_EQ(json_number(-2.5e-7), "-2.5e-07");
  const double third = 1.0 / 3;
  EXPECT_EQ(std::stod(json_number(third)), third);
  EXPECT_EQ(json_number(std::nan("")), "null");
  EXPECT_EQ(json_number(std::numeric_limits<double>::infinity()), "null");
  EXPECT_EQ(json_numbers({}), "[]");
  EXPECT_EQ(json_numbers({0, 0.5, 12.5}), "[0, 0.5, 12.5]");
}

}  // namespace test_json
