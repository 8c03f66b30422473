#pragma once
/// @file
/// Stitch planning of the suturing task (thesis §5.2.1): from the wound's two edges as the
/// sensing module sees them now, where the next stitch goes. The edges move as each stitch is
/// pulled closed, so the plan is asked again before every stitch (the chart's
/// GetStitchTargetPose) rather than made once.
///
/// Rule: stitches every `spacing` m along the cut's centreline (the midpoints of the edges),
/// the first and the last `end_margin` m from its ends (a 40 mm cut with 8 mm spacing and
/// margins takes 4 stitches, at 8, 16, 24 and 32 mm); stitch k is at s_k = end_margin +
/// k·spacing, its two targets are the edges' points across the cut at s_k, `depth` m below the
/// skin (where the Endo Stitch's tip applies each half, sim::Wound::stitchPoint). A place whose
/// gap is already below `closed_gap` is skipped: a neighbour's pull closed it.
///
/// Frames: task frame, SI. A target's frame has its origin at the edge point, x along the cut
/// (the direction of increasing s), z out of the skin (the edges' `skin_normal`), y = z × x,
/// pointing from the right edge to the left one.

#include <vector>

#include <kdl/frames.hpp>

namespace cobra::suturing {

/// The wound's edges on the skin, as sampled across the cut: right[i] and left[i] face each other,
/// in order along the cut (m, task frame).
struct WoundEdges {
  std::vector<KDL::Vector> right;
  std::vector<KDL::Vector> left;
  KDL::Vector skin_normal{0.0, 0.0, 1.0};  ///< unit, out of the skin
};

struct StitchPlanModel {
  double spacing = 0.008;      ///< m, > 0: between stitches along the cut
  double end_margin = 0.008;   ///< m, >= 0: first and last stitch from the cut's ends
  double depth = 0.002;        ///< m, >= 0: the edge points' depth below the skin
  double closed_gap = 0.0005;  ///< m, >= 0: a place with a smaller gap needs no stitch
};

/// @throws std::invalid_argument naming the parameter and the expected range.
void validate(const StitchPlanModel& model);

/// One stitch to apply.
struct StitchTarget {
  int index = -1;      ///< k: the stitch's place in the plan
  double s = 0.0;      ///< m: along the cut's centreline
  double gap = 0.0;    ///< m: the edges' distance there now
  KDL::Frame right;    ///< the right half's target (see the file comment)
  KDL::Frame left;     ///< the left half's target
};

class StitchPlanner {
 public:
  /// @throws std::invalid_argument when the model is invalid.
  explicit StitchPlanner(const StitchPlanModel& model = StitchPlanModel{});

  /// Checks `edges`: as many right as left points, >= 2 each, finite, the centreline's points
  /// >= 0.1 mm apart, a unit skin normal.
  /// @throws std::invalid_argument saying what is wrong (the sensing module's data is bad input).
  static void check(const WoundEdges& edges);
  /// check() without the message: true when `edges` pass. Real time: allocates nothing.
  static bool usable(const WoundEdges& edges) noexcept;

  /// m: the centreline's length.
  static double length(const WoundEdges& edges) noexcept;
  /// Stitches the cut takes: floor((length - 2·end_margin) / spacing) + 1, 0 when it is shorter
  /// than the margins.
  int count(const WoundEdges& edges) const noexcept;
  /// The first stitch of the plan whose index is >= `from` and whose place is still open, read
  /// from the current edges; false when none is left (the wound is closed as planned). Edges that
  /// fail check() give no stitch rather than garbage. Real time: allocates nothing, never throws.
  bool next(const WoundEdges& edges, int from, StitchTarget& target) const noexcept;

  const StitchPlanModel& model() const noexcept { return model_; }

 private:
  StitchPlanModel model_;
};

}  // namespace cobra::suturing
