// tools/shell_words: the words a POSIX shell would make of a command line, without a shell.
#include <gtest/gtest.h>

#include "tools/shell_words.hpp"

namespace tagbench {
namespace test_shell_words {
namespace {

using W = std::vector<std::string>;

TEST(ShellWords, SplitsAsAShellWould) {
  EXPECT_EQ(split_shell_words("python3 det.py --x 1"), (W{"python3", "det.py", "--x", "1"}));
  EXPECT_EQ(split_shell_words("  a\t b  "), (W{"a", "b"}));
  EXPECT_EQ(split_shell_words("'a b' \"c \\\"d\\\" \\n\" e\\ f"), (W{"a b", "c \"d\" \\n", "e f"}));
  EXPECT_EQ(split_shell_words("x''y \"\""), (W{"xy", ""}));
  EXPECT_EQ(split_shell_words("a|b;c>$HOME"), (W{"a|b;c>$HOME"}));  // no operators, no expansion
}

TEST(ShellWords, RefusesWhatAShellWouldNotClose) {
  EXPECT_THROW(split_shell_words("a 'b"), std::invalid_argument);
  EXPECT_THROW(split_shell_words("a \"b"), std::invalid_argument);
  EXPECT_THROW(split_shell_words("a\\"), std::invalid_argument);
  EXPECT_THROW(split_shell_words("   "), std::invalid_argument);
}

}  // namespace
}  // namespace test_shell_words
}  // namespace tagbench
