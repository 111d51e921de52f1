#include "tools/format.hpp"

#include <cmath>
#include <cstdio>

namespace tagbench {

std::string format_number(double v, const char* printf_format) {
  char buf[64];
  std::snprintf(buf, sizeof buf, printf_format, v);
  return buf;
}

std::string exact_number(double v) { return format_number(v, "%.17g"); }

std::string format_cell(double v, const char* printf_format) {
  return std::isfinite(v) ? format_number(v, printf_format) : std::string();
}

std::string csv_field(std::string_view s) {
  if (s.find_first_of(",\"\r\n") == std::string_view::npos) return std::string(s);
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + '"';
}

}  // namespace tagbench
