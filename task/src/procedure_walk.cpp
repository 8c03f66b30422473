#include "cobra/task/procedure_walk.hpp"

#include <algorithm>

namespace cobra::task {
namespace {

constexpr std::size_t kArms = 2;
constexpr std::size_t kPairValues = kArms * kPoseValues;

KDL::Frame decodePose(const std::vector<double>& values, std::size_t slot) {
  const double* v = values.data() + slot * kPoseValues;
  return KDL::Frame(KDL::Rotation::Quaternion(v[3], v[4], v[5], v[6]), KDL::Vector(v[0], v[1], v[2]));
}

PosePair decodePair(const std::vector<double>& values, std::size_t pair) {
  return {decodePose(values, pair * kArms), decodePose(values, pair * kArms + 1)};
}

/// The task's datums, with `hold` where the walk left each arm and the table's own poses.
class WalkSource final : public DatumSource {
 public:
  WalkSource(const StateTable& table, ItemDatumSource& task, const PosePair& at) : table_(table), task_(task), at_(at) {}
  Outcome resolve(const Datum& datum, std::size_t arm, KDL::Frame& pose, const char*& why) override {
    if (datum.name == "hold") {
      pose = at_[arm];
      return Outcome::Resolved;
    }
    if (const KDL::Frame* fixed = table_.pose(datum.name)) {
      pose = *fixed;
      return Outcome::Resolved;
    }
    return task_.resolve(datum, arm, pose, why);
  }

 private:
  const StateTable& table_;
  ItemDatumSource& task_;
  const PosePair& at_;
};

/// "needle=a|b|c": the row's goal datums of `arm`.
std::string goalDatums(const StateRow& row, std::size_t arm, const std::string& name) {
  std::string text = name + "=";
  for (std::size_t k = 0; k < row.goal(arm).size(); ++k) text += (k ? "|" : "") + describe(row.goal(arm)[k]);
  return text;
}

/// The refusal of a datum that does not resolve: the datum (its key) and why.
ProcedureVerdict& refuse(ProcedureVerdict& verdict, const GoalFailure& failure) {
  verdict.refusal.datum = std::string(failure.key_prefix) + std::string(failure.arm) + "=" +
                          (failure.datum != nullptr ? describe(*failure.datum) : std::string());
  verdict.refusal.why = failure.why;
  return verdict;
}

}  // namespace

std::string Refusal::text(std::string_view table_file) const {
  std::string text = item + ", task state '" + state + "'";
  if (line > 0) text += " (" + std::string(table_file) + ":" + std::to_string(line) + ")";
  if (!datum.empty()) text += ", " + datum;
  return text + ": " + why;
}

std::vector<GoalCandidate> decodeCandidates(std::span<const std::vector<double>> waypoints,
                                            const std::vector<std::string>& datums) {
  std::vector<GoalCandidate> candidates;
  for (std::size_t k = 0; k < waypoints.size(); ++k) {
    const std::vector<double>& values = waypoints[k];
    GoalCandidate c;
    c.goal = decodePair(values, 0);
    c.then = c.goal;
    if (values.size() >= 2 * kPairValues) {
      c.then = decodePair(values, 1);
      c.has_then = !KDL::Equal(c.goal[0], c.then[0], 0.0) || !KDL::Equal(c.goal[1], c.then[1], 0.0);
      for (std::size_t p = 2; (p + 2) * kPairValues <= values.size(); p += 2)
        c.rooms.push_back({decodePair(values, p), decodePair(values, p + 1)});
    }
    c.datum = k < datums.size() ? datums[k] : std::string();
    candidates.push_back(std::move(c));
  }
  return candidates;
}

ProcedureVerdict walkProcedure(const StateTable& table, std::string_view table_file,
                               const std::array<std::string, 2>& arms, std::span<const ProcedureStep> steps,
                               const PosePair& start, ItemDatumSource& source, StepVerifier& verifier) {
  ProcedureVerdict verdict;
  PosePair at = start;
  WalkSource datums(table, source, at);
  for (std::size_t s = 0; s < steps.size(); ++s) {
    const ProcedureStep& step = steps[s];
    Refusal& refusal = verdict.refusal;
    refusal.step = s;
    refusal.item = source.itemName(step.item);
    refusal.state = step.state;
    const StateRow* row = table.find(step.state);
    if (row == nullptr) {
      refusal.why = "the task state matches no row of " + std::string(table_file);
      return verdict;
    }
    refusal.line = row->line;
    refusal.datum = goalDatums(*row, step.arm, arms[step.arm]);
    source.select(step.item);
    GoalFailure failure;
    StepOutcome outcome;
    if (step.planned) {
      std::vector<std::vector<double>> waypoints(goalAlternatives(*row));
      for (std::vector<double>& w : waypoints) w.reserve(checkedGoalValues(*row));
      if (!checkedGoals(*row, arms, datums, waypoints, failure)) return refuse(verdict, failure);
      // The alternatives are on one arm at most (the table's rule): name them by that arm's datum.
      const std::size_t named = row->goal(0).size() > 1 ? 0 : row->goal(1).size() > 1 ? 1 : step.arm;
      std::vector<std::string> names;
      for (std::size_t k = 0; k < waypoints.size(); ++k)
        names.push_back(describe(row->goal(named)[std::min(k, row->goal(named).size() - 1)]));
      const std::vector<GoalCandidate> candidates = decodeCandidates(waypoints, names);
      outcome = verifier.planned(step, candidates);
      if (outcome.ok) refusal.datum = arms[step.arm] + "=" + candidates[outcome.chosen].datum;
    } else {
      PosePair goal;
      if (!firstGoal(*row, arms, datums, goal, failure)) return refuse(verdict, failure);
      outcome = verifier.straight(step, at, goal);
    }
    if (!outcome.ok) {
      refusal.why = outcome.why;
      return verdict;
    }
    verdict.chosen.push_back(outcome.chosen);
    at = outcome.reached;
  }
  verdict.ok = true;
  verdict.refusal = Refusal{};
  return verdict;
}

}  // namespace cobra::task
