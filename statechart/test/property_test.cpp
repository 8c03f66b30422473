// Seeded random property test: 400 random charts (states, connectors, nested scopes, guards, pn,
// e_done, e_after, doo programs), each driven by 40 random events on a fake clock advancing
// 0-200 ms before each, run step by step on cobra's Machine and on a reference interpreter
// written here from rFSM's rfsm.lua and rfsm_timeevent (find paths from the root down, collect
// every enabled path of a node and take the first, exit up to the LCA, effect, enter down;
// e_done@fqn after entry or when the doo ends; e_init_fsm on the first step; timers from entry,
// checked leaf-up, at the start of a step as cobra documents).
// After every step both must agree on the step's result, the trace of entry/exit/effect calls
// and the active leaf; and the active states must be exactly the leaf and its ancestors.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <deque>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "cobra/statechart/chart.hpp"
#include "cobra/statechart/machine.hpp"

namespace cobra::statechart {
namespace {

constexpr int kCharts = 400;
constexpr int kEventsPerChart = 40;
constexpr int kMaxStepsPerEvent = 60;  // charts may ping-pong forever on "any event" transitions
const char* const kAlphabet[] = {"e0", "e1", "e2", "e3"};

/// What a doo reports on its n-th call after entry; past the end: the last entry again.
using DooProgram = std::vector<DooStatus>;

struct NodeDesc {
  std::string name, fqn;
  int parent = 0;
  bool state = true;
  bool composite = false;
  int initial = -1;  // node index of its initial connector
  DooProgram doo;
};
struct TransDesc {
  int scope, src, tgt;  // node indices; tgt may be a composite (its initial connector then)
  std::vector<std::string> events;
  int pn = 0;
  int guard = -1;  // seed of a pure guard, or -1
  std::string label;
  double after = -1.0;  // s, for an e_after transition
};
struct ChartDesc {
  std::vector<NodeDesc> nodes;
  std::vector<TransDesc> transitions;
};

/// A guard both implementations evaluate identically: a function of its seed and the epoch.
bool guardValue(int seed, int epoch) { return ((seed * 7919 + epoch * 104729) >> 3) % 4 != 0; }

ChartDesc randomChart(std::mt19937& rng) {
  auto pick = [&](int n) { return static_cast<int>(rng() % static_cast<unsigned>(n)); };
  ChartDesc d;
  d.nodes.push_back({"root", "root", 0, true, false, -1, {}});
  const int states = 4 + pick(14);
  for (int i = 0; i < states; ++i) {
    int parent = pick(static_cast<int>(d.nodes.size()));
    NodeDesc n{"s" + std::to_string(i), d.nodes[parent].fqn + ".s" + std::to_string(i), parent, true, false, -1, {}};
    d.nodes.push_back(n);
    d.nodes[parent].composite = true;
  }
  for (NodeDesc& n : d.nodes)
    if (!n.composite && pick(3) == 0) {
      const DooStatus last = pick(2) == 0 ? DooStatus::Idle : DooStatus::Done;
      for (int k = pick(3); k > 0; --k) n.doo.push_back(DooStatus::Busy);
      n.doo.push_back(last);
    }
  // Initial transitions: one per composite to a child state, sometimes waiting for an event
  // with an unconditional fallback of lower pn.
  const std::size_t state_count = d.nodes.size();
  for (std::size_t p = 0; p < state_count; ++p) {
    if (!d.nodes[p].composite) continue;
    d.nodes.push_back({"initial", d.nodes[p].fqn + ".initial", static_cast<int>(p), false, false, -1, {}});
    d.nodes[p].initial = static_cast<int>(d.nodes.size() - 1);
    std::vector<int> children;
    for (std::size_t c = 1; c < state_count; ++c)
      if (d.nodes[c].parent == static_cast<int>(p)) children.push_back(static_cast<int>(c));
    const int initial = d.nodes[p].initial;
    if (pick(4) == 0)
      d.transitions.push_back({static_cast<int>(p), initial, children[pick(static_cast<int>(children.size()))],
                               {kAlphabet[pick(4)]}, 1, -1, ""});
    d.transitions.push_back({static_cast<int>(p), initial, children[pick(static_cast<int>(children.size()))], {}, 0,
                             -1, ""});
  }
  // Junction connectors under composite states; a connector only leads to later connectors.
  const int first_connector = static_cast<int>(d.nodes.size());
  for (int i = pick(4); i > 0; --i) {
    std::vector<int> composites;
    for (std::size_t c = 0; c < state_count; ++c)
      if (d.nodes[c].composite) composites.push_back(static_cast<int>(c));
    const int parent = composites[pick(static_cast<int>(composites.size()))];
    const std::string name = "c" + std::to_string(d.nodes.size());
    d.nodes.push_back({name, d.nodes[parent].fqn + "." + name, parent, false, false, -1, {}});
  }
  const int nodes = static_cast<int>(d.nodes.size());
  for (int i = 0; i < 3 * states; ++i) {
    TransDesc t{};
    const bool from_connector = nodes > first_connector && pick(4) == 0;
    t.src = from_connector ? first_connector + pick(nodes - first_connector) : 1 + pick(static_cast<int>(state_count) - 1);
    do {
      t.tgt = pick(3) == 0 && nodes > first_connector ? first_connector + pick(nodes - first_connector)
                                                      : 1 + pick(static_cast<int>(state_count) - 1);
    } while (from_connector && t.tgt >= first_connector && t.tgt <= t.src);
    const int events = from_connector ? pick(2) : pick(3);
    for (int e = 0; e < events; ++e)
      t.events.push_back(!from_connector && pick(5) == 0 ? "e_done" : kAlphabet[pick(4)]);
    if (!from_connector && pick(6) == 0) {
      const int tenths = 1 + pick(5);
      t.after = tenths / 10.0;
      t.events = {"e_after(0." + std::to_string(tenths) + ")"};
    }
    t.pn = pick(3);
    t.guard = pick(3) == 0 ? i : -1;
    // Defined in a random common ancestor of its ends (a state), so paths come out local,
    // relative or absolute.
    std::vector<int> ancestors;
    for (int a = d.nodes[t.src].parent;; a = d.nodes[a].parent) {
      bool above_tgt = false;
      for (int b = d.nodes[t.tgt].parent;; b = d.nodes[b].parent) {
        above_tgt = above_tgt || b == a;
        if (b == 0) break;
      }
      if (above_tgt) ancestors.push_back(a);
      if (a == 0) break;
    }
    t.scope = ancestors[pick(static_cast<int>(ancestors.size()))];
    d.transitions.push_back(t);
  }
  for (std::size_t i = 0; i < d.transitions.size(); ++i) d.transitions[i].label = "t" + std::to_string(i);
  return d;
}

/// How a transition defined in `scope` names `node`: local, relative (".a.b") or absolute.
std::string pathFrom(const ChartDesc& d, int scope, int node, bool absolute) {
  const NodeDesc& n = d.nodes[node];
  absolute = absolute && n.name != "initial";  // the builder creates `initial` for local references only
  if (n.parent == scope && !absolute) return n.name;
  if (absolute) return n.fqn;
  return n.fqn.substr(d.nodes[scope].fqn.size());
}

/// The traces both implementations write.
struct World {
  std::vector<std::string> trace;
  int epoch = 0;
  std::chrono::nanoseconds now{0};
};

/// The machine's rule for "t seconds after": the same conversion both sides use.
std::chrono::nanoseconds seconds(double t) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::duration<double>(t));
}

Chart buildChart(const ChartDesc& d, World& world, std::mt19937& rng) {
  ChartBuilder b;
  for (std::size_t i = 1; i < d.nodes.size(); ++i) {
    const NodeDesc& n = d.nodes[i];
    if (!n.state) {
      if (n.name != "initial") b.addConnector(d.nodes[n.parent].fqn, n.name);
      continue;
    }
    StateSpec spec;
    spec.entry = [&world, fqn = n.fqn] { world.trace.push_back("entry " + fqn); };
    spec.exit = [&world, fqn = n.fqn] { world.trace.push_back("exit " + fqn); };
    if (!n.doo.empty())
      spec.doo = [program = n.doo, calls = std::size_t{0}](bool restart) mutable {
        if (restart) calls = 0;
        return program[std::min(calls++, program.size() - 1)];
      };
    b.addState(d.nodes[n.parent].fqn, n.name, std::move(spec));
  }
  for (const TransDesc& t : d.transitions) {
    TransitionSpec spec;
    spec.src = pathFrom(d, t.scope, t.src, rng() % 4 == 0);
    spec.tgt = pathFrom(d, t.scope, t.tgt, rng() % 4 == 0);
    spec.events = t.events;
    spec.pn = t.pn;
    if (t.guard >= 0) spec.guard = [&world, seed = t.guard](const StepEvents&) { return guardValue(seed, world.epoch); };
    spec.effect = [&world, label = t.label](const StepEvents&) { world.trace.push_back("effect " + label); };
    b.addTransition(d.nodes[t.scope].fqn, std::move(spec));
  }
  return b.build();
}

/// rFSM's core, transliterated from rfsm.lua with plain containers (allocates freely).
class Reference {
 public:
  Reference(const ChartDesc& d, World& world) : d_(d), world_(world), actchild_(d.nodes.size(), -1),
        mode_(d.nodes.size(), 0), doo_calls_(d.nodes.size(), 0), otrs_(d.nodes.size()),
        entered_at_(d.nodes.size()), fired_(d.transitions.size(), false) {
    for (std::size_t i = 0; i < d.transitions.size(); ++i) otrs_[d.transitions[i].src].push_back(static_cast<int>(i));
    for (auto& list : otrs_)
      std::stable_sort(list.begin(), list.end(), [&](int a, int b) { return d.transitions[a].pn > d.transitions[b].pn; });
    queue_.push_back("e_init_fsm");
  }
  void raise(const std::string& e) { queue_.push_back(e); }
  bool queueEmpty() const { return queue_.empty(); }
  std::string leaf() const { return act_leaf_ < 0 ? "" : d_.nodes[act_leaf_].fqn; }

  StepResult step() {
    if (active_) checkTimeEvents();
    std::vector<std::string> events(queue_.begin(), queue_.end());
    queue_.clear();
    if (!active_) {
      const auto path = findPath(d_.nodes[0].initial, events);
      if (!path) return StepResult::CannotEnter;
      enterOne(0);
      actchild_[0] = -1;
      active_ = true;
      for (int t : *path) execTrans(t);
      return StepResult::Entered;
    }
    if (!events.empty()) {
      for (int s = 0; s >= 0; s = actchild_[s])
        if (const auto path = findPath(s, events)) {
          for (int t : *path) execTrans(t);
          return StepResult::Transitioned;
        }
      return StepResult::EventsIgnored;
    }
    if (mode_[act_leaf_] == 1) {  // active, not done: resume its doo
      const DooProgram& program = d_.nodes[act_leaf_].doo;
      const DooStatus status = program[std::min(doo_calls_[act_leaf_]++, program.size() - 1)];
      if (status == DooStatus::Busy) return StepResult::DooRan;
      if (status == DooStatus::Done) {
        mode_[act_leaf_] = 2;
        queue_.push_back("e_done@" + d_.nodes[act_leaf_].fqn);
      }
    }
    return queue_.empty() ? StepResult::Idle : StepResult::DooRan;
  }

 private:
  int target(int t) const {
    const int tgt = d_.transitions[t].tgt;
    return d_.nodes[tgt].composite ? d_.nodes[tgt].initial : tgt;
  }
  bool enabled(int t, const std::vector<std::string>& events) const {
    const TransDesc& tr = d_.transitions[t];
    if (tr.guard >= 0 && !guardValue(tr.guard, world_.epoch)) return false;
    if (tr.events.empty()) return true;
    for (std::string e : tr.events) {
      if (e == "e_done") e = "e_done@" + d_.nodes[tr.src].fqn;
      if (e.starts_with("e_after(")) e += "@" + d_.nodes[tr.src].fqn;
      if (std::find(events.begin(), events.end(), e) != events.end()) return true;
    }
    return false;
  }
  /// node_find_enabled: every enabled continuation is collected; the first one is executed.
  std::optional<std::vector<int>> findPath(int node, const std::vector<std::string>& events) const {
    std::optional<std::vector<int>> first;
    for (int t : otrs_[node]) {
      if (!enabled(t, events)) continue;
      const int tgt = target(t);
      std::optional<std::vector<int>> tail;
      if (d_.nodes[tgt].state) tail = std::vector<int>{};
      else tail = findPath(tgt, events);
      if (tail && !first) {
        tail->insert(tail->begin(), t);
        first = tail;
      }
    }
    return first;
  }
  void execTrans(int t) {
    const int src = d_.transitions[t].src, tgt = target(t);
    std::vector<int> src_path;
    for (int w = d_.nodes[src].parent;; w = d_.nodes[w].parent) {
      src_path.push_back(w);
      if (w == 0) break;
    }
    int lca = d_.nodes[tgt].parent;
    while (std::find(src_path.begin(), src_path.end(), lca) == src_path.end()) lca = d_.nodes[lca].parent;
    std::vector<int> up, down;
    for (int w = src; w != lca; w = d_.nodes[w].parent) up.push_back(w);
    for (int w = tgt; w != lca; w = d_.nodes[w].parent) down.push_back(w);
    exitState(up.back());
    world_.trace.push_back("effect " + d_.transitions[t].label);
    for (auto it = down.rbegin(); it != down.rend(); ++it) enterOne(*it);
  }
  /// rfsm_timeevent: from the active leaf up to the root, each unfired timer past its deadline.
  void checkTimeEvents() {
    for (int s = act_leaf_ < 0 ? 0 : act_leaf_;; s = d_.nodes[s].parent) {
      for (int t : otrs_[s]) {
        const TransDesc& tr = d_.transitions[t];
        if (tr.after < 0.0 || fired_[t] || world_.now <= entered_at_[s] + seconds(tr.after)) continue;
        queue_.push_back(tr.events.front() + "@" + d_.nodes[s].fqn);
        fired_[t] = true;
      }
      if (s == 0) break;
    }
  }
  void enterOne(int s) {
    const NodeDesc& n = d_.nodes[s];
    if (!n.state) return;
    entered_at_[s] = world_.now;
    for (int t : otrs_[s]) fired_[t] = false;
    mode_[s] = 1;
    actchild_[n.parent] = s;
    if (s != 0) world_.trace.push_back("entry " + n.fqn);
    if (!n.composite) {
      act_leaf_ = s;
      if (n.doo.empty()) {
        mode_[s] = 2;
        queue_.push_back("e_done@" + n.fqn);
      } else {
        doo_calls_[s] = 0;
      }
    }
  }
  void exitState(int s) {
    if (s < 0 || !d_.nodes[s].state) return;
    if (d_.nodes[s].composite) exitState(actchild_[s]);
    mode_[s] = 0;
    actchild_[d_.nodes[s].parent] = -1;
    world_.trace.push_back("exit " + d_.nodes[s].fqn);
    if (!d_.nodes[s].composite) act_leaf_ = -1;
  }

  const ChartDesc& d_;
  World& world_;
  std::vector<int> actchild_, mode_;  // mode: 0 inactive, 1 active, 2 done
  std::vector<std::size_t> doo_calls_;
  std::vector<std::vector<int>> otrs_;
  std::deque<std::string> queue_;
  std::vector<std::chrono::nanoseconds> entered_at_;
  std::vector<bool> fired_;
  bool active_ = false;
  int act_leaf_ = -1;
};

/// Counts the transitions a time event took.
struct Timeouts : Observer {
  int count = 0;
  void transitionTaken(const Chart::Transition& t) override { count += t.time_spec >= 0.0 ? 1 : 0; }
};

bool stepWasIdle(StepResult r) { return r == StepResult::Idle || r == StepResult::CannotEnter; }

TEST(StatechartProperty, RandomChartsRunStepByStepAsTheRfsmReferenceAndKeepALeafConfiguration) {
  std::mt19937 rng(20261122);
  int transitions_taken = 0, doo_steps = 0, entered = 0;
  Timeouts timeouts;
  for (int round = 0; round < kCharts; ++round) {
    const ChartDesc desc = randomChart(rng);
    World engine_world, reference_world;
    const Chart chart = buildChart(desc, engine_world, rng);
    Machine machine(chart, [&engine_world] { return engine_world.now; });
    machine.setObserver(&timeouts);
    Reference reference(desc, reference_world);
    for (int event = -1; event < kEventsPerChart; ++event) {
      engine_world.epoch = reference_world.epoch = event;
      engine_world.now = reference_world.now = engine_world.now + std::chrono::milliseconds(50 * (rng() % 5));
      if (event >= 0) {
        const std::string name = rng() % 8 == 0 ? "e_unknown" : kAlphabet[rng() % 4];
        ASSERT_EQ(machine.raise(name), RaiseStatus::Queued);
        reference.raise(name);
      }
      for (int s = 0; s < kMaxStepsPerEvent; ++s) {
        const StepResult got = machine.step();
        const StepResult want = reference.step();
        ASSERT_EQ(static_cast<int>(got), static_cast<int>(want)) << "round " << round << ", event " << event;
        ASSERT_EQ(engine_world.trace, reference_world.trace) << "round " << round << ", event " << event;
        ASSERT_EQ(machine.activeLeaf(), reference.leaf()) << "round " << round;
        engine_world.trace.clear();
        reference_world.trace.clear();
        transitions_taken += got == StepResult::Transitioned ? 1 : 0;
        doo_steps += got == StepResult::DooRan ? 1 : 0;
        if (stepWasIdle(got)) break;
      }
      if (!machine.entered()) continue;
      ++entered;
      const int leaf = chart.find(machine.activeLeaf());
      ASSERT_GE(leaf, 0) << "round " << round;
      ASSERT_FALSE(chart.node(leaf).composite);
      for (int n = 0; n < static_cast<int>(chart.nodes().size()); ++n) {
        if (chart.node(n).kind != NodeKind::State) continue;
        bool ancestor = false;
        for (int a = leaf;; a = chart.node(a).parent) {
          ancestor = ancestor || a == n;
          if (a == 0) break;
        }
        EXPECT_EQ(machine.isActive(chart.node(n).fqn), ancestor) << chart.node(n).fqn << " with leaf " << chart.node(leaf).fqn;
      }
    }
  }
  std::printf("%d transitions (%d by time events), %d doo steps, %d entered checks\n", transitions_taken,
              timeouts.count, doo_steps, entered);
  // The generator must exercise the engine, not only agree with the reference on idleness.
  EXPECT_GT(transitions_taken, 20 * kCharts);
  EXPECT_GT(doo_steps, kCharts);
  EXPECT_GT(timeouts.count, kCharts);
  EXPECT_GT(entered, kCharts * kEventsPerChart / 2);
}

}  // namespace
}  // namespace cobra::statechart
