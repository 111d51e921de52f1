#include "codes/family_io.hpp"

#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace tagbench {
namespace {

// A family or checkpoint file's text. The library reads its own files (the tools' helpers are not
// part of it); errors name the path as the tools' read_file does ("PATH: cannot open: REASON").
std::string file_text(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw std::runtime_error(path.string() + ": is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path.string() + ": cannot open: " + std::strerror(errno));
  std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (in.bad()) throw std::runtime_error(path.string() + ": read error");
  return text;
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

constexpr const char* kFirstLine =
    "tagbench family file (codes in AprilTag 1 order: MSB = top-left payload cell, row-major, 1 = white)";

struct HeaderFile {
  std::vector<std::string> comments;  // comment lines without "#", other than the standard first line
  std::map<std::string, std::string> keys;
  std::map<std::string, int> key_line;
  std::vector<Code> codes;
  std::vector<int> code_line;
};

HeaderFile parse_header_file(const std::string& text, const std::string& source,
                             const std::vector<std::string>& allowed) {
  HeaderFile f;
  std::istringstream in(text);
  std::string raw;
  int line_no = 0;
  while (std::getline(in, raw)) {
    ++line_no;
    const std::string line = trim(raw);
    const auto where = [&] { return source + ":" + std::to_string(line_no) + ": "; };
    if (line.empty()) continue;
    if (line[0] == '#') {
      const std::string c = trim(line.substr(1));
      if (!c.empty() && c != kFirstLine) f.comments.push_back(c);
      continue;
    }
    const auto colon = line.find(':');
    if (colon != std::string::npos) {
      if (!f.codes.empty()) throw std::invalid_argument(where() + "header line '" + line + "' after the codes");
      const std::string key = trim(line.substr(0, colon)), value = trim(line.substr(colon + 1));
      bool known = false;
      for (const auto& a : allowed) known = known || a == key;
      if (!known) throw std::invalid_argument(where() + "unknown header key '" + key + "'");
      if (f.keys.count(key)) throw std::invalid_argument(where() + "header key '" + key + "' given twice");
      f.keys[key] = value;
      f.key_line[key] = line_no;
      continue;
    }
    const auto code = parse_hex_code(line);
    if (!code) throw std::invalid_argument(where() + "not a hex code: '" + line + "'");
    f.codes.push_back(*code);
    f.code_line.push_back(line_no);
  }
  return f;
}

long long get_int(const HeaderFile& f, const std::string& key, const std::string& source, bool required,
                  long long fallback = 0) {
  const auto it = f.keys.find(key);
  if (it == f.keys.end()) {
    if (required) throw std::invalid_argument(source + ": missing header key '" + key + "'");
    return fallback;
  }
  long long v = 0;
  const auto& s = it->second;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  if (r.ec != std::errc() || r.ptr != s.data() + s.size())
    throw std::invalid_argument(source + ":" + std::to_string(f.key_line.at(key)) + ": '" + key +
                                "' is not an integer: '" + s + "'");
  return v;
}

// bits, hamming and complexity are ints: a value outside int must be refused, not wrapped into a
// valid-looking one ("bits: 4294967312" read as 16).
int get_small_int(const HeaderFile& f, const std::string& key, const std::string& source) {
  const long long v = get_int(f, key, source, true);
  if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max())
    throw std::invalid_argument(source + ":" + std::to_string(f.key_line.at(key)) + ": '" + key +
                                "' is out of range: " + std::to_string(v));
  return static_cast<int>(v);
}

}  // namespace

std::optional<Code> parse_hex_code(const std::string& token) {
  std::string t = token;
  if (t.size() > 2 && t[0] == '0' && (t[1] == 'x' || t[1] == 'X')) t = t.substr(2);
  if (t.empty() || t.size() > 16) return std::nullopt;
  Code v = 0;
  const auto r = std::from_chars(t.data(), t.data() + t.size(), v, 16);
  if (r.ec != std::errc() || r.ptr != t.data() + t.size()) return std::nullopt;
  return v;
}

TagFamily parse_family(const std::string& text, const std::string& source) {
  const HeaderFile f = parse_header_file(
      text, source, {"name", "bits", "hamming", "complexity", "seed", "order", "generator", "count", "status"});
  if (f.keys.count("status") && f.keys.at("status") != "complete")
    throw std::invalid_argument(source + ": status is '" + f.keys.at("status") +
                                "': a partial generator run is not a family");
  FamilyInfo info;
  if (!f.keys.count("name")) throw std::invalid_argument(source + ": missing header key 'name'");
  info.name = f.keys.at("name");
  info.bits = get_small_int(f, "bits", source);
  info.min_hamming = get_small_int(f, "hamming", source);
  info.min_complexity = get_small_int(f, "complexity", source);
  if (f.keys.count("seed")) info.seed = get_int(f, "seed", source, true);
  if (f.keys.count("order")) info.order = f.keys.at("order");
  if (f.keys.count("generator")) info.generator = f.keys.at("generator");
  info.records = f.comments;
  const long long count = get_int(f, "count", source, true);
  if (count != static_cast<long long>(f.codes.size()))
    throw std::invalid_argument(source + ": header says count " + std::to_string(count) + " but the file has " +
                                std::to_string(f.codes.size()) + " codes");
  try {
    return TagFamily(std::move(info), f.codes);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(source + ": " + e.what());
  }
}

TagFamily read_family_file(const std::filesystem::path& path) {
  return parse_family(file_text(path), path.string());
}

std::string format_family(const TagFamily& family, const std::vector<std::string>& comments) {
  const FamilyInfo& i = family.info();
  std::ostringstream o;
  o << "# " << kFirstLine << "\n";
  for (const auto& c : i.records) o << "# " << c << "\n";
  for (const auto& c : comments) o << "# " << c << "\n";
  o << "name: " << i.name << "\nbits: " << i.bits << "\nhamming: " << i.min_hamming
    << "\ncomplexity: " << i.min_complexity << "\n";
  if (i.seed) o << "seed: " << *i.seed << "\n";
  if (!i.order.empty()) o << "order: " << i.order << "\n";
  if (!i.generator.empty()) o << "generator: " << i.generator << "\n";
  o << "count: " << family.size() << "\n";
  for (const Code c : family.codes()) o << hex_code(c) << "\n";
  return o.str();
}

std::string format_family_cpp(const TagFamily& family) {
  const FamilyInfo& i = family.info();
  std::string ident = "tag" + i.name;
  for (char& ch : ident)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  std::ostringstream o;
  o << "// Tag family " << i.name << ": " << family.size() << " codes, " << i.bits << " bits, minimum Hamming distance "
    << i.min_hamming << ", minimum complexity " << i.min_complexity;
  if (i.seed) o << ", seed " << *i.seed;
  if (!i.order.empty()) o << ", " << i.order << " order";
  o << ".\n// AprilTag 1 order: MSB = top-left payload cell, row-major, 1 = white.\n#include <cstdint>\n\n"
    << "inline constexpr int " << ident << "_bits = " << i.bits << ";\n"
    << "inline constexpr int " << ident << "_min_hamming = " << i.min_hamming << ";\n"
    << "inline constexpr std::uint64_t " << ident << "_codes[" << family.size() << "] = {\n";
  for (std::size_t k = 0; k < family.size(); ++k)
    o << (k % 6 == 0 ? "    " : " ") << hex_code(family.codes()[k]) << "ULL," << (k % 6 == 5 || k + 1 == family.size() ? "\n" : "");
  o << "};\n";
  return o.str();
}

std::string format_checkpoint(const LexicodeParams& p, const LexicodeState& s) {
  std::ostringstream o;
  o << "# tagbench lexicode checkpoint: resume with `tagbench family generate ... --checkpoint FILE --resume`\n"
    << "status: partial\nbits: " << p.bits << "\nhamming: " << p.min_hamming << "\ncomplexity: " << p.resolved_complexity()
    << "\nseed: " << p.resolved_seed() << "\norder: " << to_string(p.order) << "\ngenerator: tagbench-lexicode "
    << kGeneratorVersion << "\nnext_index: " << to_decimal(s.next_index) << "\nelapsed_seconds: "
    << static_cast<long long>(s.elapsed_seconds * 1000) << "e-3\ncount: " << s.codes.size() << "\n";
  for (const Code c : s.codes) o << hex_code(c) << "\n";
  return o.str();
}

Checkpoint read_checkpoint(const std::filesystem::path& path) {
  const std::string source = path.string();
  const HeaderFile f = parse_header_file(file_text(path), source,
                                         {"status", "bits", "hamming", "complexity", "seed", "order", "generator",
                                          "next_index", "elapsed_seconds", "count"});
  if (!f.keys.count("status") || f.keys.at("status") != "partial")
    throw std::invalid_argument(source + ": not a lexicode checkpoint (no 'status: partial')");
  Checkpoint c;
  c.params.bits = get_small_int(f, "bits", source);
  c.params.min_hamming = get_small_int(f, "hamming", source);
  c.params.min_complexity = get_small_int(f, "complexity", source);
  c.params.seed = get_int(f, "seed", source, true);
  // Errors of the shared parsers gain the file's name, as every other error here has it.
  const auto named = [&](auto&& parse) {
    try {
      return parse();
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(source + ": " + e.what());
    }
  };
  c.params.order =
      named([&] { return parse_candidate_order(f.keys.count("order") ? f.keys.at("order") : "prime"); });
  if (f.keys.count("generator") && f.keys.at("generator") != "tagbench-lexicode " + std::to_string(kGeneratorVersion))
    throw std::invalid_argument(source + ": written by another generator version: '" + f.keys.at("generator") + "'");
  {
    const auto it = f.keys.find("next_index");
    if (it == f.keys.end()) throw std::invalid_argument(source + ": missing header key 'next_index'");
    // 128 bits (a candidate index can reach 2^64); digits only, at least one, and no wrap-around.
    constexpr unsigned __int128 kMax = ~static_cast<unsigned __int128>(0);
    unsigned __int128 v = 0;
    if (it->second.empty()) throw std::invalid_argument(source + ": 'next_index' is not an integer");
    for (const char ch : it->second) {
      if (ch < '0' || ch > '9') throw std::invalid_argument(source + ": 'next_index' is not an integer");
      const unsigned digit = static_cast<unsigned>(ch - '0');
      if (v > (kMax - digit) / 10) throw std::invalid_argument(source + ": 'next_index' is out of range");
      v = v * 10 + digit;
    }
    c.state.next_index = v;
  }
  if (const auto it = f.keys.find("elapsed_seconds"); it != f.keys.end()) {
    // Finite and non-negative, and at most 1e15 s so that the milliseconds format_checkpoint writes
    // back fit a long long.
    const std::string& t = it->second;
    double v = 0;
    const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
    if (t.empty() || r.ec != std::errc() || r.ptr != t.data() + t.size() || !(v >= 0) || v > 1e15)
      throw std::invalid_argument(source + ": 'elapsed_seconds' is not a number of seconds in 0..1e15: '" + t + "'");
    c.state.elapsed_seconds = v;
  }
  const long long count = get_int(f, "count", source, true);
  if (count != static_cast<long long>(f.codes.size()))
    throw std::invalid_argument(source + ": header says count " + std::to_string(count) + " but the file has " +
                                std::to_string(f.codes.size()) + " codes");
  c.state.codes = f.codes;
  named([&] { c.params.validate(); });
  return c;
}

}  // namespace tagbench
