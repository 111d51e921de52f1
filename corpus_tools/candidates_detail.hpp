#pragma once
// Shared by the candidate files only: an index field made safe for the tab-separated index.
#include <string>

namespace tagbench::corpus::detail {

// Tabs and line breaks become spaces (the index is one row a line, tab-separated).
inline std::string clean(std::string s) {
  for (char& c : s)
    if (c == '\t' || c == '\n' || c == '\r') c = ' ';
  return s;
}

}  // namespace tagbench::corpus::detail
