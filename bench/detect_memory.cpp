// detect_memory: the detector's peak memory on synthetic scenes of several sizes (issue 6).
//
//   detect_memory [--out results/memory.csv] [--sizes 640x480,1920x1080,8000x8000]
//                 [--family 36h11] [--tags 6] [--seed 1]
//
// For every size the scene (bench/scenes.hpp) is made once here, then every detector setting is
// measured in a child forked for it, so no heap state of one measurement is left for the next. In
// the child: the detector is built and run once on a tiny image (code pages and family tables are
// then resident), the kernel's peak-RSS mark is reset to the current RSS (/proc/self/clear_refs,
// "5"), one frame is detected with a fresh DetectorWorkspace, and peak RSS minus the RSS before it
// (VmHWM - VmRSS, /proc/self/status) is what that detection added: every page it touched, the
// workspace and the transient vectors. The same frame is then detected again with the warm
// workspace and measured the same way (what a video stream costs per frame once running). The
// 8-bit input image belongs to the caller and is not counted. OpenCV runs single-threaded here so
// that no thread pool is running when the process forks (and no pool stacks enter the numbers).
//
// Writes one CSV row per size and setting, to a temporary renamed over --out at the end.
#include <malloc.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "detect/detector.hpp"
#include "detect/detector_opencv.hpp"
#include "scenes.hpp"
#include "tools/atomic_file.hpp"
#include "tools/format.hpp"

namespace {

using namespace tagbench;
using namespace tagbench::bench;

struct Size {
  int width = 0, height = 0;
};

struct Setting {
  const char* name;
  bool half_resolution;
};

// The kilobyte value of one "Name:  1234 kB" line of /proc/self/status.
long long status_kb(const std::string& name) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(name + ":", 0) == 0) return std::stoll(line.substr(name.size() + 1));
  throw std::runtime_error("no " + name + " in /proc/self/status");
}

// Sets the peak-RSS mark (VmHWM) to the current RSS; returns that RSS in bytes.
long long reset_peak() {
  std::ofstream clear("/proc/self/clear_refs");
  clear << "5" << std::flush;
  if (!clear) throw std::runtime_error("cannot reset the peak RSS: /proc/self/clear_refs not writable");
  const long long rss = status_kb("VmRSS");
  // Far above means the kernel ignored the reset (Linux before 4.0); a little above is normal, the
  // kernel's RSS counters are per-CPU and approximate.
  if (status_kb("VmHWM") > rss + 1024)
    throw std::runtime_error("the kernel did not reset VmHWM through /proc/self/clear_refs (VmRSS " +
                             std::to_string(rss) + " kB, VmHWM " + std::to_string(status_kb("VmHWM")) + " kB)");
  return rss * 1024;
}

// Bytes the process's peak RSS rose above `base` since reset_peak().
long long peak_above(long long base) { return status_kb("VmHWM") * 1024 - base; }

struct Measurement {
  long long first_peak = 0, warm_peak = 0, workspace = 0;
  double ms = 0;
  std::size_t detections = 0;
};

// The child's work; its result travels back as one line of text.
Measurement measure(const cv::Mat& image, const DetectorOptions& opt) {
  const Detector det(opt);
  detect(det, cv::Mat(64, 64, CV_8UC1, cv::Scalar(128)));  // warm-up: code and tables become resident
  malloc_trim(0);  // return what the warm-up freed, so it is not reused unseen
  Measurement m;
  DetectorWorkspace ws;
  long long base = reset_peak();
  const auto t0 = std::chrono::steady_clock::now();
  m.detections = detect(det, image, ws).size();
  m.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  m.first_peak = peak_above(base);
  m.workspace = static_cast<long long>(ws.capacity_bytes());
  malloc_trim(0);
  base = reset_peak();
  detect(det, image, ws);
  m.warm_peak = peak_above(base);
  return m;
}

// Runs measure() in a forked child and parses its answer.
Measurement measure_in_child(const cv::Mat& image, const DetectorOptions& opt) {
  int fds[2];
  if (pipe(fds) != 0) throw std::runtime_error("pipe failed");
  std::fflush(nullptr);
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {
    close(fds[0]);
    std::string line;
    int code = 0;
    try {
      const Measurement m = measure(image, opt);
      std::ostringstream s;
      s << "ok " << m.first_peak << ' ' << m.warm_peak << ' ' << m.workspace << ' ' << m.ms << ' ' << m.detections;
      line = s.str();
    } catch (const std::exception& e) {
      line = std::string("error ") + e.what();
      code = 1;
    }
    const ssize_t written = write(fds[1], line.data(), line.size());
    _exit(written == static_cast<ssize_t>(line.size()) ? code : 1);
  }
  close(fds[1]);
  std::string reply;
  char buf[512];
  for (ssize_t n; (n = read(fds[0], buf, sizeof buf)) > 0;) reply.append(buf, static_cast<std::size_t>(n));
  close(fds[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  if (reply.rfind("ok ", 0) != 0)
    throw std::runtime_error("measurement failed: " + (reply.empty() ? std::string("child died") : reply));
  std::istringstream in(reply.substr(3));
  Measurement m;
  in >> m.first_peak >> m.warm_peak >> m.workspace >> m.ms >> m.detections;
  return m;
}

std::vector<Size> parse_sizes(const std::string& list) {
  std::vector<Size> out;
  std::stringstream in(list);
  for (std::string item; std::getline(in, item, ',');) {
    Size s;
    char x = 0;
    std::istringstream one(item);
    if (!(one >> s.width >> x >> s.height) || x != 'x' || !one.eof() || s.width < 16 || s.height < 16)
      throw std::invalid_argument("bad size '" + item + "' (want WxH, both >= 16)");
    out.push_back(s);
  }
  if (out.empty()) throw std::invalid_argument("no sizes given");
  return out;
}

int run(int argc, char** argv) {
  std::string out = "results/memory.csv", family = "36h11", sizes = "640x480,1920x1080,8000x8000";
  int tags = 6;
  unsigned seed = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      std::cout << "usage: detect_memory [--out FILE] [--sizes WxH,...] [--family NAME] [--tags N] [--seed S]\n";
      return 0;
    }
    if (i + 1 >= argc) throw std::invalid_argument("option " + a + " needs a value");
    const std::string v = argv[++i];
    if (a == "--out") out = v;
    else if (a == "--sizes") sizes = v;
    else if (a == "--family") family = v;
    else if (a == "--tags") tags = std::stoi(v);
    else if (a == "--seed") seed = static_cast<unsigned>(std::stoul(v));
    else throw std::invalid_argument("unknown option " + a);
  }
  const std::vector<Size> size_list = parse_sizes(sizes);
  cv::setNumThreads(0);  // see the file comment: no thread pool across fork()

  std::ostringstream csv;
  csv << "width,height,megapixels,half_resolution,families,max_hamming,seg_sigma,max_pixels,tags_in_scene,"
         "detections,detect_ms,peak_rss_mb,bytes_per_pixel,workspace_mb,warm_frame_peak_mb\n";
  const Setting settings[] = {{"full", false}, {"half", true}};
  for (const Size& s : size_list) {
    std::cerr << "detect_memory: " << s.width << "x" << s.height << " scene\n";
    const Scene scene = make_scene(s.width, s.height, family, tags, seed);
    malloc_trim(0);
    const double pixels = static_cast<double>(s.width) * s.height;
    for (const Setting& set : settings) {
      DetectorOptions opt = DetectorOptions::paper();
      opt.families = {family};
      opt.half_resolution = set.half_resolution;
      const Measurement m = measure_in_child(scene.image, opt);
      const double mb = 1024.0 * 1024.0;
      csv << s.width << ',' << s.height << ',' << format_number(pixels / 1e6, "%.3f") << ','
          << (set.half_resolution ? 1 : 0) << ',' << family << ',' << opt.max_hamming << ',' << opt.seg_sigma << ','
          << opt.max_pixels << ',' << scene.tags.size() << ',' << m.detections << ',' << format_number(m.ms, "%.1f")
          << ',' << format_number(m.first_peak / mb, "%.1f") << ',' << format_number(m.first_peak / pixels, "%.1f")
          << ',' << format_number(m.workspace / mb, "%.1f") << ',' << format_number(m.warm_peak / mb, "%.2f") << '\n';
      std::cerr << "  " << set.name << ": peak +" << format_number(m.first_peak / mb, "%.1f") << " MB ("
                << format_number(m.first_peak / pixels, "%.1f") << " B/px), workspace "
                << format_number(m.workspace / mb, "%.1f") << " MB, warm frame +"
                << format_number(m.warm_peak / mb, "%.2f") << " MB, " << m.detections << "/" << scene.tags.size()
                << " tags, " << format_number(m.ms, "%.0f") << " ms\n";
    }
  }
  write_file_atomic(out, csv.str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::invalid_argument& e) {
    std::cerr << "detect_memory: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "detect_memory: " << e.what() << "\n";
    return 1;
  }
}
