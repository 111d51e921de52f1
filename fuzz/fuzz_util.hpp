#pragma once
// Helpers shared by the fuzz targets: a reader that turns the fuzzer's bytes into values (running
// out of bytes yields zeros, so every input is usable), and FUZZ_CHECK, which aborts (a crash to
// libFuzzer, a failed test to the replay) when a property of our code does not hold.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>

namespace fuzz {

class Reader {
 public:
  Reader(const std::uint8_t* data, std::size_t size) : p_(data), n_(size) {}
  std::size_t left() const { return n_ - i_; }
  std::uint8_t u8() { return i_ < n_ ? p_[i_++] : 0; }
  std::uint16_t u16() { return static_cast<std::uint16_t>(u8() | (u8() << 8)); }
  std::uint32_t u32() { return static_cast<std::uint32_t>(u16()) | (static_cast<std::uint32_t>(u16()) << 16); }
  float f32() {
    const std::uint32_t v = u32();
    float f;
    std::memcpy(&f, &v, sizeof f);
    return f;
  }
  bool flag() { return (u8() & 1) != 0; }
  // The rest of the input, unread.
  std::string rest() {
    std::string s(reinterpret_cast<const char*>(p_ + i_), n_ - i_);
    i_ = n_;
    return s;
  }
  const std::uint8_t* tail() const { return p_ + i_; }

 private:
  const std::uint8_t* p_;
  std::size_t n_, i_ = 0;
};

[[noreturn]] inline void check_failed(const char* cond, const char* file, int line, const std::string& what) {
  std::fprintf(stderr, "%s:%d: FUZZ_CHECK(%s) failed: %s\n", file, line, cond, what.c_str());
  std::fflush(stderr);
  std::abort();
}

}  // namespace fuzz

#define FUZZ_CHECK(cond, what)                                              \
  do {                                                                      \
    if (!(cond)) ::fuzz::check_failed(#cond, __FILE__, __LINE__, (what));  \
  } while (0)

namespace fuzz {

// A refusal must be one message that starts with the input's name and a colon ("NAME: problem").
inline void check_error_names(const std::exception& e, const std::string& name) {
  const std::string what = e.what();
  FUZZ_CHECK(what.rfind(name + ":", 0) == 0, "the error does not name the input: " + what);
}

}  // namespace fuzz
