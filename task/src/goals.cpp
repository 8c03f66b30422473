#include "cobra/task/goals.hpp"

#include <algorithm>
#include <cassert>
#include <cstdio>

namespace cobra::task {
namespace {

constexpr std::size_t kArms = 2;

/// `datum` with its offset applied (the arm is commanded in its datum's frame), into `pose`.
DatumSource::Outcome resolveMoved(DatumSource& source, const Datum& datum, std::size_t arm, KDL::Frame& pose,
                                  const char*& why) {
  const DatumSource::Outcome outcome = source.resolve(datum, arm, pose, why);
  if (outcome != DatumSource::Outcome::Resolved) return outcome;
  if (datum.offset != 0.0) pose = alongZ(pose, datum.offset);
  return outcome;
}

bool fail(GoalFailure& failure, const char* key_prefix, std::string_view arm, const Datum& datum, const char* why) {
  failure.key_prefix = key_prefix;
  failure.arm = arm;
  failure.datum = &datum;
  failure.why = why;
  return false;
}

const Datum& alternative(const StateRow& row, std::size_t arm, std::size_t k) {
  const std::vector<Datum>& goals = row.goal(arm);
  return goals[std::min(k, goals.size() - 1)];
}

std::size_t alternatives(const StateRow& row) { return std::max(row.goal(0).size(), row.goal(1).size()); }

}  // namespace

void encodePose(const KDL::Frame& pose, std::size_t slot, std::vector<double>& values) noexcept {
  double* out = values.data() + slot * kPoseValues;
  out[0] = pose.p.x();
  out[1] = pose.p.y();
  out[2] = pose.p.z();
  pose.M.GetQuaternion(out[3], out[4], out[5], out[6]);
}

std::string describe(const Datum& datum) {
  FailureText text;
  text << datum;
  return std::string(text.view());
}

FailureText& FailureText::operator<<(std::string_view text) noexcept {
  const std::size_t n = std::min(text.size(), kCapacity - size_);
  std::copy_n(text.data(), n, chars_.data() + size_);
  size_ += n;
  return *this;
}

FailureText& FailureText::operator<<(int value) noexcept {
  char buffer[16];
  const int n = std::snprintf(buffer, sizeof buffer, "%d", value);
  return *this << std::string_view(buffer, static_cast<std::size_t>(std::max(n, 0)));
}

FailureText& FailureText::operator<<(const Datum& datum) noexcept {
  *this << std::string_view(datum.name);
  if (datum.offset == 0.0) return *this;
  char buffer[32];
  const int n = std::snprintf(buffer, sizeof buffer, "%+g", datum.offset);
  return *this << std::string_view(buffer, static_cast<std::size_t>(std::max(n, 0)));
}

void GoalFailure::write(FailureText& out) const noexcept {
  out << key_prefix << arm << "=";
  if (datum != nullptr) out << *datum;
  out << ": " << why;
}

std::string GoalFailure::message() const {
  FailureText text;
  write(text);
  return std::string(text.view());
}

const StateRow* rowFor(const StateTable& table, std::string_view state, std::string_view table_file,
                       FailureText& failure) noexcept {
  const StateRow* row = table.find(state);
  if (row == nullptr) failure << "task state '" << state << "' matches no row of " << table_file;
  return row;
}

void rowWhere(std::string_view state, std::string_view table_file, const StateRow& row, FailureText& out) noexcept {
  out << "task state '" << state << "' (" << table_file << ":" << row.line << "): ";
}

bool hasChecks(const StateRow& row) noexcept {
  return alternatives(row) > 1 || !row.then(0).name.empty() || !row.then(1).name.empty() ||
         !row.roomFor(0).from.name.empty() || !row.roomFor(1).from.name.empty();
}

bool firstGoal(const StateRow& row, const std::array<std::string, 2>& arms, DatumSource& source,
               std::array<KDL::Frame, 2>& first, GoalFailure& failure) {
  KDL::Frame pose;
  for (std::size_t k = 0; k < alternatives(row); ++k) {
    for (std::size_t a = 0; a < kArms; ++a) {
      const Datum& datum = alternative(row, a, k);
      const char* why = "";
      if (resolveMoved(source, datum, a, pose, why) != DatumSource::Outcome::Resolved)
        return fail(failure, "", arms[a], datum, why);
      if (k == 0) first[a] = pose;
    }
  }
  return true;
}

std::size_t goalAlternatives(const StateRow& row) noexcept { return alternatives(row); }

std::size_t checkedGoalValues(const StateRow& row) noexcept {
  std::size_t values = 2 * kArms * kPoseValues;  // the goal pair, then where the motion after it goes
  for (std::size_t a = 0; a < kArms; ++a)
    if (!row.roomFor(a).from.name.empty()) values += 2 * kArms * kPoseValues;  // its start and end pairs
  return values;
}

bool checkedGoals(const StateRow& row, const std::array<std::string, 2>& arms, DatumSource& source,
                  std::span<std::vector<double>> waypoints, GoalFailure& failure) {
  assert(waypoints.size() == alternatives(row));
  for (std::size_t k = 0; k < waypoints.size(); ++k) {
    std::array<KDL::Frame, kArms> goals;
    std::vector<double>& values = waypoints[k];
    values.resize(2 * kArms * kPoseValues);  // within the reserved capacity: no allocation
    for (std::size_t a = 0; a < kArms; ++a) {
      const char* why = "";
      const Datum& datum = alternative(row, a, k);
      if (resolveMoved(source, datum, a, goals[a], why) != DatumSource::Outcome::Resolved)
        return fail(failure, "", arms[a], datum, why);
      encodePose(goals[a], a, values);
      KDL::Frame next = goals[a];
      if (!row.then(a).name.empty() &&
          resolveMoved(source, row.then(a), a, next, why) != DatumSource::Outcome::Resolved)
        return fail(failure, "then_", arms[a], row.then(a), why);
      encodePose(next, kArms + a, values);
    }
    for (std::size_t a = 0; a < kArms; ++a) {
      const DatumMotion& room = row.roomFor(a);
      if (room.from.name.empty()) continue;
      const std::size_t other = 1 - a, at = values.size();
      values.resize(at + 2 * kArms * kPoseValues);
      bool coming = true;
      for (std::size_t end = 0; end < 2 && coming; ++end) {
        const Datum& datum = end == 0 ? room.from : room.to;
        const char* why = "";
        KDL::Frame pose;
        const DatumSource::Outcome outcome = resolveMoved(source, datum, a, pose, why);
        if (outcome == DatumSource::Outcome::NotComing) {
          coming = false;  // the motion will not come: nothing to make room for
        } else if (outcome == DatumSource::Outcome::Missing) {
          return fail(failure, "room_for_", arms[a], datum, why);
        } else {
          encodePose(pose, at / kPoseValues + end * kArms + a, values);
          encodePose(goals[other], at / kPoseValues + end * kArms + other, values);
        }
      }
      if (!coming) values.resize(at);
    }
  }
  return true;
}

}  // namespace cobra::task
