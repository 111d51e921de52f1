#include "cli/detect_pipeline.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <exception>
#include <iterator>
#include <stdexcept>
#include <system_error>
#include <utility>

#include "cli/detect_explain.hpp"
#include "cli/detect_pictures.hpp"
#include "cli/image_file.hpp"
#include "detect/detector_opencv.hpp"
#include "detect/image.hpp"
#include "tools/atomic_file.hpp"

namespace tagbench::cli::detect_cmd {

namespace fs = std::filesystem;

Outcome Processor::run(Job& job, DetectorWorkspace& ws) const {
  Outcome o;
  o.label = job.label;
  o.frame_number = job.frame_number;
  if (!job.error.empty()) {
    o.error = job.error;
    return o;
  }
  std::vector<fs::path> written;
  try {
    const cv::Mat img = std::move(job.frame);
    o.width = img.cols;
    o.height = img.rows;
    const bool debug = s_.debug_dir.has_value();
    DetectorTrace trace;
    const auto t0 = std::chrono::steady_clock::now();
    o.detections = detect(det_, img, ws, debug || !s_.explain.empty() ? &trace : nullptr);
    o.detect_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

    for (const ExplainPoint& p : s_.explain) {
      // Pixel centres at integers: the image covers [-0.5, W - 0.5] x [-0.5, H - 0.5].
      if (!(p.at.x() >= -0.5 && p.at.y() >= -0.5 && p.at.x() <= o.width - 0.5 && p.at.y() <= o.height - 0.5)) {
        o.explained.push_back({p.spec, p.at, "outside_image", -1, -1,
                               "the point is outside the image (" + std::to_string(o.width) + " x " +
                                   std::to_string(o.height) + " px)"});
        continue;
      }
      o.explained.push_back(explain_point(p, trace, o.detections, det_));
    }

    // Pictures: everything encoded first, then written (each atomically); on a failure the
    // pictures already written for this input are removed, so a failed input leaves nothing.
    std::vector<std::pair<fs::path, std::string>> files;
    if (s_.draw) {
      const cv::Mat pic = draw_detections(img, o.detections, det_.options(), det_.families().size() > 1);
      if (s_.draw_is_file) {
        files.emplace_back(*s_.draw, encode(pic, lower(s_.draw->extension().string())));
      } else {
        files.emplace_back(*s_.draw / (job.out_name + ".png"), encode(pic, ".png"));
      }
    }
    if (debug) {
      const auto pics = stage_pictures(to_float_image(img), trace, o.detections, det_);
      for (std::size_t i = 0; i < pics.size(); ++i)
        if (!pics[i].empty())
          files.emplace_back(*s_.debug_dir / (job.out_name + "_" + kStages[i] + ".png"), encode(pics[i], ".png"));
    }
    for (const auto& [path, bytes] : files) {
      make_parent(path);
      write_file_atomic(path, bytes);
      written.push_back(path);
    }
  } catch (const std::exception& e) {
    fail(o, written, e.what());
  } catch (...) {
    fail(o, written, "unknown error");
  }
  return o;
}

void Processor::remove_empty_created_dirs() const {
  std::lock_guard<std::mutex> lock(dir_mutex_);
  std::vector<fs::path> dirs = created_dirs_;
  std::sort(dirs.begin(), dirs.end(), [](const fs::path& a, const fs::path& b) {
    return std::distance(a.begin(), a.end()) > std::distance(b.begin(), b.end());
  });
  for (const auto& d : dirs) {
    std::error_code ec;
    fs::remove(d, ec);  // fails, harmlessly, on a directory with files in it
  }
}

void Processor::fail(Outcome& o, const std::vector<fs::path>& written, const std::string& why) {
  for (const auto& p : written) {
    std::error_code ec;
    fs::remove(p, ec);
  }
  o.error = why.empty() ? "failed" : why;
  o.detections.clear();
}

void Processor::make_parent(const fs::path& file) const {
  if (s_.draw_is_file && s_.draw && file == *s_.draw) return;
  const fs::path dir = file.parent_path();
  std::lock_guard<std::mutex> lock(dir_mutex_);
  std::error_code ec;
  if (fs::is_directory(dir, ec)) return;
  for (fs::path d = dir; !d.empty() && !fs::exists(d, ec); d = d.parent_path()) {
    created_dirs_.push_back(d);
    if (d == d.parent_path()) break;
  }
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error("cannot create directory " + dir.string() + ": " + ec.message());
}

Pipeline::Pipeline(const Processor& proc, Sink& sink, int threads)
    : proc_(proc), sink_(sink), window_(static_cast<std::size_t>(threads) * 2 + 2),
      bar_("detect", ::isatty(STDERR_FILENO) != 0), start_(std::chrono::steady_clock::now()) {
  for (int i = 0; i < threads; ++i) workers_.emplace_back([this] { work(); });
}

void Pipeline::submit(Job job) {
  while (submitted_ - emitted_ >= window_) emit_next();
  job.index = submitted_++;
  {
    std::lock_guard<std::mutex> lock(m_);
    queue_.push_back(std::move(job));
  }
  work_cv_.notify_one();
}

void Pipeline::finish() {
  while (emitted_ < submitted_) emit_next();
  stop();
}

void Pipeline::emit_next() {
  Outcome o;
  {
    std::unique_lock<std::mutex> lock(m_);
    done_cv_.wait(lock, [&] { return done_.count(emitted_) > 0; });
    auto it = done_.find(emitted_);
    o = std::move(it->second);
    done_.erase(it);
  }
  sink_.emit(o);
  ++emitted_;
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const std::size_t total = std::max(expected_, emitted_);
  const double rate = elapsed > 0 ? static_cast<double>(emitted_) / elapsed : 0.0;
  char detail[64];
  std::snprintf(detail, sizeof detail, "%.1f img/s", rate);
  bar_.update(static_cast<double>(emitted_) / static_cast<double>(total),
              std::to_string(emitted_) + "/" + std::to_string(total) + " images", detail,
              rate > 0 ? static_cast<double>(total - emitted_) / rate : -1.0);
}

void Pipeline::work() {
  DetectorWorkspace ws;  // this worker's detection buffers, reused frame after frame
  while (true) {
    Job job;
    {
      std::unique_lock<std::mutex> lock(m_);
      work_cv_.wait(lock, [&] { return closing_ || !queue_.empty(); });
      if (queue_.empty()) return;
      job = std::move(queue_.front());
      queue_.pop_front();
    }
    const std::size_t index = job.index;
    Outcome o = proc_.run(job, ws);
    {
      std::lock_guard<std::mutex> lock(m_);
      done_.emplace(index, std::move(o));
    }
    done_cv_.notify_all();
  }
}

void Pipeline::stop() {
  {
    std::lock_guard<std::mutex> lock(m_);
    closing_ = true;
  }
  work_cv_.notify_all();
  for (auto& t : workers_)
    if (t.joinable()) t.join();
}

}  // namespace tagbench::cli::detect_cmd
