#include "cobra/trajectory/trajectory.hpp"

#include <algorithm>
#include <utility>

namespace cobra::trajectory {

Trajectory::Trajectory(std::vector<Segment> segments) : segments_(std::move(segments)) {
  start_times_.reserve(segments_.size());
  for (const Segment& s : segments_) start_times_.push_back(s.start_time);
  const Segment& last = segments_.back();
  duration_ = last.start_time + last.polynomial.duration();
}

void Trajectory::evaluate(double t, State& out) const noexcept {
  if (!(t >= 0.0)) {  // also NaN
    segments_.front().polynomial.evaluate(0.0, out);
    out = State{out.position};
    return;
  }
  if (t > duration_) {
    const Segment& last = segments_.back();
    last.polynomial.evaluate(last.polynomial.duration(), out);
    out = State{out.position};
    return;
  }
  // The last segment whose start is <= t (there is one: the first starts at 0 <= t).
  const auto after = std::upper_bound(start_times_.begin(), start_times_.end(), t);
  const Segment& segment = segments_[static_cast<std::size_t>(after - start_times_.begin()) - 1];
  segment.polynomial.evaluate(t - segment.start_time, out);
}

PolynomialTrajectory::PolynomialTrajectory(int order, const Conditions& conditions, double duration)
    : PolynomialTrajectory(Polynomial(order, conditions, duration)) {}

PolynomialTrajectory::PolynomialTrajectory(const Polynomial& polynomial)
    : Trajectory(std::vector<Segment>{Segment{0.0, polynomial}}) {}

PolynomialTrajectory stopTrajectory(const State& current, double stop_time) {
  return PolynomialTrajectory(Polynomial::stop(current, stop_time));
}

}  // namespace cobra::trajectory
