#pragma once
// What a chart that stopped changing state is waiting for, and what it heard there (internal to
// cobra::run_core). A transition waiting for a misspelled event, or a chart waiting on an answer
// that came under another name (e_deploy_failed_outlin for a misspelled deployment), otherwise
// sits silent until the run's time limit; the watch says, once the chart has been in one state
// for `run.stall_notice` s, which events its state and the states around it wait for and which
// events arrived there that no transition took, and the time limit's reason says it again.

#include <string>
#include <vector>

namespace cobra::statechart {
class Chart;
}

namespace cobra::run {

class StallWatch {
 public:
  /// The chart entered a state at `t` (s): what it heard before is forgotten.
  void entered(double t);
  /// An event for this chart (its sources') arrived at `t` s. Keeps the first kMaxHeard distinct
  /// names, each with its first source and time.
  void heard(const std::string& event, const std::string& source, double t);
  /// True once per state, the first time the chart has been in it for `after` s at `t`.
  bool due(double t, double after);
  /// "NAME chart in STATE since T s; it waits for e_a, e_b (its transitions there); heard there
  /// with no change of state: e_x (Src at T s), ..." (`chart`: the loaded chart, for the transitions; may
  /// be null, e.g. a chart of another host).
  std::string text(const std::string& name, const std::string& state, const statechart::Chart* chart) const;

  static constexpr std::size_t kMaxHeard = 8;

 private:
  struct Heard {
    std::string event, source;
    double t = 0.0;
  };
  double since_ = 0.0;
  bool said_ = false;
  std::vector<Heard> heard_;
};

}  // namespace cobra::run
