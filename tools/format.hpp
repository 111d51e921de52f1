#pragma once
// Numbers and text fields for the CSV, scene and report files the programs write. The printf
// format of each column is part of that file's definition (its bytes must not change between
// versions), so callers name it; nothing here picks a precision for them.
#include <string>
#include <string_view>

namespace tagbench {

// `v` through a printf format for one double: "%.6g", "%.17g" (reads back exactly), "%.4f".
std::string format_number(double v, const char* printf_format);

// "%.17g": enough digits to read back as the same double, for numbers another
// program reads (POV-Ray scene files, cache keys).
std::string exact_number(double v);

// format_number, but empty for NaN and infinities: a CSV cell that has no value.
std::string format_cell(double v, const char* printf_format);

// A CSV text field: as it is, or quoted (RFC 4180: in double quotes, quotes doubled) when it holds
// a comma, a double quote or a line break.
std::string csv_field(std::string_view s);

}  // namespace tagbench
