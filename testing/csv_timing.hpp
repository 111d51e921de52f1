#pragma once
// A result CSV without its timing columns (found by their header names "ms" and "ms_median", wherever
// they are): what must be identical between runs with the same settings. Plain CSV (no quoted commas).
#include <cstddef>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace tagbench::testing {

inline std::string csv_without_timing(const std::string& csv) {
  const auto split = [](const std::string& line) {
    std::vector<std::string> f;
    std::string cur;
    for (const char c : line) {
      if (c == ',') {
        f.push_back(cur);
        cur.clear();
      } else {
        cur += c;
      }
    }
    f.push_back(cur);
    return f;
  };
  std::istringstream in(csv);
  std::string line, out;
  std::set<std::size_t> drop;
  for (bool header = true; std::getline(in, line); header = false) {
    const auto f = split(line);
    if (header)
      for (std::size_t i = 0; i < f.size(); ++i)
        if (f[i] == "ms" || f[i] == "ms_median") drop.insert(i);
    bool first = true;
    for (std::size_t i = 0; i < f.size(); ++i) {
      if (drop.count(i)) continue;
      if (!first) out += ',';
      out += f[i];
      first = false;
    }
    out += '\n';
  }
  return out;
}

}  // namespace tagbench::testing
