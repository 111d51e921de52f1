#pragma once
// Pieces of the JSON the tools write (sidecars, `tagbench detect`), so that any path or name a user
// hands us still gives a valid document.
#include <string>
#include <vector>

namespace tagbench {

// A JSON string literal: quotes, backslashes and control characters escaped; bytes that are not
// valid UTF-8 (a file name on Linux is any bytes) become U+FFFD.
std::string json_string(const std::string& s);

// The shortest decimal that reads back to the same double; null for NaN and infinities.
std::string json_number(double v);

// [a, b, ...] of json_number.
std::string json_numbers(const std::vector<double>& v);

}  // namespace tagbench
