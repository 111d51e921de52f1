// tagbench render: a tag as a PNG (1 pixel per cell by default, the form POV-Ray's image_map needs)
// or a printable SVG whose black square has a given size in millimetres.
#include <opencv2/imgcodecs.hpp>

#include <filesystem>

#include "cli/args.hpp"
#include "cli/commands.hpp"
#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "tools/atomic_file.hpp"

namespace tagbench::cli {

namespace {
constexpr const char* kRenderHelp = R"(usage: tagbench render --family F --id N [--px-per-cell K] [--tag-size-mm S] -o FILE

Writes tag N of family F (a built-in name or a family file).
  -o, --out FILE       output; .png: (d+4)*K pixels square, white ring, black ring, payload
                       (K = 1 by default: one pixel per cell, as POV-Ray's image_map wants);
                       .svg: printable vector tag
  --px-per-cell K      PNG pixels per cell, 1..1000 (default 1)
  --tag-size-mm S      SVG: edge of the black square in mm, the pose 'tag size' (default 100)
)";
}

int cmd_render(const Words& words) {
  if (wants_help(words, kRenderHelp)) return 0;
  const Args a(words, {{"family"}, {"id"}, {"px-per-cell"}, {"tag-size-mm"}, {"out", true, false, "o"}});
  if (!a.positionals().empty()) throw UsageError("unexpected argument '" + a.positionals()[0] + "'");
  if (!a.has("family")) throw UsageError("--family is required");
  if (!a.has("id")) throw UsageError("--id is required");
  if (!a.has("out")) throw UsageError("-o/--out is required");
  const TagFamily family = usage_on_invalid("--family: ", [&] { return load_family(*a.get("family")); });
  const long long id = a.get_int("id", 0, 0, 1LL << 40);
  const TagCells cells = usage_on_invalid("--id: ", [&] { return tag_cells(family, static_cast<int>(id)); });
  const std::filesystem::path out = *a.get("out");
  const std::string ext = out.extension().string();
  if (ext == ".svg") {
    if (a.has("px-per-cell")) throw UsageError("--px-per-cell applies to PNG output only");
    const double mm = a.get_double("tag-size-mm", 100.0, 1e-3, 1e6);
    write_file_atomic(out, tag_svg(cells, mm, family.name() + " id " + std::to_string(id)));
  } else if (ext == ".png") {
    if (a.has("tag-size-mm")) throw UsageError("--tag-size-mm applies to SVG output only");
    const int k = static_cast<int>(a.get_int("px-per-cell", 1, 1, 1000));
    cv::Mat img(cells.n * k, cells.n * k, CV_8UC1);
    for (int y = 0; y < img.rows; ++y)
      for (int x = 0; x < img.cols; ++x) img.at<std::uint8_t>(y, x) = cells.at(y / k, x / k) ? 255 : 0;
    std::vector<std::uint8_t> png;
    if (!cv::imencode(".png", img, png)) throw std::runtime_error(out.string() + ": PNG encoding failed");
    write_file_atomic(out, std::string_view(reinterpret_cast<const char*>(png.data()), png.size()));
  } else {
    throw UsageError("-o " + out.string() + ": unknown output format (use .png or .svg)");
  }
  return 0;
}

}  // namespace tagbench::cli
