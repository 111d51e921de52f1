// render_frames (render.hpp): the frames looked up in the cache, and the missing ones rendered as one
// batch scene by povray processes running at once; and the povray executable found and its errors read.
#include "raytrace/render.hpp"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <thread>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "raytrace/render_batches.hpp"
#include "raytrace/render_detail.hpp"
#include "tools/atomic_file.hpp"
#include "tools/child_process.hpp"
#include "tools/sysinfo.hpp"

namespace tagbench::bench {

using namespace render_detail;

namespace {

namespace fs = std::filesystem;

// The executable povray would run, or nullopt.
std::optional<fs::path> find_executable(const std::string& name) {
  if (name.empty()) return std::nullopt;
  const auto usable = [](const fs::path& p) {
    std::error_code ec;
    return fs::is_regular_file(p, ec) && ::access(p.c_str(), X_OK) == 0;
  };
  if (name.find('/') != std::string::npos) {
    if (usable(name)) return fs::absolute(name);
    return std::nullopt;
  }
  const char* path = std::getenv("PATH");
  if (!path) return std::nullopt;
  std::string_view rest(path);
  while (true) {
    const auto colon = rest.find(':');
    const std::string dir(rest.substr(0, colon));
    const fs::path candidate = fs::path(dir.empty() ? "." : dir) / name;
    if (usable(candidate)) return fs::absolute(candidate);
    if (colon == std::string_view::npos) break;
    rest.remove_prefix(colon + 1);
  }
  return std::nullopt;
}

// POV-Ray's error message from its log: the first line naming an error, with its wrapped continuation lines.
std::string povray_error(const fs::path& log, const ChildStatus& status) {
  std::string text;
  try {
    text = read_file(log);
  } catch (const std::exception&) {
  }
  std::vector<std::string> lines;
  for (std::size_t pos = 0; pos < text.size();) {
    const auto nl = text.find('\n', pos);
    lines.push_back(text.substr(pos, nl == std::string::npos ? std::string::npos : nl - pos));
    pos = nl == std::string::npos ? text.size() : nl + 1;
  }
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (lines[i].find("Error") == std::string::npos && lines[i].find("error") == std::string::npos) continue;
    std::string msg = lines[i];
    for (std::size_t j = i + 1; j < lines.size() && !lines[j].empty() && lines[j][0] == ' '; ++j) msg += lines[j];
    return "povray: " + msg;
  }
  if (status.signal != 0) return "povray was killed by signal " + std::to_string(status.signal);
  if (status.exit_code != 0) return "povray exited with status " + std::to_string(status.exit_code);
  return "povray wrote no image for this frame";
}

std::size_t placeholder_count(const std::string& t) {
  std::size_t n = 0;
  for (auto p = t.find(kPlaceholder); p != std::string::npos; p = t.find(kPlaceholder, p + 1)) ++n;
  return n;
}

// One distinct frame to render.
struct Job {
  std::string key;
  const FramePose* frame = nullptr;
  FrameScene scene;
  TagCells cells;
  std::string error;
  bool done = false;
};

}  // namespace

std::optional<fs::path> find_povray(const std::string& povray) { return find_executable(povray); }

RenderReport render_frames(const std::vector<FramePose>& frames, const std::string& scene_template,
                           const RenderOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  if (placeholder_count(scene_template) != 1)
    throw std::invalid_argument(std::string("the scene template must contain ") + kPlaceholder + " exactly once");
  if (options.cache_dir.empty()) throw std::invalid_argument("no cache directory given");
  fs::create_directories(options.cache_dir);
  const fs::path dir = fs::absolute(options.cache_dir);
  const std::string template_key = key_of(scene_template);

  // Before the cache is looked up: frames a killed run finished are in it again.
  clear_dead_batches(dir);

  RenderReport report;
  report.frames.resize(frames.size());
  std::map<std::string, TagFamily> families;
  std::vector<Job> jobs;                        // distinct frames to render, in first-seen order
  std::map<std::string, std::size_t> job_of;    // key -> index into jobs
  std::vector<std::ptrdiff_t> frame_job(frames.size(), -1);
  std::set<std::string> cached;                // keys found in the cache
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const FramePose& f = frames[i];
    check_frame(f, i);
    const TagCells cells = cells_for(families, f, i);
    const std::string key = key_of(frame_key_text(f, template_key, cells));
    const fs::path png = dir / ("frame-" + key + ".png");
    RenderedFrame& out = report.frames[i];
    if (auto it = job_of.find(key); it != job_of.end()) {
      frame_job[i] = static_cast<std::ptrdiff_t>(it->second);
      continue;
    }
    if (cached.contains(key) || decodes_as_frame(png)) {
      if (cached.insert(key).second) ++report.from_cache;
      out.png = png;
      out.from_cache = true;
      continue;
    }
    Job job;
    job.key = key;
    job.frame = &f;
    job.scene = frame_scene(f, cells);
    job.cells = cells;
    job_of.emplace(key, jobs.size());
    frame_job[i] = static_cast<std::ptrdiff_t>(jobs.size());
    jobs.push_back(std::move(job));
  }

  if (!jobs.empty()) {
    const auto exe = find_executable(options.povray);
    if (!exe) {
      if (options.povray == "povray") throw std::runtime_error("povray not found: install the Debian package povray");
      throw std::runtime_error("povray '" + options.povray + "': " +
                               (options.povray.find('/') != std::string::npos ? "not an executable file"
                                                                              : "no executable of this name in PATH"));
    }

    // The tags' images, one pixel per cell, named by their content.
    for (const Job& j : jobs) {
      const fs::path tag_path = dir / j.scene.tag_png;
      std::error_code ec;
      const cv::Mat existing =
          fs::is_regular_file(tag_path, ec) ? cv::imread(tag_path.string(), cv::IMREAD_UNCHANGED) : cv::Mat();
      if (existing.rows == j.cells.n && existing.cols == j.cells.n) continue;
      cv::Mat img(j.cells.n, j.cells.n, CV_8UC1);
      for (int y = 0; y < j.cells.n; ++y)
        for (int x = 0; x < j.cells.n; ++x) img.at<std::uint8_t>(y, x) = j.cells.at(y, x) ? 255 : 0;
      std::vector<std::uint8_t> bytes;
      if (!cv::imencode(".png", img, bytes)) throw std::runtime_error(tag_path.string() + ": PNG encoding failed");
      write_file_atomic(tag_path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
    }

    // One scene for every missing frame, numbered 1..M in job order.
    std::string keys;
    std::vector<std::string> job_keys;
    for (const Job& j : jobs) {
      keys += j.key;
      job_keys.push_back(j.key);
    }
    // The owner first, so that a later run can clear this batch's files should this process be killed;
    // the keys, so that it can keep the frames this batch finished (render_batches.hpp).
    const std::string batch = owner_tag() + "-" + key_of(keys).substr(0, 12);
    std::string cases = "#switch (frame_number)\n";
    for (std::size_t k = 0; k < jobs.size(); ++k) cases += frame_case(static_cast<int>(k + 1), *jobs[k].frame, jobs[k].scene);
    cases += "#else\n  #error \"tagbench: no frame with this number\"\n#end\n";
    std::string scene = scene_template;
    scene.replace(scene.find(kPlaceholder), std::string(kPlaceholder).size(), cases);
    const std::string scene_file = "batch-" + batch + ".pov";
    write_batch_keys(dir, batch, job_keys);
    write_file_atomic(dir / scene_file, scene);
    const int total = static_cast<int>(jobs.size());
    const int final_frame = std::max(total, 2);  // +KFF1 would switch animation (and frame-numbered names) off
    const int digits = static_cast<int>(std::to_string(final_frame).size());
    const auto tmp_name = [&](int k) {
      std::string n = std::to_string(k);
      return "tmp-" + batch + "-" + std::string(static_cast<std::size_t>(digits) - n.size(), '0') + n + ".png";
    };

    // Chunks of consecutive frame numbers, at least one per process, at most max_frames_per_process long.
    const int processes = options.processes > 0 ? options.processes : hardware_threads();
    const int per = std::max(1, options.max_frames_per_process);
    const int chunk_count = std::min(total, std::max(processes, (total + per - 1) / per));
    std::vector<std::pair<int, int>> chunks;
    for (int c = 0, first = 1; c < chunk_count; ++c) {
      const int len = total / chunk_count + (c < total % chunk_count ? 1 : 0);
      chunks.emplace_back(first, first + len - 1);
      first += len;
    }

    std::mutex mu;  // guards jobs[*].done/error, the counters, the chunk queue and progress calls
    std::size_t next_chunk = 0, finished = 0;
    std::atomic<bool> any_success{false};
    std::optional<std::string> systematic;  // every frame fails the same way (a broken template): stop
    std::atomic<int> runs{0};
    std::exception_ptr worker_error;  // a system failure (fork, rename): rethrown after the workers stop
    const auto work = [&](int worker_id) {
      int run_no = 0, same_failures = 0;
      std::string last_failure;
      while (true) {
        std::pair<int, int> chunk;
        {
          std::lock_guard lock(mu);
          if (next_chunk == chunks.size()) return;
          chunk = chunks[next_chunk++];
        }
        int next = chunk.first;
        while (next <= chunk.second) {
          {
            std::lock_guard lock(mu);
            if (systematic) {
              for (int k = next; k <= chunk.second; ++k) {
                jobs[static_cast<std::size_t>(k - 1)].error = *systematic;
                ++finished;
              }
              if (options.progress) options.progress(finished, jobs.size());
              break;
            }
          }
          const std::string log =
              "batch-" + batch + "-w" + std::to_string(worker_id) + "-" + std::to_string(run_no++) + ".log";
          std::vector<std::string> args{"+I" + scene_file, "+Otmp-" + batch + "-.png"};
          for (const char* q : kRenderFlags) args.emplace_back(q);
          args.insert(args.end(), {"+WT1", "+KFI1", "+KFF" + std::to_string(final_frame), "+SF" + std::to_string(next),
                                   "+EF" + std::to_string(chunk.second)});
          // POV-Ray dies with us (run_child): after a kill -9 an orphan would render on for minutes,
          // for nobody (its frames are only ever moved into the cache by this process).
          std::vector<std::string> argv{exe->string()};
          argv.insert(argv.end(), args.begin(), args.end());
          const ChildStatus status = run_child(argv, dir, dir / log, options.nice);
          ++runs;
          int k = next;
          std::size_t newly = 0;
          for (; k <= chunk.second; ++k) {
            const fs::path tmp = dir / tmp_name(k);
            if (!decodes_as_frame(tmp)) break;
            Job& j = jobs[static_cast<std::size_t>(k - 1)];
            fs::rename(tmp, dir / ("frame-" + j.key + ".png"));
            j.done = true;
            ++newly;
          }
          std::string failure;
          std::error_code ec;
          if (k <= chunk.second) {
            failure = povray_error(dir / log, status);
            fs::remove(dir / tmp_name(k), ec);  // a partial image, if any
          }
          fs::remove(dir / log, ec);
          std::lock_guard lock(mu);
          finished += newly;
          if (newly > 0) {
            any_success = true;
            same_failures = 0;
          }
          if (k <= chunk.second) {
            // Frame k failed (POV-Ray stops at the first frame it cannot render); the rest go on.
            jobs[static_cast<std::size_t>(k - 1)].error = failure;
            ++finished;
            same_failures = failure == last_failure ? same_failures + 1 : 1;
            last_failure = failure;
            if (same_failures >= 3 && !any_success && !systematic) systematic = "not rendered: " + failure;
          }
          if (options.progress) options.progress(finished, jobs.size());
          next = k + 1;
        }
      }
    };
    const auto worker = [&](int worker_id) {
      try {
        work(worker_id);
      } catch (...) {
        std::lock_guard lock(mu);
        if (!worker_error) worker_error = std::current_exception();
        next_chunk = chunks.size();  // the others stop after their current run
      }
    };
    std::vector<std::thread> threads;
    const int nthreads = std::min<int>(processes, static_cast<int>(chunks.size()));
    for (int w = 0; w < nthreads; ++w) threads.emplace_back(worker, w);
    for (auto& t : threads) t.join();
    if (worker_error) std::rethrow_exception(worker_error);
    report.povray_runs = runs;
    for (const Job& j : jobs) {
      if (j.done)
        ++report.rendered;
      else
        ++report.failed;
    }
    std::error_code ec;
    // Kept otherwise, as POV-Ray's messages cite its lines, until the next run that renders (clear_dead_batches).
    if (report.failed == 0) fs::remove(dir / scene_file, ec);
    fs::remove(dir / ("batch-" + batch + ".keys"), ec);
    for (std::size_t i = 0; i < frames.size(); ++i) {
      if (frame_job[i] < 0) continue;
      const Job& j = jobs[static_cast<std::size_t>(frame_job[i])];
      RenderedFrame& out = report.frames[i];
      if (j.done) {
        out.png = dir / ("frame-" + j.key + ".png");
      } else {
        out.error = j.error.empty() ? "povray wrote no image for this frame" : j.error;
      }
    }
  }
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return report;
}

}  // namespace tagbench::bench
