#include "cli/image_file.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>

namespace tagbench::cli {

// libjpeg pads a JPEG whose data ends early with grey and only warns, so OpenCV would hand us the
// partial picture as if it were whole. A JPEG is complete when its markers lead to the end-of-image
// marker (FF D9); segments are skipped by their lengths (so a thumbnail's own EOI inside APP1 does not
// count) and entropy-coded data up to the next marker. Bytes after the EOI are allowed.
bool jpeg_is_complete(const std::string& b) {
  const auto at = [&](std::size_t i) { return static_cast<unsigned char>(b[i]); };
  std::size_t i = 2;  // after SOI
  while (i < b.size()) {
    if (at(i) != 0xff) {  // stray bytes between segments: libjpeg skips them too
      ++i;
      continue;
    }
    while (i < b.size() && at(i) == 0xff) ++i;  // fill bytes
    if (i >= b.size()) return false;
    const unsigned m = at(i++);
    if (m == 0xd9) return true;                                        // EOI
    if (m == 0x00 || m == 0x01 || (m >= 0xd0 && m <= 0xd7)) continue;  // no length
    if (i + 2 > b.size()) return false;
    const std::size_t len = (static_cast<std::size_t>(at(i)) << 8) | at(i + 1);
    if (len < 2 || i + len > b.size()) return false;
    i += len;
    if (m != 0xda) continue;
    // After SOS: entropy-coded data, where FF is followed by 00 (a data byte) or RST0-7.
    while (i + 1 < b.size() && !(at(i) == 0xff && at(i + 1) != 0x00 && !(at(i + 1) >= 0xd0 && at(i + 1) <= 0xd7)))
      ++i;
    if (i + 1 >= b.size()) return false;
  }
  return false;
}

cv::Mat decode_image(const std::string& bytes) {
  if (bytes.empty()) throw std::runtime_error("empty file (0 bytes)");
  // imdecode takes the buffer as a Mat with an int length.
  if (bytes.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw std::runtime_error("file too large to decode (over 2 GiB)");
  if (bytes.size() >= 3 && bytes.compare(0, 3, "\xff\xd8\xff") == 0 && !jpeg_is_complete(bytes))
    throw std::runtime_error("truncated JPEG (the data ends before the end-of-image marker)");
  const cv::Mat raw(1, static_cast<int>(bytes.size()), CV_8UC1, const_cast<char*>(bytes.data()));
  cv::Mat img;
  try {
    img = cv::imdecode(raw, cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR);
  } catch (const cv::Exception&) {
    img.release();
  }
  if (img.empty()) throw std::runtime_error("cannot decode the image (corrupt or unsupported format)");
  return img;
}

cv::Mat load_image(const std::filesystem::path& path) {
  std::string bytes;
  {
    errno = 0;
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error(std::string("cannot open: ") + (errno ? std::strerror(errno) : "unknown error"));
    // At most 1 GiB (a 100-megapixel 16-bit colour image, the detector's pixel limit, is under that
    // even uncompressed): /dev/zero or a runaway FIFO would otherwise be read until memory runs out.
    constexpr std::size_t kMaxBytes = std::size_t{1} << 30;
    char chunk[1 << 16];
    while (in.read(chunk, sizeof chunk) || in.gcount() > 0) {
      bytes.append(chunk, static_cast<std::size_t>(in.gcount()));
      if (bytes.size() > kMaxBytes) throw std::runtime_error("over 1 GiB: not an image file this tool reads");
    }
    if (in.bad()) throw std::runtime_error("read error");
  }
  return decode_image(bytes);
}

}  // namespace tagbench::cli
