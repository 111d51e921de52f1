// External detectors: the command, its batch, its lines (external_detector.hpp).
#include "external/external_detector.hpp"

#include <atomic>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>

#include "tools/atomic_file.hpp"
#include "tools/child_process.hpp"
#include "tools/format.hpp"
#include "tools/shell_words.hpp"

namespace tagbench::bench {

ExternalDetector parse_external_detector(const std::string& spec, double timeout_seconds) {
  const std::size_t eq = spec.find('=');
  if (eq == std::string::npos) throw std::invalid_argument("external:" + spec + ": expected external:NAME=COMMAND");
  ExternalDetector d;
  d.name = spec.substr(0, eq);
  d.command = spec.substr(eq + 1);
  d.timeout_seconds = timeout_seconds;
  if (d.name.empty() || d.name.find_first_of(",\"\r\n ") != std::string::npos)
    throw std::invalid_argument("external:" + spec + ": NAME must be non-empty, without commas, quotes or blanks");
  try {
    d.argv = split_shell_words(d.command);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("external detector " + d.name + ": COMMAND '" + d.command + "': " + e.what());
  }
  return d;
}

namespace {

std::string last_line(const std::string& text) {
  std::string t = text;
  while (!t.empty() && (t.back() == '\n' || t.back() == '\r')) t.pop_back();
  const std::size_t nl = t.rfind('\n');
  std::string l = nl == std::string::npos ? t : t.substr(nl + 1);
  for (char& c : l)
    if (static_cast<unsigned char>(c) < 0x20) c = ' ';
  return l.size() > 200 ? l.substr(0, 200) + "..." : l;
}

}  // namespace

std::vector<ImageDetections> run_external(const ExternalDetector& d, const std::vector<std::string>& images,
                                          const std::filesystem::path& workdir) {
  const std::string who = "external detector " + d.name;
  std::string list;
  std::map<std::string, std::size_t> index;
  for (std::size_t i = 0; i < images.size(); ++i) {
    list += images[i] + "\n";
    index.emplace(images[i], i);
  }
  const std::filesystem::path in = workdir / (d.name + ".stdin"), out = workdir / (d.name + ".stdout"),
                              err = workdir / (d.name + ".stderr");
  write_file_atomic(in, list);
  const ChildStatus st = run_child_io(d.argv, workdir, {in, out, err, d.timeout_seconds});
  const std::string text = read_file(out);

  // What it answered, line by line, up to the first line that is not a detection line.
  std::vector<ImageDetections> got(images.size());
  std::vector<bool> have(images.size(), false);
  std::string bad;  // the first bad line's message
  bool bad_names_image = false;
  std::size_t start = 0, line = 0;
  while (start < text.size() && bad.empty()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) {
      if (st.code() == 0 && !st.timed_out) end = text.size();
      else break;  // an unfinished last line of a run that did not end well
    }
    const std::string_view l(text.data() + start, end - start);
    ++line;
    start = end + 1;
    if (l.find_first_not_of(" \t\r") == std::string_view::npos) continue;
    const std::string where = who + ": output line " + std::to_string(line);
    try {
      ImageDetections det = parse_detection_line(l);
      det.line = line;
      const auto it = index.find(det.image);
      if (it == index.end()) {
        bad = where + " names image '" + det.image + "', which it was not given";
        break;
      }
      if (have[it->second]) {
        bad = where + ": image '" + det.image + "' given twice";
        break;
      }
      if (!det.error.empty()) {
        bad = who + ": image '" + det.image + "': " + det.error;
        bad_names_image = true;
        break;
      }
      have[it->second] = true;
      got[it->second] = std::move(det);
    } catch (const std::exception& e) {
      bad = where + " is not a detection line (" + e.what() + ")";
    }
  }
  std::size_t missing = 0, first_missing = images.size();
  for (std::size_t i = 0; i < images.size(); ++i)
    if (!have[i]) {
      ++missing;
      if (first_missing == images.size()) first_missing = i;
    }
  const std::string first_image = first_missing < images.size() ? images[first_missing] : std::string("(none)");
  if (st.timed_out)
    throw std::runtime_error(who + ": no end within " + format_number(d.timeout_seconds, "%.10g") +
                             " s (--external-timeout); killed at image '" + first_image + "' (" +
                             std::to_string(missing) + " of " + std::to_string(images.size()) + " images without a line)");
  if (st.exit_code == 127 || st.exit_code == 126)
    throw std::runtime_error(who + ": cannot run '" + d.argv[0] + "' (not found or not executable), at image '" +
                             first_image + "'");
  if (st.code() != 0) {
    const std::string why = st.signal ? "was killed by signal " + std::to_string(st.signal)
                                      : "exited with status " + std::to_string(st.exit_code);
    const std::string tail = last_line(read_file(err));
    throw std::runtime_error(who + ": " + why + " at image '" + first_image + "'" +
                             (tail.empty() ? "" : " (its last message: " + tail + ")"));
  }
  if (!bad.empty())
    throw std::runtime_error(bad_names_image ? bad : bad + " (first image without a valid line: '" + first_image + "')");
  if (missing)
    throw std::runtime_error(who + ": no line for image '" + first_image + "' (" + std::to_string(missing) + " of " +
                             std::to_string(images.size()) + " images left out)");
  return got;
}

ExternalWorkDir::ExternalWorkDir() {
  constexpr std::string_view kPrefix = "tagbench-external-";
  static std::atomic<int> counter{0};
  const std::filesystem::path tmp = std::filesystem::temp_directory_path();
  std::error_code ec;
  for (std::filesystem::directory_iterator it(tmp, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string n = it->path().filename().string();
    std::error_code rec;
    if (n.starts_with(kPrefix) && owner_prefix_is_gone(n.substr(kPrefix.size())) && it->is_directory(rec))
      std::filesystem::remove_all(it->path(), rec);
  }
  path_ = tmp / (std::string(kPrefix) + owner_tag() + "-" + std::to_string(counter++));
  std::filesystem::remove_all(path_);
  std::filesystem::create_directories(path_);
}

ExternalWorkDir::~ExternalWorkDir() {
  std::error_code ec;
  std::filesystem::remove_all(path_, ec);
}

std::vector<ImageDetections> run_external(const ExternalDetector& d, const std::vector<std::string>& images) {
  const ExternalWorkDir dir;
  return run_external(d, images, dir.path());
}

}  // namespace tagbench::bench
