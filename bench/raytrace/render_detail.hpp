#pragma once
// What render.cpp (frames, cache keys, a frame's #case) and render_frames.cpp (the cache lookup and
// the povray runs) share and nothing else needs: the render flags and the template's placeholder, the
// cache keys, and the text a frame puts into the batch's scene.
#include <cstddef>
#include <map>
#include <string>
#include <string_view>

#include "codes/tag_family.hpp"
#include "codes/tag_layout.hpp"
#include "raytrace/render.hpp"

namespace tagbench::bench::render_detail {

// The render settings of docs/paper-to-code.md section 4 (besides the animation and thread flags); part of every key.
inline constexpr const char* kRenderFlags[] = {"+FN", "-D", "+W400", "+H400", "+A0.1", "+AM2", "+R3", "File_Gamma=1.0", "-V"};
inline constexpr const char* kPlaceholder = "@FRAME_SWITCH@";

// Cache keys: 64-bit FNV-1a as 16 hex digits.
std::string key_of(std::string_view text);

// A frame's tag image and size, and the SDL of its #case.
struct FrameScene {
  std::string tag_png;   // file name in the cache directory, named by the cells
  double tag_width = 0;  // whole printed tag, metres
};

FrameScene frame_scene(const FramePose& f, const TagCells& cells);

// The frame's `#case (number)` of the batch scene's #switch (frame_number).
std::string frame_case(int number, const FramePose& f, const FrameScene& scene);

// Everything that determines a frame's pixels, as text (what key_of names it by).
std::string frame_key_text(const FramePose& f, const std::string& template_key, const TagCells& cells);

// Throws std::invalid_argument "frame INDEX: ..." for a frame that cannot be rendered.
void check_frame(const FramePose& f, std::size_t index);

// The frame's tag cells, its family loaded once into `families` (load_family's errors pass through);
// an id out of range throws std::invalid_argument "frame INDEX: ...".
TagCells cells_for(std::map<std::string, TagFamily>& families, const FramePose& f, std::size_t index);

}  // namespace tagbench::bench::render_detail
