#pragma once
// SHA-256 (FIPS 180-4) through OpenSSL's EVP interface, as lowercase hex.
#include <filesystem>
#include <string>
#include <string_view>

namespace tagbench::corpus {

std::string sha256_hex(std::string_view bytes);
// Streams the file; throws std::runtime_error naming it if it cannot be read.
std::string sha256_file(const std::filesystem::path& file);

}  // namespace tagbench::corpus
