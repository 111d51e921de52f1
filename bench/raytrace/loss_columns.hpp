#pragma once
// The loss-stage columns the benchmark CSVs share (issue 17, section 2): per row, `loss_stage` and
// `loss_bits` (detect/explain_loss.hpp: where a missed tag was lost, and for misread / wrong_id the
// bits of its code read wrong); per summary row, `lost_STAGE` for each stage a missed tag can be lost
// at. Cells are empty where there is nothing to say: a detected tag, a detector that cannot explain
// (Comparator::can_explain), a summary row of such a detector.
#include <array>
#include <cstddef>
#include <optional>
#include <string>

#include "detect/explain_loss.hpp"

namespace tagbench::bench {

// The stages a missed tag can be lost at, in pipeline order.
inline constexpr std::size_t kLossStageCount = 9;
inline constexpr std::array<LossStage, kLossStageCount> kLossStages = {
    LossStage::kNoCluster, LossStage::kNoSegment, LossStage::kNoQuad,      LossStage::kQuadRejected,
    LossStage::kMisread,   LossStage::kWrongId,   LossStage::kDuplicate,   LossStage::kBelowMargin,
    LossStage::kWithdrawn};

// Missed tags per stage (kLossStages order); `explains`: the detector gives stages at all.
struct LossCounts {
  bool explains = false;
  std::array<int, kLossStageCount> lost{};
  void add(const std::optional<LossExplanation>& loss) {
    if (!loss) return;
    for (std::size_t k = 0; k < kLossStageCount; ++k)
      if (loss->stage == kLossStages[k]) ++lost[k];
  }
};

// ",loss_stage,loss_bits" and a row's two cells (each with its leading comma).
inline std::string loss_header() { return ",loss_stage,loss_bits"; }
inline std::string loss_cells(const std::optional<LossExplanation>& loss) {
  std::string o = ",";
  if (loss) o += loss_stage_name(loss->stage);
  o += ',';
  if (loss && loss->bits_wrong >= 0) o += std::to_string(loss->bits_wrong);
  return o;
}
// ",lost_no_cluster,...,lost_below_margin" and a summary row's cells.
inline std::string lost_header() {
  std::string o;
  for (const LossStage s : kLossStages) o += std::string(",lost_") + loss_stage_name(s);
  return o;
}
inline std::string lost_cells(const LossCounts& c) {
  std::string o;
  for (const int n : c.lost) {
    o += ',';
    if (c.explains) o += std::to_string(n);
  }
  return o;
}

}  // namespace tagbench::bench
