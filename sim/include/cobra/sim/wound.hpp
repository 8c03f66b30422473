#pragma once
/// @file
/// A planar wound, the Endo Stitch's stitches and the thread that closes it (thesis §5.1: a
/// linear cut on a planar surface of uniform tissue; §5.2.2: a stitch passes the needle through
/// both edges and the thread is pulled to join them; §5.5.2: two layers of one material; §5.6:
/// the stick that hooks the thread and pushes it aside).
///
/// Frame W of the wound: the skin's surface is the plane z = 0, +z points out of the skin. The
/// cut's centreline is a polyline on that plane (straight, slanted or curved) parametrised by its
/// arc length s (m). At s the in-plane normal n(s) = z × t(s) (t the centreline's direction)
/// points to the LEFT edge; the right edge lies along -n(s).
///
/// Physics (simple, stated, SI):
///  - Opening: the edges stand g0(s) = max_gap·sqrt(1 - (2s/L - 1)²) apart (an elliptic opening,
///    0 at the cut's ends, L its length), minus what the stitches pulled together: a stitch at s_i
///    that closed δ_i narrows the gap around it with a triangular weight of half-width
///    closure_spread, never below 0.
///  - A half-stitch is applied when the Endo Stitch is actuated with its tip inside the wound
///    within stitch_tolerance of the edge point: the edge at depth stitch_depth below the skin.
///    The needle leaves the tissue on the skin bite metres beyond that edge (the stitch's skin
///    point); the thread follows it. The right half comes first, then the left half of the same
///    stitch (thesis §5.1: the right edge, then the left).
///  - Thread: anchored at the first stitch's right skin point; its path runs through every skin
///    point in order and then, free, to the tool's tip (round the stick while hooked).
///    The stick catches the free thread where it touches it (within hook_radius of its tip): the
///    thread bends round that point, which moves with the stick, so its pull grows from zero.
///    Each half-stitch draws the thread through with the needle, leaving `slack` m of loop: its
///    rest length becomes the path at that moment plus the slack (never more than the thread's
///    `length`). A path longer than the rest length stretches it: T = stiffness·(path - rest).
///  - Pulling a complete stitch: the edges come together against the tissue, T = k_t·δ
///    (k_t = tissue_stiffness), and the crossing through the wound shortens by δ, so the
///    equilibrium is δ = stiffness·(D0 - rest) / (stiffness + k_t), D0 the path with δ = 0; δ is
///    bounded by the gap there (closed edges press, the thread then stretches alone) and never
///    decreases (the thread does not slide back through the tissue). Earlier stitches keep the
///    closure they reached.
///  - Over breaking_tension the thread breaks: no more stitches, no tension.

#include <cstdint>
#include <vector>

#include <kdl/frames.hpp>

namespace cobra::sim {

/// The cut and its tissue. Numbers marked ASSUMPTION are of the order of a skin phantom; the
/// thesis gives none.
struct WoundModel {
  /// m: the centreline on the skin (z = 0 in W), >= 2 points, consecutive points >= 1 mm apart.
  /// Default: a straight 40 mm cut along x, centred on W's origin.
  std::vector<KDL::Vector> cut{KDL::Vector(-0.02, 0.0, 0.0), KDL::Vector(0.02, 0.0, 0.0)};
  double max_gap = 0.006;            ///< m, > 0: the edges' distance at the middle of the cut
  double upper_layer = 0.002;        ///< m, > 0: thickness of the upper layer (§5.5.2: two layers)
  double lower_layer = 0.004;        ///< m, > 0: thickness of the lower layer
  double tissue_stiffness = 400.0;   ///< N/m, > 0: thread tension per metre a stitch closes (ASSUMPTION)
  double closure_spread = 0.012;     ///< m, > 0: half-width over which a stitch narrows the gap (ASSUMPTION)
  double bite = 0.004;               ///< m, > 0: skin point's distance beyond the edge
  double stitch_depth = 0.002;       ///< m, in (0, upper_layer + lower_layer): depth of the edge point
  double stitch_tolerance = 0.0015;  ///< m, > 0: how close the tip must be to the edge point
  double closed_gap = 0.0005;        ///< m, >= 0: a stitch whose gap is below this counts as closed
  int max_stitches = 16;             ///< > 0: stitches the model holds (storage reserved at construction)
};

/// The suture on the Endo Stitch's needle, and the stick that hooks it (thesis §5.6 E-G).
struct ThreadModel {
  double length = 0.30;              ///< m, > 0: the whole thread, anchor to needle
  double slack = 0.02;               ///< m, >= 0: loop left after the needle draws it through a half-stitch
  double stiffness = 800.0;          ///< N/m, > 0: tension per metre stretched (ASSUMPTION)
  double breaking_tension = 15.0;    ///< N, > 0: the thread breaks above it (ASSUMPTION, of a 2-0 suture's knot pull)
  double hook_radius = 0.002;        ///< m, > 0: the stick catches the free thread within this distance
  /// s, >= 0: how long the thread takes to slide off the stick once it lets go (0: at once). The
  /// bend point moves from the stick's tip to the thread's straight line over this time, so the
  /// thread's pull on the stick fades instead of vanishing in one step (ASSUMPTION for a non-zero
  /// value: the gripper turns the stick's tip out of the thread at a finite speed).
  double release_time = 0.0;
};

/// @throws std::invalid_argument naming the parameter (and the cut's point) and the expected range.
void validate(const WoundModel& wound);
/// @throws std::invalid_argument naming the parameter and the expected range.
void validate(const ThreadModel& thread);

enum class WoundSide : std::uint8_t { Right, Left };
const char* toString(WoundSide side) noexcept;

/// Why an actuation applied no stitch (None: it did).
enum class StitchMiss : std::uint8_t {
  None,
  OutsideWound,    ///< the tip is not between the edges below the skin
  FarFromEdge,     ///< inside, but farther than stitch_tolerance from the edge point
  LeftBeforeRight, ///< a left half with no open right half
  RightStillOpen,  ///< a right half while the previous stitch's left half is missing
  NotAtOpenStitch, ///< a left half at another place along the cut than its right half
  ThreadBroken,
  NoThreadLeft,    ///< the path to the new skin point would need more thread than there is
  TooManyStitches,
};
const char* toString(StitchMiss miss) noexcept;

/// One stitch: where, its two halves, its closure.
struct Stitch {
  double s = 0.0;             ///< m: arc length along the cut
  bool right = false;         ///< right half applied
  bool left = false;          ///< left half applied
  double closure = 0.0;       ///< m: δ, how much this stitch pulled the edges together
  bool complete() const noexcept { return right && left; }
};

/// Outcome of one actuation of the Endo Stitch.
struct StitchResult {
  StitchMiss miss = StitchMiss::None;
  int stitch = -1;            ///< index of the stitch the half belongs to, -1 on a miss
  WoundSide side = WoundSide::Right;
  double distance = 0.0;      ///< m: tip to the nearest edge point (the miss's figure)
  bool applied() const noexcept { return miss == StitchMiss::None; }
};

/// The wound, its stitches and the thread. Positions in W. Construction reserves all storage:
/// `actuate`, `step` and the queries are noexcept and allocate nothing; no randomness.
class Wound {
 public:
  /// @throws std::invalid_argument when a model is invalid (see validate).
  Wound(WoundModel wound, ThreadModel thread = ThreadModel{});

  /// m: the cut's length L.
  double length() const noexcept { return length_; }
  /// m: the edges' current distance at s (clamped to [0, L]).
  double gap(double s) const noexcept;
  /// m: the opening before any stitch, g0(s).
  double initialGap(double s) const noexcept;
  /// The point of `side`'s edge at s, `depth` m below the skin (0: on the skin).
  KDL::Vector edgePoint(WoundSide side, double s, double depth) const noexcept;
  /// Where the tip must be for `side`'s half-stitch at s: the edge point at stitch_depth.
  KDL::Vector stitchPoint(WoundSide side, double s) const noexcept { return edgePoint(side, s, model_.stitch_depth); }
  /// Unit vector from the right edge towards the left one at s, on the skin.
  KDL::Vector normal(double s) const noexcept;
  /// Centreline point at s.
  KDL::Vector centre(double s) const noexcept;
  /// The arc length of the centreline point nearest to `p` (its projection on the plane).
  double nearestS(const KDL::Vector& p) const noexcept;

  /// The Endo Stitch's switch: tries `side`'s half-stitch with the tip at `tip` (m, W).
  StitchResult actuate(WoundSide side, const KDL::Vector& tip) noexcept;
  /// Advances the thread with the tool's tip at `tool` and the stick's tip at `stick` (m, W), `dt`
  /// s after the last step: the stick hooks the free thread when it comes within hook_radius of
  /// it; a release under way advances by dt; a complete stitch closes under the tension; over
  /// breaking_tension the thread breaks.
  void step(const KDL::Vector& tool, const KDL::Vector& stick, double dt = 0.0) noexcept;
  /// The stick lets the thread go: at once with release_time 0, else the thread slides off it over
  /// release_time (hooked() and releasing() stay true meanwhile, the bend point moving from where
  /// the stick held it to the straight line from the last skin point to the tool). Let go, the
  /// stick catches the thread again only after they have been farther than hook_radius apart (a
  /// stick resting against the thread it let go does not hook it: it must come to it).
  void releaseThread() noexcept;
  /// Whether the thread is sliding off the stick (a release under way).
  bool releasing() const noexcept { return releasing_; }
  /// The edge `p` (m, W) is on: the side of the centreline it lies (Left where the in-plane
  /// normal points, Right otherwise): the half-stitch an Endo Stitch actuated there tries.
  WoundSide sideAt(const KDL::Vector& p) const noexcept;
  /// Changes whenever the wound's state changes: a half-stitch applied, a stitch's closure, the
  /// thread hooked, released or broken. It does not change with the thread's tension and path,
  /// which follow the tools continuously. Readers recompute what depends on the gap (edges,
  /// maxGap, stitch gaps) only when it changed.
  std::uint64_t revision() const noexcept { return revision_; }

  double tension() const noexcept { return tension_; }  ///< N
  bool broken() const noexcept { return broken_; }
  bool hooked() const noexcept { return hooked_; }
  /// m: where the hooked thread bends round the stick (meaningful while hooked()): the point of the
  /// stick's side it touched when caught (within hook_radius of the tip), moving with the stick.
  const KDL::Vector& hookPoint() const noexcept { return hook_; }
  /// m: the thread's length along its path (anchor, skin points, stick, tool).
  double threadPath() const noexcept { return path_; }
  /// m: its unstretched length as far as the needle has drawn it (see the file comment).
  double threadRest() const noexcept { return rest_; }
  /// m: the free thread's (last skin point to tool, via the stick) distance from `p`; +inf with no stitch.
  double freeThreadDistance(const KDL::Vector& p) const noexcept;
  /// N, W: the force the tensed thread puts on the tool's tip (tension along the free thread, toward
  /// the hook or the last skin point) and on the stick while hooked (the thread bent round it:
  /// tension along both of its sides); zero when slack, broken or without a stitch.
  KDL::Vector toolForce() const noexcept;
  KDL::Vector stickForce() const noexcept;
  const std::vector<Stitch>& stitches() const noexcept { return stitches_; }
  /// m: the gap at stitch i (its s).
  double stitchGap(int i) const noexcept;
  /// m, W: where the thread leaves the skin for `side`'s half of stitch i (bite metres beyond
  /// that edge, on the skin): the thread's path runs through these points in order.
  KDL::Vector skinPoint(int stitch, WoundSide side) const noexcept;
  /// m: the widest gap along the cut (sampled every 0.5 mm): what the stitches left open between
  /// and beyond them.
  double maxGap() const noexcept;
  /// Whether every stitch so far is complete and closed (its gap below closed_gap). How many
  /// stitches the wound needs is the stitch plan's business, not the wound's.
  bool stitchesClosed() const noexcept;
  const WoundModel& model() const noexcept { return model_; }
  const ThreadModel& threadModel() const noexcept { return thread_; }

 private:
  struct Locus {
    std::size_t segment;
    double along;  // m, from the segment's start
  };
  Locus locate(double s) const noexcept;
  /// Thread length from the anchor to the last skin point (m).
  double fixedPath() const noexcept;
  /// Length of the free thread to `tool` (m), through the stick while hooked.
  double freePath(const KDL::Vector& tool) const noexcept;
  const KDL::Vector* lastSkinPoint(KDL::Vector& storage) const noexcept;

  WoundModel model_;
  ThreadModel thread_;
  std::vector<double> arc_;  // m: arc length at each cut point
  double length_ = 0.0;
  std::vector<Stitch> stitches_;
  double tension_ = 0.0;
  double path_ = 0.0;
  double rest_ = 0.0;
  bool broken_ = false;
  bool hooked_ = false;
  bool releasing_ = false;
  bool armed_ = true;          // the stick may catch the thread: not let go of it while touching it since
  double release_left_ = 0.0;  // s: of a release under way
  KDL::Vector hook_;
  KDL::Vector hook_offset_;    // m: the bend point from the stick's tip, where the thread touched it
  KDL::Vector released_at_;    // m: the bend point when the stick let go
  KDL::Vector tool_;
  std::uint64_t revision_ = 0;
};

}  // namespace cobra::sim
