#pragma once
// Speed of the lexicode generator (results/generator_speed.csv): small families timed live at
// several thread counts (and checked bit-exact against the shipped ones), plus the recorded runs of
// the shipped 36-bit families (hours long, so taken from their family files' generation records).
#include <string>
#include <vector>

namespace tagbench::bench {

struct GeneratorSpeedRow {
  std::string family, source;  // source: "measured" (this run) or "recorded" (the family file's record)
  int bits = 0, hamming = 0, complexity = 0;
  long long seed = 0;
  std::string order;
  int threads = 0;
  double candidates = 0, wall_seconds = 0;
  std::size_t codes = 0;
  bool matches_shipped = false;  // measured rows: the output equals the shipped family
  std::string scan, cpu;
  double candidates_per_second() const { return wall_seconds > 0 ? candidates / wall_seconds : 0; }
};

// Times the given built-in generated families (each must be shipped) for each thread count.
std::vector<GeneratorSpeedRow> measure_generator_speed(const std::vector<std::string>& families,
                                                       const std::vector<int>& thread_counts);
// The generation records of every shipped generated family whose file has one.
std::vector<GeneratorSpeedRow> recorded_generator_runs();

std::string generator_speed_csv(const std::vector<GeneratorSpeedRow>& rows);

}  // namespace tagbench::bench
