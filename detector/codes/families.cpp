#include "codes/families.hpp"

#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>

#include "codes/family_io.hpp"
#include "codes/rival_codebooks.hpp"
#include "codes/tag_family.hpp"

namespace tagbench {

// Generated at build time from detector/codes/families/*.fam: {file name, contents}.
struct EmbeddedFile {
  const char* name;
  const char* text;
};
extern const EmbeddedFile kEmbeddedFamilies[];
extern const std::size_t kEmbeddedFamilyCount;
extern const char* const kPendingFamilies[];
extern const std::size_t kPendingFamilyCount;

namespace {

using Builder = TagFamily (*)();

TagFamily make_rival(const char* name, std::vector<Code> codes, int h, const char* spec) {
  FamilyInfo info;
  info.name = name;
  info.bits = 36;
  info.min_hamming = h;
  info.min_complexity = min_complexity_of(codes, 6);
  info.generator = std::string("spec ") + spec;
  return TagFamily(std::move(info), std::move(codes));
}

struct Registry {
  std::vector<std::string> names;
  std::map<std::string, std::string> embedded_text;  // name -> family file text
  std::map<std::string, std::unique_ptr<TagFamily>> built;
  std::mutex mu;

  Registry() {
    for (std::size_t i = 0; i < kEmbeddedFamilyCount; ++i) {
      std::string n = kEmbeddedFamilies[i].name;
      names.push_back(n);
      embedded_text[n] = kEmbeddedFamilies[i].text;
    }
    for (const char* n : {"artoolkitplus-simple", "artoolkitplus-bch", "artag", "artag-2046"}) names.push_back(n);
  }

  const TagFamily& get(const std::string& key) {
    std::lock_guard lock(mu);
    if (auto it = built.find(key); it != built.end()) return *it->second;
    std::unique_ptr<TagFamily> f;
    if (auto it = embedded_text.find(key); it != embedded_text.end()) {
      f = std::make_unique<TagFamily>(parse_family(it->second, "built-in family " + key));
    } else if (key == "artoolkitplus-simple") {
      f = std::make_unique<TagFamily>(make_rival("artoolkitplus-simple", artoolkitplus_simple_codes(), 4, "artoolkitplus-simple"));
    } else if (key == "artoolkitplus-bch") {
      f = std::make_unique<TagFamily>(make_rival("artoolkitplus-bch", artoolkitplus_bch_codes(), 2, "artoolkitplus-bch-36-12"));
    } else if (key == "artag") {
      f = std::make_unique<TagFamily>(make_rival("artag", artag_codes(false), 4, "artag-36-10-linear"));
    } else if (key == "artag-2046") {
      f = std::make_unique<TagFamily>(make_rival("artag-2046", artag_codes(true), 4, "artag-36-10-linear+complements"));
    } else {
      std::string known;
      for (const auto& n : names) known += (known.empty() ? "" : ", ") + n;
      throw std::invalid_argument("unknown family '" + key + "' (known: " + known + ")");
    }
    return *(built[key] = std::move(f));
  }
};

Registry& registry() {
  static Registry r;
  return r;
}

}  // namespace

std::string canonical_family_name(const std::string& name) {
  if (name.rfind("tag", 0) == 0 && name.size() > 3 && std::isdigit(static_cast<unsigned char>(name[3])))
    return name.substr(3);
  return name;
}

std::vector<std::string> builtin_family_names() { return registry().names; }

const TagFamily& builtin_family(const std::string& name) { return registry().get(canonical_family_name(name)); }

bool names_a_family_file(const std::string& name_or_path) {
  return name_or_path.find('/') != std::string::npos || name_or_path.ends_with(".fam");
}

TagFamily load_family(const std::string& name_or_path) {
  std::error_code ec;
  if (std::filesystem::is_regular_file(name_or_path, ec)) return read_family_file(name_or_path);
  if (names_a_family_file(name_or_path)) {
    const auto st = std::filesystem::status(name_or_path, ec);
    throw std::invalid_argument("family file " + name_or_path + ": " +
                                (!std::filesystem::exists(st)        ? "no such file"
                                 : std::filesystem::is_directory(st) ? "is a directory"
                                                                     : "not a regular file"));
  }
  return builtin_family(name_or_path);
}

std::vector<std::string> pending_family_names() {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < kPendingFamilyCount; ++i) out.push_back(kPendingFamilies[i]);
  return out;
}

}  // namespace tagbench
