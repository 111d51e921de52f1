#pragma once
// Reading JSON (RFC 8259): the datasets' truth.json and the detection lines external detectors print
// (bench/dataset, bench/score). A plain value tree; numbers are doubles read exactly as strtod would
// (std::from_chars), so a number json_number wrote reads back as the same double.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace tagbench {

class JsonValue {
 public:
  enum class Kind { kNull, kBool, kNumber, kString, kArray, kObject };

  JsonValue() = default;
  Kind kind() const { return kind_; }
  bool is_null() const { return kind_ == Kind::kNull; }
  bool is_number() const { return kind_ == Kind::kNumber; }
  bool is_string() const { return kind_ == Kind::kString; }
  bool is_array() const { return kind_ == Kind::kArray; }
  bool is_object() const { return kind_ == Kind::kObject; }

  // Typed access; throws JsonError "WHAT: expected a number" (etc.) naming `what`, the caller's name
  // for the value ("frame 3: t").
  double number(const std::string& what) const;
  int integer(const std::string& what) const;  // a number with no fraction, within int
  // A non-negative integer read from the number's own digits (a double holds only 53 bits): seeds.
  std::uint64_t uint64(const std::string& what) const;
  bool boolean(const std::string& what) const;
  const std::string& string(const std::string& what) const;
  const std::vector<JsonValue>& array(const std::string& what) const;
  // A member of an object; throws "WHAT: no member 'key'" when missing (find: nullptr).
  const JsonValue& at(const std::string& key, const std::string& what) const;
  const JsonValue* find(const std::string& key) const;
  const std::vector<std::pair<std::string, JsonValue>>& members(const std::string& what) const;

  static JsonValue make_null() { return {}; }
  static JsonValue make_bool(bool b);
  static JsonValue make_number(double v, std::string literal = {});
  static JsonValue make_string(std::string s);
  static JsonValue make_array(std::vector<JsonValue> v);
  static JsonValue make_object(std::vector<std::pair<std::string, JsonValue>> m);

 private:
  Kind kind_ = Kind::kNull;
  bool bool_ = false;
  double number_ = 0;
  std::string string_;  // a string's value; a number's literal text
  std::vector<JsonValue> array_;
  std::vector<std::pair<std::string, JsonValue>> object_;  // in document order; a repeated key is an error
};

struct JsonError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// One JSON document (surrounding white space allowed, nothing else after it). Throws JsonError
// "at byte N: what is wrong". Nesting deeper than 200 levels is refused (no stack overflow on hostile input).
JsonValue parse_json(std::string_view text);

}  // namespace tagbench
