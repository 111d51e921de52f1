// Exported datasets (issue 12, section 1): the files hold the sweep's frames bit for bit (read back
// through truth.json: poses, corners, views; the PNGs: the images the detectors get), a distortion
// frame carries its lens, and the folder rules (new, empty, an earlier dataset; nothing else) hold.
#include <gtest/gtest.h>

#include <fstream>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "../../raytrace/tests/test_frames.hpp"
#include "dataset/dataset.hpp"
#include "scratch_dir.hpp"
#include "tools/atomic_file.hpp"

namespace tagbench::bench {
namespace test_dataset {
namespace {

namespace fs = std::filesystem;

SweepSettings small_conditions() {
  SweepSettings s;
  s.experiment = Experiment::kConditions;
  s.trials = 1;
  s.conditions = {Condition::kNoise, Condition::kDistortion};  // one render: both are image effects
  return s;
}

// The plan's frames rendered (from the shared cache) as the sweep renders them.
RenderReport render_plan(const std::vector<SweepFrame>& plan) {
  std::vector<FramePose> poses;
  for (const auto& f : plan) poses.push_back(f.frame);
  return render_frames(poses, scene_template(SceneKind::kPlain), test::gentle_options(test::shared_cache()));
}

TEST(Dataset, FilesHoldTheSweepsFramesExactly) {
  if (!test::have_povray()) GTEST_SKIP() << "povray not installed";
  const SweepSettings s = small_conditions();
  const DatasetFiles files = make_dataset(s, test::gentle_options(test::shared_cache()));
  testing::ScratchDir dir("tagbench_dataset");
  write_dataset(dir.path() / "ds", files);
  const Dataset d = read_dataset(dir.path() / "ds");

  SweepSettings with_ours = s;
  with_ours.detectors = {comparator_names().front()};
  const std::vector<SweepFrame> plan = plan_sweep(with_ours);
  ASSERT_EQ(d.frames.size(), plan.size());
  EXPECT_EQ(d.settings.experiment, Experiment::kConditions);
  EXPECT_EQ(d.settings.conditions, s.conditions);
  const RenderReport report = render_plan(plan);
  for (std::size_t i = 0; i < plan.size(); ++i) {
    const DatasetFrame& got = d.frames[i];
    const SweepFrame& want = plan[i];
    EXPECT_EQ(got.index, i);
    EXPECT_EQ(got.file, dataset_frame_file(i));
    EXPECT_EQ(got.frame.condition, want.condition);
    EXPECT_EQ(got.frame.step, want.step);
    EXPECT_EQ(got.frame.seed, want.seed);
    EXPECT_EQ(got.frame.frame.id, want.frame.id);
    EXPECT_EQ(got.frame.frame.pose.R, want.frame.pose.R);  // bit for bit
    EXPECT_EQ(got.frame.frame.pose.t, want.frame.pose.t);
    for (std::size_t k = 0; k < 4; ++k) EXPECT_EQ(got.frame.truth.corners[k], want.truth.corners[k]);
    EXPECT_EQ(got.frame.truth.black_square_px, want.truth.black_square_px);
    EXPECT_EQ(got.frame.view.roll_deg, want.view.roll_deg);
    EXPECT_EQ(got.frame.view.pixel, want.view.pixel);
    const bool distorted = want.condition == Condition::kDistortion && want.step != 0;
    ASSERT_EQ(got.distortion.has_value(), distorted) << i;
    if (distorted) {
      EXPECT_EQ((*got.distortion)[0], -want.step);
    }
    // The PNG is the image the detectors get.
    const cv::Mat png = cv::imread((dir.path() / "ds" / got.file).string(), cv::IMREAD_UNCHANGED);
    const cv::Mat expected = apply_effect(read_frame_gray(report.frames[i].png), want);
    ASSERT_EQ(png.type(), CV_8UC1);
    EXPECT_EQ(cv::norm(png, expected, cv::NORM_INF), 0) << got.file;
  }
}

TEST(Dataset, SixdofFilesHoldTheFramesTheirLensAndCameraEffects) {
  if (!test::have_povray()) GTEST_SKIP() << "povray not installed";
  SweepSettings s;
  s.experiment = Experiment::kSixdof;
  s.trials = 3;
  s.sixdof.noise_max = 6;
  const DatasetFiles files = make_dataset(s, test::gentle_options(test::shared_cache()));
  testing::ScratchDir dir("tagbench_dataset");
  write_dataset(dir.path() / "ds", files);
  const Dataset d = read_dataset(dir.path() / "ds");
  EXPECT_EQ(d.settings.experiment, Experiment::kSixdof);
  EXPECT_EQ(d.settings.sixdof.noise_max, 6);
  EXPECT_EQ(d.settings.sixdof.distortion, s.sixdof.distortion);
  EXPECT_NE(files.truth_json.find("\"distortion\": [-0.2, 0.05, 0.001, -5e-04, 0],\n    \"model\""), std::string::npos);
  SweepSettings with_ours = s;
  with_ours.detectors = {comparator_names().front()};
  const std::vector<SweepFrame> plan = plan_sweep(with_ours);
  ASSERT_EQ(d.frames.size(), 3u);
  const RenderReport report = render_plan(plan);
  for (std::size_t i = 0; i < plan.size(); ++i) {
    const DatasetFrame& got = d.frames[i];
    const SweepFrame& want = plan[i];
    ASSERT_TRUE(got.distortion.has_value());
    EXPECT_EQ(*got.distortion, s.sixdof.distortion);
    ASSERT_TRUE(got.frame.effect.camera.has_value());
    EXPECT_EQ(got.frame.effect.camera->defocus_sigma_px, want.effect.camera->defocus_sigma_px);
    EXPECT_EQ(got.frame.effect.camera->noise_sigma, want.effect.camera->noise_sigma);
    EXPECT_EQ(got.frame.effect.camera->noise_seed, want.effect.camera->noise_seed);
    EXPECT_EQ(got.frame.sample, want.sample);
    EXPECT_EQ(got.frame.image_position, want.image_position);
    EXPECT_EQ(got.frame.view.phi_deg, want.view.phi_deg);
    for (std::size_t k = 0; k < 4; ++k) EXPECT_EQ(got.frame.truth.corners[k], want.truth.corners[k]);
    const cv::Mat png = cv::imread((dir.path() / "ds" / got.file).string(), cv::IMREAD_UNCHANGED);
    const cv::Mat expected = apply_effect(read_frame_gray(report.frames[i].png), want);
    EXPECT_EQ(cv::norm(png, expected, cv::NORM_INF), 0) << got.file;
    // ... and the read-back frame makes the same image (its camera effects are all there).
    EXPECT_EQ(cv::norm(apply_effect(read_frame_gray(report.frames[i].png), got.frame), expected, cv::NORM_INF), 0);
  }
}

TEST(Dataset, FolderRules) {
  testing::ScratchDir dir("tagbench_dataset");
  DatasetFiles files;
  files.frames = {{"frame_00000.png", "a"}, {"frame_00001.png", "b"}};
  SweepSettings s;
  s.trials = 1;
  s.steps = {0};
  s.detectors = {comparator_names().front()};
  s = resolve_settings(s);
  const auto plan = plan_sweep(s);
  files.truth_json = truth_json(s, {plan[0], plan[0]}, {});
  // A folder holding something else is refused, untouched.
  const auto refused = [&](const std::string& fragment) {
    try {
      write_dataset(dir.path() / "other", files);
      ADD_FAILURE() << "written";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  fs::create_directories(dir.path() / "other");
  write_file_atomic(dir.path() / "other" / "keep.txt", "x");
  refused("not empty and not a dataset");
  EXPECT_FALSE(fs::exists(dir.path() / "other" / "truth.json"));
  // So is one whose truth.json is not a dataset's (someone else's file of that name).
  write_file_atomic(dir.path() / "other" / "truth.json", "{}");
  refused("its truth.json is not a tagbench dataset's");
  EXPECT_EQ(read_file(dir.path() / "other" / "truth.json"), "{}");
  // An earlier dataset is replaced; its frames the new one lacks are removed.
  write_dataset(dir.path() / "ds", files);
  EXPECT_TRUE(fs::exists(dir.path() / "ds" / "frame_00001.png"));
  DatasetFiles fewer = files;
  fewer.frames.pop_back();
  fewer.truth_json = truth_json(s, {plan[0]}, {});
  write_dataset(dir.path() / "ds", fewer);
  EXPECT_TRUE(fs::exists(dir.path() / "ds" / "frame_00000.png"));
  EXPECT_FALSE(fs::exists(dir.path() / "ds" / "frame_00001.png"));
  EXPECT_EQ(read_dataset(dir.path() / "ds").frames.size(), 1u);
}

TEST(Dataset, BadTruthIsOneLineNamingTheFileAndFrame) {
  testing::ScratchDir dir("tagbench_dataset");
  SweepSettings s;
  s.trials = 1;
  s.steps = {0, 10};
  s.detectors = {comparator_names().front()};
  s = resolve_settings(s);
  std::string t = truth_json(s, plan_sweep(s), {});
  const auto expect_error = [&](const std::string& text, const std::string& part) {
    write_file_atomic(dir.path() / "truth.json", text);
    try {
      read_dataset(dir.path());
      ADD_FAILURE() << "accepted";
    } catch (const std::runtime_error& e) {
      const std::string m = e.what();
      EXPECT_EQ(m.find((dir.path() / "truth.json").string() + ": "), 0u) << m;
      EXPECT_NE(m.find(part), std::string::npos) << m;
      EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
  };
  expect_error("{", "at byte 1");
  std::string other = t;
  other.replace(other.find("tagbench-dataset 1"), 18, "something else 2");
  expect_error(other, "is not tagbench-dataset 1");
  std::string bad_id = t;
  const auto second = bad_id.find("\"index\": 1");
  bad_id.replace(bad_id.find("\"id\": ", second), 6, "\"id\": \"x\", \"was\": ");
  expect_error(bad_id, "frame 1: id: expected a number");
  std::string escape = t;
  escape.replace(escape.find("frame_00000.png"), 15, "../escape.png");
  expect_error(escape, "frame 0: file: '../escape.png' is not a file name inside the dataset folder");
  // What scoring relies on: distinct files, ids of the family, frames at all.
  std::string twice = t;
  twice.replace(twice.find("frame_00001.png"), 15, "frame_00000.png");
  expect_error(twice, "frame 1: file 'frame_00000.png' is also frame 0's");
  std::string far_id = t;
  const auto id_at = far_id.find("\"id\": ", far_id.find("\"index\": 1"));
  far_id.replace(id_at, far_id.find(',', id_at) - id_at, "\"id\": 99999");
  expect_error(far_id, "frame 1: id 99999 is not in family 36h11");
  std::string not_r = t;
  const auto r_at = not_r.find("\"R\": ");
  not_r.replace(r_at, not_r.find("]]", r_at) + 2 - r_at, "\"R\": [[0, 0, 0], [0, 0, 0], [0, 0, 0]]");
  expect_error(not_r, "frame 0: R: not a rotation");
  std::string none = t;
  const auto frames_at = none.find("\"frames\": [");
  none.replace(frames_at, none.find("\n  ]", frames_at) + 4 - frames_at, "\"frames\": []");
  expect_error(none, "frames: empty");
  write_file_atomic(dir.path() / "truth.json", t);
  EXPECT_EQ(read_dataset(dir.path()).frames.size(), 2u);
}

}  // namespace
}  // namespace test_dataset
}  // namespace tagbench::bench
