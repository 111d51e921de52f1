#include "tools/json_read.hpp"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>

namespace tagbench {

namespace {

const char* kind_name(JsonValue::Kind k) {
  switch (k) {
    case JsonValue::Kind::kNull: return "null";
    case JsonValue::Kind::kBool: return "a boolean";
    case JsonValue::Kind::kNumber: return "a number";
    case JsonValue::Kind::kString: return "a string";
    case JsonValue::Kind::kArray: return "an array";
    case JsonValue::Kind::kObject: return "an object";
  }
  return "?";
}

[[noreturn]] void wrong_kind(const std::string& what, const char* expected, JsonValue::Kind got) {
  throw JsonError(what + ": expected " + expected + ", got " + kind_name(got));
}

class Parser {
 public:
  explicit Parser(std::string_view t) : t_(t) {}

  JsonValue document() {
    space();
    JsonValue v = value(0);
    space();
    if (i_ != t_.size()) fail("unexpected text after the JSON value");
    return v;
  }

 private:
  [[noreturn]] void fail(const std::string& why) const { throw JsonError("at byte " + std::to_string(i_) + ": " + why); }

  void space() {
    while (i_ < t_.size() && (t_[i_] == ' ' || t_[i_] == '\t' || t_[i_] == '\n' || t_[i_] == '\r')) ++i_;
  }

  bool literal(std::string_view word) {
    if (t_.substr(i_, word.size()) != word) return false;
    i_ += word.size();
    return true;
  }

  JsonValue value(int depth) {
    if (depth > 200) fail("nested deeper than 200 levels");
    if (i_ >= t_.size()) fail("unexpected end of the text");
    const char c = t_[i_];
    if (c == '{') return object(depth);
    if (c == '[') return array(depth);
    if (c == '"') return JsonValue::make_string(string());
    if (literal("true")) return JsonValue::make_bool(true);
    if (literal("false")) return JsonValue::make_bool(false);
    if (literal("null")) return JsonValue::make_null();
    if (c == '-' || (c >= '0' && c <= '9')) {
      const std::size_t start = i_;
      const double v = number();
      return JsonValue::make_number(v, std::string(t_.substr(start, i_ - start)));
    }
    fail(std::string("unexpected character '") + (c >= 0x20 && c < 0x7f ? std::string(1, c) : "?") + "'");
  }

  JsonValue object(int depth) {
    ++i_;
    std::vector<std::pair<std::string, JsonValue>> m;
    space();
    if (i_ < t_.size() && t_[i_] == '}') {
      ++i_;
      return JsonValue::make_object(std::move(m));
    }
    while (true) {
      space();
      if (i_ >= t_.size() || t_[i_] != '"') fail("expected a member name in double quotes");
      std::string key = string();
      for (const auto& kv : m)
        if (kv.first == key) fail("member '" + key + "' given twice");
      space();
      if (i_ >= t_.size() || t_[i_] != ':') fail("expected ':' after a member name");
      ++i_;
      space();
      m.emplace_back(std::move(key), value(depth + 1));
      space();
      if (i_ < t_.size() && t_[i_] == ',') {
        ++i_;
        continue;
      }
      if (i_ < t_.size() && t_[i_] == '}') {
        ++i_;
        return JsonValue::make_object(std::move(m));
      }
      fail("expected ',' or '}' in an object");
    }
  }

  JsonValue array(int depth) {
    ++i_;
    std::vector<JsonValue> v;
    space();
    if (i_ < t_.size() && t_[i_] == ']') {
      ++i_;
      return JsonValue::make_array(std::move(v));
    }
    while (true) {
      space();
      v.push_back(value(depth + 1));
      space();
      if (i_ < t_.size() && t_[i_] == ',') {
        ++i_;
        continue;
      }
      if (i_ < t_.size() && t_[i_] == ']') {
        ++i_;
        return JsonValue::make_array(std::move(v));
      }
      fail("expected ',' or ']' in an array");
    }
  }

  unsigned hex4() {
    if (i_ + 4 > t_.size()) fail("a \\u escape needs four hex digits");
    unsigned v = 0;
    for (int k = 0; k < 4; ++k) {
      const char c = t_[i_++];
      v <<= 4;
      if (c >= '0' && c <= '9') v |= static_cast<unsigned>(c - '0');
      else if (c >= 'a' && c <= 'f') v |= static_cast<unsigned>(c - 'a' + 10);
      else if (c >= 'A' && c <= 'F') v |= static_cast<unsigned>(c - 'A' + 10);
      else fail("a \\u escape needs four hex digits");
    }
    return v;
  }

  static void utf8(std::string& out, std::uint32_t cp) {
    if (cp < 0x80) {
      out += static_cast<char>(cp);
    } else if (cp < 0x800) {
      out += static_cast<char>(0xc0 | (cp >> 6));
      out += static_cast<char>(0x80 | (cp & 0x3f));
    } else if (cp < 0x10000) {
      out += static_cast<char>(0xe0 | (cp >> 12));
      out += static_cast<char>(0x80 | ((cp >> 6) & 0x3f));
      out += static_cast<char>(0x80 | (cp & 0x3f));
    } else {
      out += static_cast<char>(0xf0 | (cp >> 18));
      out += static_cast<char>(0x80 | ((cp >> 12) & 0x3f));
      out += static_cast<char>(0x80 | ((cp >> 6) & 0x3f));
      out += static_cast<char>(0x80 | (cp & 0x3f));
    }
  }

  std::string string() {
    ++i_;  // the opening quote
    std::string out;
    while (true) {
      if (i_ >= t_.size()) fail("a string is not closed");
      const char c = t_[i_++];
      if (c == '"') return out;
      if (static_cast<unsigned char>(c) < 0x20) fail("a control character inside a string");
      if (c != '\\') {
        out += c;
        continue;
      }
      if (i_ >= t_.size()) fail("a string is not closed");
      switch (t_[i_++]) {
        case '"': out += '"'; break;
        case '\\': out += '\\'; break;
        case '/': out += '/'; break;
        case 'b': out += '\b'; break;
        case 'f': out += '\f'; break;
        case 'n': out += '\n'; break;
        case 'r': out += '\r'; break;
        case 't': out += '\t'; break;
        case 'u': {
          std::uint32_t cp = hex4();
          if (cp >= 0xd800 && cp < 0xdc00 && t_.substr(i_, 2) == "\\u") {
            i_ += 2;
            const unsigned lo = hex4();
            if (lo >= 0xdc00 && lo < 0xe000) cp = 0x10000 + ((cp - 0xd800) << 10) + (lo - 0xdc00);
            else cp = 0xfffd;
          } else if (cp >= 0xd800 && cp < 0xe000) {
            cp = 0xfffd;  // a lone surrogate
          }
          utf8(out, cp);
          break;
        }
        default: fail("an unknown escape in a string");
      }
    }
  }

  double number() {
    const std::size_t start = i_;
    if (t_[i_] == '-') ++i_;
    const auto digits = [&] {
      const std::size_t s = i_;
      while (i_ < t_.size() && t_[i_] >= '0' && t_[i_] <= '9') ++i_;
      return i_ - s;
    };
    const std::size_t int_start = i_;
    if (digits() == 0) fail("a number needs digits");
    if (t_[int_start] == '0' && i_ - int_start > 1) fail("a number with a leading zero");
    if (i_ < t_.size() && t_[i_] == '.') {
      ++i_;
      if (digits() == 0) fail("a number needs digits after '.'");
    }
    if (i_ < t_.size() && (t_[i_] == 'e' || t_[i_] == 'E')) {
      ++i_;
      if (i_ < t_.size() && (t_[i_] == '+' || t_[i_] == '-')) ++i_;
      if (digits() == 0) fail("a number needs digits in its exponent");
    }
    double v = 0;
    const auto r = std::from_chars(t_.data() + start, t_.data() + i_, v);
    if (r.ec != std::errc() || !std::isfinite(v)) {
      i_ = start;
      fail("a number out of range");
    }
    return v;
  }

  std::string_view t_;
  std::size_t i_ = 0;
};

}  // namespace

JsonValue JsonValue::make_bool(bool b) {
  JsonValue v;
  v.kind_ = Kind::kBool;
  v.bool_ = b;
  return v;
}
JsonValue JsonValue::make_number(double x, std::string literal) {
  JsonValue v;
  v.kind_ = Kind::kNumber;
  v.number_ = x;
  v.string_ = std::move(literal);
  return v;
}
JsonValue JsonValue::make_string(std::string s) {
  JsonValue v;
  v.kind_ = Kind::kString;
  v.string_ = std::move(s);
  return v;
}
JsonValue JsonValue::make_array(std::vector<JsonValue> a) {
  JsonValue v;
  v.kind_ = Kind::kArray;
  v.array_ = std::move(a);
  return v;
}
JsonValue JsonValue::make_object(std::vector<std::pair<std::string, JsonValue>> m) {
  JsonValue v;
  v.kind_ = Kind::kObject;
  v.object_ = std::move(m);
  return v;
}

double JsonValue::number(const std::string& what) const {
  if (kind_ != Kind::kNumber) wrong_kind(what, "a number", kind_);
  return number_;
}

int JsonValue::integer(const std::string& what) const {
  const double x = number(what);
  if (x != std::floor(x) || x < std::numeric_limits<int>::min() || x > std::numeric_limits<int>::max())
    throw JsonError(what + ": expected an integer");
  return static_cast<int>(x);
}

std::uint64_t JsonValue::uint64(const std::string& what) const {
  number(what);
  std::uint64_t v = 0;
  const auto r = std::from_chars(string_.data(), string_.data() + string_.size(), v);
  if (string_.empty() || r.ec != std::errc() || r.ptr != string_.data() + string_.size())
    throw JsonError(what + ": expected a whole number from 0 to 2^64 - 1");
  return v;
}

bool JsonValue::boolean(const std::string& what) const {
  if (kind_ != Kind::kBool) wrong_kind(what, "true or false", kind_);
  return bool_;
}

const std::string& JsonValue::string(const std::string& what) const {
  if (kind_ != Kind::kString) wrong_kind(what, "a string", kind_);
  return string_;
}

const std::vector<JsonValue>& JsonValue::array(const std::string& what) const {
  if (kind_ != Kind::kArray) wrong_kind(what, "an array", kind_);
  return array_;
}

const std::vector<std::pair<std::string, JsonValue>>& JsonValue::members(const std::string& what) const {
  if (kind_ != Kind::kObject) wrong_kind(what, "an object", kind_);
  return object_;
}

const JsonValue* JsonValue::find(const std::string& key) const {
  if (kind_ != Kind::kObject) return nullptr;
  for (const auto& kv : object_)
    if (kv.first == key) return &kv.second;
  return nullptr;
}

const JsonValue& JsonValue::at(const std::string& key, const std::string& what) const {
  members(what);
  if (const JsonValue* v = find(key)) return *v;
  throw JsonError(what + ": no member '" + key + "'");
}

JsonValue parse_json(std::string_view text) { return Parser(text).document(); }

}  // namespace tagbench
