#pragma once
#include <string>

namespace tagbench {
// The CPU's model name from /proc/cpuinfo ("unknown" if unavailable), for benchmark records.
std::string cpu_model_name();
// std::thread::hardware_concurrency(), at least 1.
int hardware_threads();
}  // namespace tagbench
