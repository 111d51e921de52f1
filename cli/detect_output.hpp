#pragma once
// tagbench detect: the output. One JSON document for the whole run, a JSON line per image, or CSV rows (the formats:
// detect_args.cpp's kHelp, cmd_detect.cpp's header), written to stdout in input order; failed inputs
// are reported on stderr as they come and listed in the JSON's "errors".
#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "cli/detect_args.hpp"
#include "cli/detect_inputs.hpp"
#include "detect/detector.hpp"
#include "detect/pose.hpp"

namespace tagbench::cli::detect_cmd {

namespace fs = std::filesystem;

class Sink {
 public:
  Sink(const Settings& s, const Detector& det);

  void begin();
  void emit(const Outcome& o);
  void end();

  std::size_t failures() const { return errors_.size(); }

 private:
  void put(const std::string& s) { std::fwrite(s.data(), 1, s.size(), stdout); }

  static std::string point(const Eigen::Vector2d& p);
  static std::string matrix(const Eigen::Matrix3d& m);
  static std::string pose(const PoseSolution& p);
  void emit_json(const Outcome& o);
  void emit_csv(const Outcome& o);
  void emit_jsonl(const Outcome& o);
  const Settings& s_;
  const Detector& det_;
  bool tty_;
  std::size_t images_ = 0;
  std::vector<Outcome> errors_;
};

}  // namespace tagbench::cli::detect_cmd
