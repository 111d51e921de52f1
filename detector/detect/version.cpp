// The linked library's version (<tagbench/version.hpp>), from the CMake project version.
#include <tagbench/version.hpp>

namespace tagbench {

const char* version() { return TAGBENCH_VERSION_STRING; }

}  // namespace tagbench
