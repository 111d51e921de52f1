#pragma once
// A small command-line parser for the git-style subcommands: --name value, --name=value, flags,
// repeatable options and positionals. Every error is a UsageError with a one-line message that
// names the option.
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace tagbench::cli {

// One line for stderr: control characters (a newline in a file name or an OpenCV message) are shown
// escaped (`escape`, as \xNN) or as spaces, so every error stays on its own line.
std::string one_line(const std::string& s, bool escape);

// Why `p` is not a directory one can use: "no such directory", or "not a directory" when it exists.
std::string why_not_directory(const std::string& p);

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// f(), with an std::invalid_argument or std::out_of_range it throws (a family name or file that cannot be loaded, an id or
// option outside the library's domain) turned into a UsageError (exit 2), its message after `prefix`.
template <class F>
decltype(auto) usage_on_invalid(const std::string& prefix, F&& f) {
  try {
    return std::forward<F>(f)();
  } catch (const std::invalid_argument& e) {
    throw UsageError(prefix + e.what());
  } catch (const std::out_of_range& e) {
    throw UsageError(prefix + e.what());
  }
}

struct OptionSpec {
  OptionSpec(std::string n, bool value = true, bool repeat = false, std::string short_n = "")
      : name(std::move(n)), takes_value(value), repeatable(repeat), short_name(std::move(short_n)) {}
  std::string name;        // without dashes, e.g. "bits"
  bool takes_value;
  bool repeatable;
  std::string short_name;  // e.g. "o" for -o; empty if none
};

class Args {
 public:
  // Parses argv after the subcommand words; throws UsageError on unknown options or missing values.
  Args(const std::vector<std::string>& argv, const std::vector<OptionSpec>& specs);

  bool has(const std::string& name) const { return values_.count(name) > 0; }
  bool flag(const std::string& name) const { return has(name); }
  std::optional<std::string> get(const std::string& name) const;
  std::string get_or(const std::string& name, const std::string& fallback) const;
  std::vector<std::string> all(const std::string& name) const;
  const std::vector<std::string>& positionals() const { return positionals_; }

  // Typed getters that check the range; errors name the option: "--bits: 'x' is not an integer".
  long long get_int(const std::string& name, long long fallback, long long lo, long long hi) const;
  std::optional<long long> get_int(const std::string& name, long long lo, long long hi) const;
  double get_double(const std::string& name, double fallback, double lo, double hi) const;

 private:
  std::map<std::string, std::vector<std::string>> values_;
  std::vector<std::string> positionals_;
};

// "a,b,,c" -> {"a", "b", "c"}: the comma-separated lists of options like --families; empty items dropped.
std::vector<std::string> split_commas(const std::string& s);

// "a,b,c" -> {"a", "b", "c"}; an empty item (or an empty `s`) is a UsageError naming the option.
std::vector<std::string> split_items(const std::string& option, const std::string& s);

// An option's comma-separated list, strictly: UsageError (naming `option`) for an empty item ("a,,b",
// "a,"), an item given twice (it would be run and counted twice) or, unless `may_be_empty`, no item.
std::vector<std::string> option_list(const std::string& option, const std::string& s, bool may_be_empty = false);

long long parse_int(const std::string& option, const std::string& text, long long lo, long long hi);
double parse_double(const std::string& option, const std::string& text, double lo, double hi);

}  // namespace tagbench::cli
