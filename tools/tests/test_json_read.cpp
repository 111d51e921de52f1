// tools/json_read: what json_string / json_number write reads back exactly, and malformed text is one
// error naming the byte where it goes wrong.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "tools/json.hpp"
#include "tools/json_read.hpp"

namespace tagbench {
namespace test_json_read {
namespace {

TEST(JsonRead, ReadsEveryKindAndKeepsMemberOrder) {
  const JsonValue v = parse_json(R"( {"b": [1, -2.5e3, true, false, null], "a": "x\"y\\u00e9\n", "o": {}} )");
  ASSERT_TRUE(v.is_object());
  ASSERT_EQ(v.members("doc").size(), 3u);
  EXPECT_EQ(v.members("doc")[0].first, "b");
  const auto& b = v.at("b", "doc").array("b");
  ASSERT_EQ(b.size(), 5u);
  EXPECT_EQ(b[0].integer("b0"), 1);
  EXPECT_EQ(b[1].number("b1"), -2500);
  EXPECT_TRUE(b[2].boolean("b2"));
  EXPECT_FALSE(b[3].boolean("b3"));
  EXPECT_TRUE(b[4].is_null());
  EXPECT_EQ(v.at("a", "doc").string("a"), "x\"y\\u00e9\n");
  EXPECT_TRUE(v.at("o", "doc").members("o").empty());
  EXPECT_EQ(parse_json(R"("\u00e9\ud83d\ude00")").string("s"), "\xc3\xa9\xf0\x9f\x98\x80");
}

TEST(JsonRead, NumbersWrittenByJsonNumberReadBackExactly) {
  for (const double x : {0.1, 1.0 / 3, -199.49999999999997, 6.02214076e23, 5e-324, 0.0}) {
    EXPECT_EQ(parse_json(json_number(x)).number("x"), x) << json_number(x);
  }
  EXPECT_EQ(parse_json("18446744073709551615").uint64("seed"), 18446744073709551615ULL);
  EXPECT_EQ(parse_json("9007199254740993").uint64("seed"), 9007199254740993ULL);  // not a double
  EXPECT_THROW(parse_json("-1").uint64("seed"), JsonError);
  EXPECT_THROW(parse_json("1.5").uint64("seed"), JsonError);
  EXPECT_EQ(parse_json(json_string("a\x01\"b")).string("s"), "a\x01\"b");
}

TEST(JsonRead, TypedAccessNamesTheValue) {
  const JsonValue v = parse_json(R"({"id": 2.5, "s": 3})");
  try {
    v.at("id", "frame 3").integer("frame 3: id");
    FAIL();
  } catch (const JsonError& e) {
    EXPECT_STREQ(e.what(), "frame 3: id: expected an integer");
  }
  try {
    v.at("s", "frame 3").string("frame 3: s");
    FAIL();
  } catch (const JsonError& e) {
    EXPECT_STREQ(e.what(), "frame 3: s: expected a string, got a number");
  }
  try {
    v.at("t", "frame 3");
    FAIL();
  } catch (const JsonError& e) {
    EXPECT_STREQ(e.what(), "frame 3: no member 't'");
  }
}

TEST(JsonRead, MalformedTextIsRefusedWithItsPlace) {
  const auto error = [](const std::string& text) {
    try {
      parse_json(text);
    } catch (const JsonError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(error(R"({"a": 1,})"), "at byte 8: expected a member name in double quotes");
  EXPECT_EQ(error("[1 2]"), "at byte 3: expected ',' or ']' in an array");
  EXPECT_EQ(error("{\"a\": 1} x"), "at byte 9: unexpected text after the JSON value");
  EXPECT_EQ(error("01"), "at byte 2: a number with a leading zero");
  EXPECT_EQ(error("1e999"), "at byte 0: a number out of range");
  EXPECT_EQ(error("\"abc"), "at byte 4: a string is not closed");
  EXPECT_EQ(error(R"({"a": 1, "a": 2})"), "at byte 12: member 'a' given twice");
  EXPECT_EQ(error(""), "at byte 0: unexpected end of the text");
  EXPECT_EQ(error("nul"), "at byte 0: unexpected character 'n'");
  EXPECT_EQ(error(std::string(300, '[')), "at byte 201: nested deeper than 200 levels");
  EXPECT_EQ(error("NaN"), "at byte 0: unexpected character 'N'");
}

}  // namespace
}  // namespace test_json_read
}  // namespace tagbench
