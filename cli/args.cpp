#include "cli/args.hpp"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <filesystem>
#include <cmath>

namespace tagbench::cli {

std::string why_not_directory(const std::string& p) {
  std::error_code ec;
  return std::filesystem::exists(p, ec) ? "not a directory" : "no such directory";
}

std::string one_line(const std::string& s, bool escape) {
  std::string out;
  for (const char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    if (c >= 0x20 && c != 0x7f) {
      out += ch;
    } else if (!escape) {
      if (!out.empty() && out.back() != ' ') out += ' ';
    } else {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", c);
      out += buf;
    }
  }
  while (!out.empty() && out.back() == ' ') out.pop_back();
  return out;
}

Args::Args(const std::vector<std::string>& argv, const std::vector<OptionSpec>& specs) {
  const auto find = [&](const std::string& name, bool is_short) -> const OptionSpec* {
    for (const auto& s : specs)
      if ((is_short ? s.short_name : s.name) == name && !name.empty()) return &s;
    return nullptr;
  };
  bool only_positionals = false;
  for (std::size_t i = 0; i < argv.size(); ++i) {
    const std::string& a = argv[i];
    if (only_positionals || a.size() < 2 || a[0] != '-') {
      positionals_.push_back(a);
      continue;
    }
    if (a == "--") {
      only_positionals = true;
      continue;
    }
    const bool is_long = a.rfind("--", 0) == 0;
    std::string name = a.substr(is_long ? 2 : 1);
    std::optional<std::string> inline_value;
    if (const auto eq = name.find('='); is_long && eq != std::string::npos) {
      inline_value = name.substr(eq + 1);
      name = name.substr(0, eq);
    }
    const OptionSpec* spec = find(name, !is_long);
    if (!spec) throw UsageError("unknown option '" + a + "'");
    const std::string shown = "--" + spec->name;
    auto& slot = values_[spec->name];
    if (!slot.empty() && !spec->repeatable) throw UsageError(shown + " given more than once");
    if (!spec->takes_value) {
      if (inline_value) throw UsageError(shown + " takes no value");
      slot.push_back("1");
      continue;
    }
    if (inline_value) {
      slot.push_back(*inline_value);
    } else {
      if (i + 1 >= argv.size()) throw UsageError(shown + " needs a value");
      slot.push_back(argv[++i]);
    }
  }
}

std::optional<std::string> Args::get(const std::string& name) const {
  const auto it = values_.find(name);
  if (it == values_.end() || it->second.empty()) return std::nullopt;
  return it->second.back();
}

std::string Args::get_or(const std::string& name, const std::string& fallback) const {
  return get(name).value_or(fallback);
}

std::vector<std::string> Args::all(const std::string& name) const {
  const auto it = values_.find(name);
  return it == values_.end() ? std::vector<std::string>{} : it->second;
}

std::vector<std::string> split_items(const std::string& option, const std::string& s) {
  std::vector<std::string> out;
  std::string cur;
  for (const char c : s + ",") {
    if (c == ',') {
      if (cur.empty()) throw UsageError(option + ": empty item in '" + s + "'");
      out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  return out;
}

std::vector<std::string> option_list(const std::string& option, const std::string& s, bool may_be_empty) {
  if (s.empty()) {
    if (may_be_empty) return {};
    throw UsageError(option + ": empty list");
  }
  std::vector<std::string> out = split_items(option, s);
  for (auto it = out.begin(); it != out.end(); ++it)
    if (std::find(out.begin(), it, *it) != it) throw UsageError(option + ": '" + *it + "' given twice");
  return out;
}

std::vector<std::string> split_commas(const std::string& s) {
  std::vector<std::string> out;
  std::string cur;
  for (const char c : s + ",") {
    if (c == ',') {
      if (!cur.empty()) out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  return out;
}

long long parse_int(const std::string& option, const std::string& text, long long lo, long long hi) {
  long long v = 0;
  const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
  if (r.ec != std::errc() || r.ptr != text.data() + text.size() || text.empty())
    throw UsageError(option + ": '" + text + "' is not an integer");
  if (v < lo || v > hi)
    throw UsageError(option + ": " + text + " is outside " + std::to_string(lo) + ".." + std::to_string(hi));
  return v;
}

double parse_double(const std::string& option, const std::string& text, double lo, double hi) {
  double v = 0;
  const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
  if (r.ec != std::errc() || r.ptr != text.data() + text.size() || text.empty() || !std::isfinite(v))
    throw UsageError(option + ": '" + text + "' is not a finite number");
  if (v < lo || v > hi) throw UsageError(option + ": " + text + " is outside the allowed range");
  return v;
}

long long Args::get_int(const std::string& name, long long fallback, long long lo, long long hi) const {
  const auto v = get(name);
  return v ? parse_int("--" + name, *v, lo, hi) : fallback;
}

std::optional<long long> Args::get_int(const std::string& name, long long lo, long long hi) const {
  const auto v = get(name);
  if (!v) return std::nullopt;
  return parse_int("--" + name, *v, lo, hi);
}

double Args::get_double(const std::string& name, double fallback, double lo, double hi) const {
  const auto v = get(name);
  return v ? parse_double("--" + name, *v, lo, hi) : fallback;
}

}  // namespace tagbench::cli
