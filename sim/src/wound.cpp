#include "cobra/sim/wound.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "cobra/text/number.hpp"

namespace cobra::sim {
namespace {

void require(bool ok, const std::string& what, const std::string& expected) {
  if (!ok) throw std::invalid_argument(what + ": expected " + expected);
}

using text::number;

/// The point of the segment [a, b] nearest to p (m).
KDL::Vector closestOnSegment(const KDL::Vector& p, const KDL::Vector& a, const KDL::Vector& b) noexcept {
  const KDL::Vector ab = b - a;
  const double squared = KDL::dot(ab, ab);
  const double t = squared > 0.0 ? std::clamp(KDL::dot(p - a, ab) / squared, 0.0, 1.0) : 0.0;
  return a + ab * t;
}

/// Distance from p to the segment [a, b] (m).
double segmentDistance(const KDL::Vector& p, const KDL::Vector& a, const KDL::Vector& b) noexcept {
  return (p - closestOnSegment(p, a, b)).Norm();
}

}  // namespace

void validate(const WoundModel& w) {
  require(w.cut.size() >= 2, "wound: cut has " + std::to_string(w.cut.size()) + " point(s)",
          "at least 2 points of the centreline on the skin (m)");
  for (std::size_t i = 0; i < w.cut.size(); ++i) {
    const KDL::Vector& p = w.cut[i];
    const std::string name = "wound: cut point " + std::to_string(i);
    require(std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z()), name + " is not finite",
            "finite coordinates (m)");
    require(p.z() == 0.0, name + " has z = " + number(p.z()) + " m", "z = 0: the cut lies on the skin, the plane z = 0 of the wound frame");
    if (i > 0)
      require((p - w.cut[i - 1]).Norm() >= 1e-3,
              name + " is " + number((p - w.cut[i - 1]).Norm()) + " m from point " + std::to_string(i - 1),
              "consecutive points at least 0.001 m apart");
  }
  const auto positive = [](double v, const char* name, const char* unit) {
    require(std::isfinite(v) && v > 0.0, std::string("wound: ") + name + " is " + number(v) + " " + unit,
            std::string("a finite value > 0 ") + unit);
  };
  positive(w.max_gap, "max_gap", "m");
  positive(w.upper_layer, "upper_layer", "m");
  positive(w.lower_layer, "lower_layer", "m");
  positive(w.tissue_stiffness, "tissue_stiffness", "N/m");
  positive(w.closure_spread, "closure_spread", "m");
  positive(w.bite, "bite", "m");
  positive(w.stitch_tolerance, "stitch_tolerance", "m");
  require(std::isfinite(w.stitch_depth) && w.stitch_depth > 0.0 && w.stitch_depth < w.upper_layer + w.lower_layer,
          "wound: stitch_depth is " + number(w.stitch_depth) + " m",
          "a depth inside the tissue, in (0, " + number(w.upper_layer + w.lower_layer) + ") m");
  require(std::isfinite(w.closed_gap) && w.closed_gap >= 0.0, "wound: closed_gap is " + number(w.closed_gap) + " m",
          "a finite value >= 0 m");
  require(w.max_stitches > 0, "wound: max_stitches is " + std::to_string(w.max_stitches), "a count > 0");
}

void validate(const ThreadModel& t) {
  const auto positive = [](double v, const char* name, const char* unit) {
    require(std::isfinite(v) && v > 0.0, std::string("thread: ") + name + " is " + number(v) + " " + unit,
            std::string("a finite value > 0 ") + unit);
  };
  positive(t.length, "length", "m");
  require(std::isfinite(t.slack) && t.slack >= 0.0 && t.slack < t.length, "thread: slack is " + number(t.slack) + " m",
          "a finite value >= 0 m and below the thread's length");
  positive(t.stiffness, "stiffness", "N/m");
  positive(t.breaking_tension, "breaking_tension", "N");
  positive(t.hook_radius, "hook_radius", "m");
  require(std::isfinite(t.release_time) && t.release_time >= 0.0, "thread: release_time is " + number(t.release_time) + " s",
          "a finite value >= 0 s");
}

const char* toString(WoundSide side) noexcept { return side == WoundSide::Right ? "right" : "left"; }

const char* toString(StitchMiss miss) noexcept {
  switch (miss) {
    case StitchMiss::None: return "applied";
    case StitchMiss::OutsideWound: return "the tip is not inside the wound";
    case StitchMiss::FarFromEdge: return "the tip is too far from the edge point";
    case StitchMiss::LeftBeforeRight: return "a left half-stitch needs its right half first";
    case StitchMiss::RightStillOpen: return "the previous stitch still lacks its left half";
    case StitchMiss::NotAtOpenStitch: return "the left half is not where its right half is";
    case StitchMiss::ThreadBroken: return "the thread is broken";
    case StitchMiss::NoThreadLeft: return "not enough thread left";
    case StitchMiss::TooManyStitches: return "no room for another stitch";
  }
  return "?";
}

Wound::Wound(WoundModel wound, ThreadModel thread) : model_(std::move(wound)), thread_(thread) {
  validate(model_);
  validate(thread_);
  arc_.reserve(model_.cut.size());
  arc_.push_back(0.0);
  for (std::size_t i = 1; i < model_.cut.size(); ++i) arc_.push_back(arc_.back() + (model_.cut[i] - model_.cut[i - 1]).Norm());
  length_ = arc_.back();
  stitches_.reserve(static_cast<std::size_t>(model_.max_stitches));
}

Wound::Locus Wound::locate(double s) const noexcept {
  s = std::clamp(s, 0.0, length_);
  std::size_t i = 0;
  while (i + 2 < arc_.size() && s > arc_[i + 1]) ++i;
  return {i, s - arc_[i]};
}

KDL::Vector Wound::centre(double s) const noexcept {
  const Locus l = locate(s);
  const KDL::Vector& a = model_.cut[l.segment];
  const KDL::Vector& b = model_.cut[l.segment + 1];
  return a + (b - a) * (l.along / (b - a).Norm());
}

KDL::Vector Wound::normal(double s) const noexcept {
  const Locus l = locate(s);
  KDL::Vector t = model_.cut[l.segment + 1] - model_.cut[l.segment];
  t.Normalize();
  return {-t.y(), t.x(), 0.0};  // z × t
}

double Wound::nearestS(const KDL::Vector& p) const noexcept {
  const KDL::Vector flat(p.x(), p.y(), 0.0);
  double best_s = 0.0;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i + 1 < model_.cut.size(); ++i) {
    const KDL::Vector ab = model_.cut[i + 1] - model_.cut[i];
    const double len = ab.Norm();
    const double along = std::clamp(KDL::dot(flat - model_.cut[i], ab) / len, 0.0, len);
    const double d = (flat - (model_.cut[i] + ab * (along / len))).Norm();
    if (d < best) {
      best = d;
      best_s = arc_[i] + along;
    }
  }
  return best_s;
}

double Wound::initialGap(double s) const noexcept {
  const double u = 2.0 * std::clamp(s, 0.0, length_) / length_ - 1.0;
  return model_.max_gap * std::sqrt(std::max(0.0, 1.0 - u * u));
}

double Wound::gap(double s) const noexcept {
  double g = initialGap(s);
  for (const Stitch& st : stitches_) g -= st.closure * std::max(0.0, 1.0 - std::abs(s - st.s) / model_.closure_spread);
  return std::max(0.0, g);
}

KDL::Vector Wound::edgePoint(WoundSide side, double s, double depth) const noexcept {
  const double half = 0.5 * gap(s) * (side == WoundSide::Left ? 1.0 : -1.0);
  return centre(s) + normal(s) * half - KDL::Vector(0.0, 0.0, depth);
}

KDL::Vector Wound::skinPoint(int stitch, WoundSide side) const noexcept {
  const double s = stitches_[static_cast<std::size_t>(stitch)].s;
  const double half = (0.5 * gap(s) + model_.bite) * (side == WoundSide::Left ? 1.0 : -1.0);
  return centre(s) + normal(s) * half;
}

double Wound::fixedPath() const noexcept {
  double path = 0.0;
  bool first = true;
  KDL::Vector previous;
  for (int i = 0; i < static_cast<int>(stitches_.size()); ++i) {
    for (const WoundSide side : {WoundSide::Right, WoundSide::Left}) {
      const Stitch& st = stitches_[static_cast<std::size_t>(i)];
      if ((side == WoundSide::Right && !st.right) || (side == WoundSide::Left && !st.left)) continue;
      const KDL::Vector p = skinPoint(i, side);
      if (!first) path += (p - previous).Norm();
      previous = p;
      first = false;
    }
  }
  return path;
}

const KDL::Vector* Wound::lastSkinPoint(KDL::Vector& storage) const noexcept {
  if (stitches_.empty()) return nullptr;
  const int last = static_cast<int>(stitches_.size()) - 1;
  storage = skinPoint(last, stitches_.back().left ? WoundSide::Left : WoundSide::Right);
  return &storage;
}

double Wound::freePath(const KDL::Vector& tool) const noexcept {
  KDL::Vector storage;
  const KDL::Vector* last = lastSkinPoint(storage);
  if (last == nullptr) return 0.0;
  return hooked_ ? (hook_ - *last).Norm() + (tool - hook_).Norm() : (tool - *last).Norm();
}

double Wound::freeThreadDistance(const KDL::Vector& p) const noexcept {
  KDL::Vector storage;
  const KDL::Vector* last = lastSkinPoint(storage);
  if (last == nullptr || broken_) return std::numeric_limits<double>::infinity();
  if (!hooked_) return segmentDistance(p, *last, tool_);
  return std::min(segmentDistance(p, *last, hook_), segmentDistance(p, hook_, tool_));
}

namespace {
/// Unit vector from `from` to `to`, zero when they coincide.
KDL::Vector towards(const KDL::Vector& from, const KDL::Vector& to) noexcept {
  const KDL::Vector d = to - from;
  const double n = d.Norm();
  return n > 1e-12 ? d / n : KDL::Vector::Zero();
}
}  // namespace

KDL::Vector Wound::toolForce() const noexcept {
  KDL::Vector storage;
  const KDL::Vector* last = lastSkinPoint(storage);
  if (last == nullptr || broken_ || tension_ <= 0.0) return KDL::Vector::Zero();
  return towards(tool_, hooked_ ? hook_ : *last) * tension_;
}

KDL::Vector Wound::stickForce() const noexcept {
  KDL::Vector storage;
  const KDL::Vector* last = lastSkinPoint(storage);
  if (last == nullptr || broken_ || !hooked_ || tension_ <= 0.0) return KDL::Vector::Zero();
  return (towards(hook_, *last) + towards(hook_, tool_)) * tension_;
}

StitchResult Wound::actuate(WoundSide side, const KDL::Vector& tip) noexcept {
  StitchResult r;
  r.side = side;
  if (broken_) {
    r.miss = StitchMiss::ThreadBroken;
    return r;
  }
  const bool open = !stitches_.empty() && !stitches_.back().complete();
  double s = nearestS(tip);
  if (side == WoundSide::Right) {
    if (open) r.miss = StitchMiss::RightStillOpen;
    else if (static_cast<int>(stitches_.size()) == model_.max_stitches) r.miss = StitchMiss::TooManyStitches;
  } else if (!open) {
    r.miss = StitchMiss::LeftBeforeRight;
  }
  if (!r.applied()) return r;
  if (side == WoundSide::Left) {
    const double open_s = stitches_.back().s;
    r.distance = (tip - stitchPoint(side, open_s)).Norm();
    if (std::abs(s - open_s) > model_.stitch_tolerance) {
      r.miss = StitchMiss::NotAtOpenStitch;
      return r;
    }
    s = open_s;
  }
  r.distance = (tip - stitchPoint(side, s)).Norm();
  const double lateral = KDL::dot(tip - centre(s), normal(s));
  const double depth = -tip.z();
  if (depth <= 0.0 || depth > model_.upper_layer + model_.lower_layer ||
      std::abs(lateral) > 0.5 * gap(s) + model_.stitch_tolerance) {
    r.miss = StitchMiss::OutsideWound;
    return r;
  }
  if (r.distance > model_.stitch_tolerance) {
    r.miss = StitchMiss::FarFromEdge;
    return r;
  }
  // The needle draws the thread through: its rest length becomes the path to the tip plus the slack.
  if (side == WoundSide::Right) stitches_.push_back(Stitch{s, true, false, 0.0});
  else stitches_.back().left = true;
  const double rest = fixedPath() + (tip - skinPoint(static_cast<int>(stitches_.size()) - 1, side)).Norm() + thread_.slack;
  if (rest > thread_.length) {
    if (side == WoundSide::Right) stitches_.pop_back();
    else stitches_.back().left = false;
    r.miss = StitchMiss::NoThreadLeft;
    return r;
  }
  rest_ = rest;
  ++revision_;
  r.stitch = static_cast<int>(stitches_.size()) - 1;
  return r;
}

void Wound::step(const KDL::Vector& tool, const KDL::Vector& stick, double dt) noexcept {
  tool_ = tool;
  KDL::Vector storage;
  const KDL::Vector* last = lastSkinPoint(storage);
  if (broken_ || last == nullptr) {
    tension_ = 0.0;
    path_ = fixedPath();
    return;
  }
  if (releasing_) {
    release_left_ -= std::max(0.0, dt);
    if (release_left_ <= 0.0) {
      releasing_ = hooked_ = false;
      armed_ = false;  // it catches the thread again only once they have been apart
      ++revision_;
    } else {
      // The bend point slides from where the stick let go to the straight thread, linearly in time.
      const KDL::Vector line = closestOnSegment(released_at_, *last, tool);
      hook_ = line + (released_at_ - line) * (release_left_ / thread_.release_time);
    }
  } else if (hooked_) hook_ = stick + hook_offset_;
  else {
    const KDL::Vector touched = closestOnSegment(stick, *last, tool);
    const bool touching = (touched - stick).Norm() <= thread_.hook_radius;
    if (!touching) armed_ = true;
    else if (armed_) {
      // Caught where it touches the stick's side: the thread is still straight, and bends as the
      // stick moves on (its pull grows from zero instead of appearing in one step).
      hooked_ = true;
      hook_offset_ = touched - stick;
      hook_ = touched;
      ++revision_;
    }
  }
  double path = fixedPath() + freePath(tool);
  Stitch& pulled = stitches_.back();
  if (pulled.complete()) {
    // Equilibrium of the pulled stitch (file comment): the crossing shortens one for one with δ.
    const double k = thread_.stiffness;
    const double unclosed = path + pulled.closure;
    const double balance = k * (unclosed - rest_) / (k + model_.tissue_stiffness);
    const double others = gap(pulled.s) + pulled.closure;  // the gap this stitch alone could close
    const double closure = std::clamp(std::max(pulled.closure, balance), 0.0, std::max(0.0, others));
    if (closure != pulled.closure) {
      pulled.closure = closure;
      ++revision_;
      path = fixedPath() + freePath(tool);
    }
  }
  path_ = path;
  tension_ = std::max(0.0, thread_.stiffness * (path - rest_));
  if (tension_ > thread_.breaking_tension) {
    broken_ = true;
    hooked_ = releasing_ = false;
    tension_ = 0.0;
    ++revision_;
  }
}

void Wound::releaseThread() noexcept {
  if (!hooked_ || releasing_) return;
  if (thread_.release_time > 0.0) {
    releasing_ = true;
    release_left_ = thread_.release_time;
    released_at_ = hook_;
    return;
  }
  hooked_ = false;
  armed_ = false;
  ++revision_;
}

WoundSide Wound::sideAt(const KDL::Vector& p) const noexcept {
  const double s = nearestS(p);
  return KDL::dot(p - centre(s), normal(s)) > 0.0 ? WoundSide::Left : WoundSide::Right;
}

double Wound::stitchGap(int i) const noexcept { return gap(stitches_[static_cast<std::size_t>(i)].s); }

double Wound::maxGap() const noexcept {
  const int samples = static_cast<int>(std::ceil(length_ / 5e-4));
  double widest = 0.0;
  for (int i = 0; i <= samples; ++i) widest = std::max(widest, gap(length_ * i / samples));
  return widest;
}

bool Wound::stitchesClosed() const noexcept {
  if (stitches_.empty()) return false;
  for (int i = 0; i < static_cast<int>(stitches_.size()); ++i)
    if (!stitches_[static_cast<std::size_t>(i)].complete() || stitchGap(i) >= model_.closed_gap) return false;
  return true;
}

}  // namespace cobra::sim
