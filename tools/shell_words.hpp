#pragma once
// A command line split into words as a POSIX shell would split it, without running a shell: blanks
// separate words; 'single quotes' keep everything; "double quotes" keep everything but \\ \" \$ \`
// escapes; a backslash outside quotes keeps the next character. No expansion (variables, globs, ~)
// and no operators (| ; & > <: plain characters here).
#include <string>
#include <vector>

namespace tagbench {

// Throws std::invalid_argument "unclosed single quote" / "unclosed double quote" / "a backslash at
// the end" / "no words".
std::vector<std::string> split_shell_words(const std::string& text);

}  // namespace tagbench
