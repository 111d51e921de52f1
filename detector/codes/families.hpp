#pragma once
// The families tagbench knows by name: the AprilTag families our generator produced (shipped as
// family files, embedded at build time) and the rival codebooks built from their specifications.
#include <filesystem>
#include <string>
#include <vector>

#include "tag_family.hpp"

namespace tagbench {

// Names of the built-in families, in a stable display order.
std::vector<std::string> builtin_family_names();

// A built-in family by name ("36h11", "tag36h11" and "artoolkitplus-bch" all work); throws
// std::invalid_argument "unknown family 'X' (known: ...)" otherwise. Built once, then shared.
const TagFamily& builtin_family(const std::string& name);

// A family name without AprilTag's "tag" prefix ("tag36h11" -> "36h11"; "artoolkitplus-bch" and
// file paths unchanged): the form builtin_family looks up, for comparing names from different tools.
std::string canonical_family_name(const std::string& name);

// A built-in family, or a family file when `name_or_path` names an existing file.
TagFamily load_family(const std::string& name_or_path);

// Whether `name_or_path` is meant as a family file (a path with '/' or a name ending in .fam), not a
// built-in name: load_family's rule for reporting "no such file" rather than "unknown family".
bool names_a_family_file(const std::string& name_or_path);

// Families whose lexicode run is still in progress (checkpoint shipped, family not yet complete).
std::vector<std::string> pending_family_names();

}  // namespace tagbench
