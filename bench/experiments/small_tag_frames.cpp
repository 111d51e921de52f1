#include "experiments/small_tag_frames.hpp"

#include <stdexcept>

#include "raytrace/sweeps.hpp"
#include "realistic/realistic_set.hpp"

namespace tagbench::bench::experiments {
namespace {

std::vector<TruthFrame> raytraced(const FrameSource& src) {
  SweepSettings s;
  s.trials = src.count;
  s.seed = src.seed;
  s.detectors = {"tagbench-paper"};
  if (src.kind == "distance") {
    s.experiment = Experiment::kDistance;
    s.steps = src.steps;
  } else {
    s.experiment = Experiment::kConditions;
    s.conditions = {Condition::kBlur};
  }
  std::vector<SweepFrame> plan = plan_sweep(s);
  if (src.kind == "blur" && !src.steps.empty())
    std::erase_if(plan, [&](const SweepFrame& f) {
      return std::find(src.steps.begin(), src.steps.end(), f.step) == src.steps.end();
    });
  std::vector<FramePose> poses;
  for (const auto& f : plan) poses.push_back(f.frame);
  RenderOptions ro;
  ro.cache_dir = src.cache;
  ro.processes = src.processes;
  ro.nice = 10;
  const RenderReport rep = render_frames(poses, scene_template(SceneKind::kPlain), ro);
  std::vector<TruthFrame> out;
  for (std::size_t i = 0; i < plan.size(); ++i) {
    if (!rep.frames[i].ok()) throw std::runtime_error("frame " + std::to_string(i) + " did not render: " + rep.frames[i].error);
    TruthFrame t;
    t.label = src.kind + " " + std::to_string(plan[i].step) + " #" + std::to_string(plan[i].trial);
    t.condition = plan[i].step;
    t.gray8 = apply_effect(read_frame_gray(rep.frames[i].png), plan[i]);
    t.tags.push_back(TruthTag{plan[i].frame.id, plan[i].truth.corners, plan[i].truth.black_square_px,
                              view_angle_deg(plan[i].truth.pose)});
    out.push_back(std::move(t));
  }
  return out;
}

}  // namespace

std::vector<TruthFrame> make_frames(const FrameSource& src) {
  if (src.kind == "distance" || src.kind == "blur") return raytraced(src);
  if (src.kind != "realistic") throw std::invalid_argument("unknown frame source '" + src.kind + "' (realistic, distance, blur)");
  bench::RealisticSettings rs;
  rs.seed = src.seed;
  std::vector<TruthFrame> out;
  for (int i = 0; i < src.count; ++i) {
    const bench::RealisticFrame f = bench::make_realistic_frame(rs, i);
    TruthFrame t;
    t.label = "realistic#" + std::to_string(i);
    t.condition = f.degradation.blur_sigma_px;
    t.gray8 = f.image;
    for (const auto& g : f.tags) t.tags.push_back(TruthTag{g.id, g.corners, g.black_square_px, g.tilt_deg});
    out.push_back(std::move(t));
  }
  return out;
}

}  // namespace tagbench::bench::experiments
