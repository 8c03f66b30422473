#include "cobra/suturing/stitch_plan.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "cobra/text/number.hpp"

namespace cobra::suturing {
namespace {

using text::number;

bool finite(const KDL::Vector& v) noexcept { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }

KDL::Vector midpoint(const WoundEdges& e, std::size_t i) noexcept { return (e.right[i] + e.left[i]) * 0.5; }

}  // namespace

void validate(const StitchPlanModel& m) {
  const auto require = [](double v, bool positive, const char* name) {
    if (!std::isfinite(v) || v < 0.0 || (positive && v == 0.0))
      throw std::invalid_argument(std::string("stitch plan: ") + name + " is " + number(v) + " m: expected a finite value " +
                                  (positive ? "> 0" : ">= 0") + " m");
  };
  require(m.spacing, true, "spacing");
  require(m.end_margin, false, "end_margin");
  require(m.depth, false, "depth");
  require(m.closed_gap, false, "closed_gap");
}

StitchPlanner::StitchPlanner(const StitchPlanModel& model) : model_(model) { validate(model_); }

void StitchPlanner::check(const WoundEdges& e) {
  if (e.right.size() != e.left.size())
    throw std::invalid_argument("wound edges: " + std::to_string(e.right.size()) + " right and " +
                                std::to_string(e.left.size()) +
                                " left points: expected as many of each, facing each other across the cut");
  if (e.right.size() < 2)
    throw std::invalid_argument("wound edges: " + std::to_string(e.right.size()) +
                                " point(s) per edge: expected at least 2 along the cut");
  if (!finite(e.skin_normal) || std::abs(e.skin_normal.Norm() - 1.0) > 1e-6)
    throw std::invalid_argument("wound edges: the skin normal has length " + number(e.skin_normal.Norm()) +
                                ": expected a unit vector out of the skin");
  for (std::size_t i = 0; i < e.right.size(); ++i) {
    if (!finite(e.right[i]) || !finite(e.left[i]))
      throw std::invalid_argument("wound edges: point " + std::to_string(i) + " is not finite: expected positions in m");
    if (i > 0 && (midpoint(e, i) - midpoint(e, i - 1)).Norm() < 1e-4)
      throw std::invalid_argument("wound edges: points " + std::to_string(i - 1) + " and " + std::to_string(i) +
                                  " are " + number((midpoint(e, i) - midpoint(e, i - 1)).Norm()) +
                                  " m apart along the cut: expected at least 0.0001 m");
  }
}

bool StitchPlanner::usable(const WoundEdges& e) noexcept {
  if (e.right.size() != e.left.size() || e.right.size() < 2) return false;
  if (!finite(e.skin_normal) || std::abs(e.skin_normal.Norm() - 1.0) > 1e-6) return false;
  for (std::size_t i = 0; i < e.right.size(); ++i) {
    if (!finite(e.right[i]) || !finite(e.left[i])) return false;
    if (i > 0 && (midpoint(e, i) - midpoint(e, i - 1)).Norm() < 1e-4) return false;
  }
  return true;
}

double StitchPlanner::length(const WoundEdges& e) noexcept {
  double length = 0.0;
  for (std::size_t i = 1; i < e.right.size(); ++i) length += (midpoint(e, i) - midpoint(e, i - 1)).Norm();
  return length;
}

int StitchPlanner::count(const WoundEdges& edges) const noexcept {
  const double usable = length(edges) - 2.0 * model_.end_margin;
  // The 1e-9 m keeps a cut of exactly n spacings from losing its last stitch to rounding.
  return usable < 0.0 ? 0 : static_cast<int>(std::floor(usable / model_.spacing + 1e-9)) + 1;
}

bool StitchPlanner::next(const WoundEdges& e, int from, StitchTarget& target) const noexcept {
  if (!usable(e)) return false;
  const int stitches = count(e);
  for (int k = std::max(from, 0); k < stitches; ++k) {
    const double s = model_.end_margin + k * model_.spacing;
    // The centreline segment holding s, and where along it.
    double start = 0.0;
    std::size_t i = 0;
    double along = 0.0;
    for (; i + 1 < e.right.size(); ++i) {
      const double segment = (midpoint(e, i + 1) - midpoint(e, i)).Norm();
      if (s <= start + segment || i + 2 == e.right.size()) {
        along = std::min(1.0, (s - start) / segment);
        break;
      }
      start += segment;
    }
    const KDL::Vector right = e.right[i] + (e.right[i + 1] - e.right[i]) * along;
    const KDL::Vector left = e.left[i] + (e.left[i + 1] - e.left[i]) * along;
    const double gap = (left - right).Norm();
    if (gap < model_.closed_gap) continue;
    const KDL::Vector& z = e.skin_normal;
    KDL::Vector x = midpoint(e, i + 1) - midpoint(e, i);
    x = x - z * KDL::dot(x, z);
    x.Normalize();
    const KDL::Rotation frame(x, z * x, z);
    const KDL::Vector down = z * model_.depth;
    target = StitchTarget{k, s, gap, KDL::Frame(frame, right - down), KDL::Frame(frame, left - down)};
    return true;
  }
  return false;
}

}  // namespace cobra::suturing
