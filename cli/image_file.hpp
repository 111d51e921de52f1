#pragma once
// Reading an image file the way `tagbench detect` does (shared with fuzz/fuzz_image_file.cpp, which
// feeds it arbitrary bytes): the whole file is read, then decoded by OpenCV with its depth and
// channels kept (8/16-bit, float; gray, BGR, BGRA), so the detector sees what the file holds.
#include <filesystem>
#include <string>

#include <opencv2/core/mat.hpp>

namespace tagbench::cli {

// Decodes the bytes of an image file. Throws std::runtime_error with a one-line reason for empty,
// truncated (JPEG), undecodable or unsupported data; never returns an empty Mat.
cv::Mat decode_image(const std::string& bytes);

// Reads `path` and decodes it (decode_image); a file that cannot be opened or read is a
// std::runtime_error too. The message does not name the file: the caller does.
cv::Mat load_image(const std::filesystem::path& path);

// True when a JPEG's markers lead to its end-of-image marker (see image_file.cpp).
bool jpeg_is_complete(const std::string& bytes);

}  // namespace tagbench::cli
