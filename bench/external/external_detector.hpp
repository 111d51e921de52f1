#pragma once
// A detector outside the build run inside the experiments (issue 12, section 3):
// `--detectors ...,external:NAME=COMMAND`. COMMAND is split into words as a shell would (no shell is
// run), started once per batch of frames in the batch's folder, given the images' absolute paths on
// stdin, one a line, and must print one detection line (detection_lines.hpp) per image, in any order,
// in our conventions (README "Conventions"; an adapter converts its detector's). It gets the frames
// the built-in detectors get; a lens (the distortion condition) is not passed on.
#include <filesystem>
#include <string>
#include <vector>

#include "external/detection_lines.hpp"

namespace tagbench::bench {

struct ExternalDetector {
  std::string name;                // the rows' detector name
  std::string command;             // as given
  std::vector<std::string> argv;   // COMMAND split into words
  double timeout_seconds = 1800;   // per batch; past it the command is killed
};

// "NAME=COMMAND" (after "external:"): throws std::invalid_argument naming the problem (no '=', an empty
// or CSV-unsafe name, a command a shell could not split).
ExternalDetector parse_external_detector(const std::string& spec, double timeout_seconds);

// Runs `d` on `images` (absolute paths) in folder `workdir` (its stdin, stdout and stderr files go
// there). Returns the detections per image, in the order of `images`. Throws std::runtime_error with
// one line "external detector NAME: ..." naming the image for: a command that cannot run, exits
// non-zero or is killed, runs past its timeout (the first image it left without a line), prints a line
// that is not a detection line, names an image it was not given or one twice, or leaves one out, or
// reports an "error" for an image.
std::vector<ImageDetections> run_external(const ExternalDetector& d, const std::vector<std::string>& images,
                                          const std::filesystem::path& workdir);

// The same in a temporary folder of its own (under the system's), removed afterwards.
std::vector<ImageDetections> run_external(const ExternalDetector& d, const std::vector<std::string>& images);

// A work folder for external detectors, TMP/tagbench-external-OWNER-N under the system's temporary
// folder (N counts this process's folders), made empty and removed with what it holds when this
// ends. The work folders of runs that are gone (killed, or ended by a signal while a detector ran:
// run_child_io) are removed first; those of runs still going stay.
class ExternalWorkDir {
 public:
  ExternalWorkDir();
  ~ExternalWorkDir();
  ExternalWorkDir(const ExternalWorkDir&) = delete;
  ExternalWorkDir& operator=(const ExternalWorkDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace tagbench::bench
