// The observer `summary`: values sampled when a chart enters or leaves a state (the distance
// between two Frame ports, or a double port), or counts of events; each a SummaryValue of the
// result (the report shows every SummaryValue).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include <kdl/frames.hpp>

#include "builtin_observers.hpp"
#include "cobra/core/component.hpp"
#include "cobra/run/runner.hpp"
#include "lua_reader.hpp"

namespace cobra::run {
namespace {

using detail::Reader;

class SummaryObserver final : public Observer {
 public:
  void attach(ObserverContext& run) override {
    run_ = &run;
    for (const SummarySpec& s : run.spec.summary) {
      Entry e;
      e.spec = &s;
      const std::string at = s.where.text(), use = "run.summary '" + s.name + "'";
      if (s.kind == SummarySpec::Kind::Distance)
        for (const std::string& port : s.ports)
          e.frames.push_back(std::make_unique<Tap<KDL::Frame>>(run.components, port, at, use, "KDL.Frame"));
      if (s.kind == SummarySpec::Kind::Port) e.value = std::make_unique<Tap<double>>(run.components, s.ports[0], at, use, "double");
      if (s.kind != SummarySpec::Kind::Count) {
        e.chart = run.chart(s.chart);
        if (e.chart == nullptr) throw std::runtime_error(at + ": " + use + ": unknown chart '" + s.chart + "'");
      }
      for (const SummarySpec::Expected& expected : s.expected) {
        e.expected_charts.push_back(run.chart(expected.chart));
        if (e.expected_charts.back() == nullptr)
          throw std::runtime_error(at + ": " + use + ": expected '" + expected.event + "': unknown chart '" +
                                   expected.chart + "'");
      }
      e.expected_events.reserve(kExpectedReserve);
      e.index = run.result.summary.size();
      run.result.summary.push_back({s.name, s.unit, {}, {}, {}});
      if (!s.expected.empty()) {
        e.expected_index = run.result.summary.size();
        run.result.summary.push_back({"expected task events", "", {}, {}, {}});
      }
      entries_.push_back(std::move(e));
    }
  }

  // On a chart's entry into (or exit from) the state; in every catch-up round too (the wall
  // clock's states between two observations), since it follows chart states only.
  void step(const Moment& now) override {
    if (now.full) markExpected();
    for (Entry& e : entries_) {
      const SummarySpec& s = *e.spec;
      if (s.kind == SummarySpec::Kind::Count || !e.chart->changed) continue;
      const bool in = startsWith(e.chart->state, s.state), was = startsWith(e.chart->previous, s.state);
      if (s.leave ? !(was && !in) : !(in && !was)) continue;
      double value = NAN;
      KDL::Frame a, b;
      if (s.kind == SummarySpec::Kind::Distance && e.frames[0]->read(a) && e.frames[1]->read(b))
        value = s.scale * (a.p - b.p).Norm();
      if (s.kind == SummarySpec::Kind::Port && e.value->read(value)) value *= s.scale;
      if (std::isnan(value)) continue;
      SummaryValue& v = run_->result.summary[e.index];
      v.values.push_back(value);
      v.times.push_back(now.t);
      char text[64];
      std::snprintf(text, sizeof text, "%.2f", value);
      if (s.say) run_->say("  " + s.name + ": " + text + (s.unit.empty() ? "" : " " + s.unit));
    }
  }

  void finish(RunResult& result) override {
    for (const Entry& e : entries_) {
      SummaryValue& v = result.summary[e.index];
      const SummarySpec& s = *e.spec;
      if (s.kind == SummarySpec::Kind::Count) {
        countEvents(e, result);
        continue;
      }
      char number[32];
      for (const double value : v.values) {
        std::snprintf(number, sizeof number, "%.2f", value);
        v.text += (v.text.empty() ? "" : ", ") + std::string(number) + (s.unit.empty() ? "" : " " + s.unit);
      }
      if (v.text.empty()) v.text = "-";
      if (core::Component* owner = s.of.empty() ? nullptr : ownerOf(run_->components, s.of, true))
        v.text += " (" + std::to_string(v.values.size()) + " of " + std::to_string(owner->call<int>(memberOf(s.of))) + ")";
    }
  }

 private:
  struct Entry {
    const SummarySpec* spec = nullptr;
    std::vector<const ChartState*> expected_charts;  // per SummarySpec::expected
    std::vector<std::size_t> expected_events;        // indices in RunResult::events heard where expected
    std::size_t expected_index = 0;                  // its row in RunResult::summary (with `expected`)
    std::vector<std::unique_ptr<Tap<KDL::Frame>>> frames;  // Distance
    std::unique_ptr<Tap<double>> value;                    // Port
    const ChartState* chart = nullptr;                     // not Count
    std::size_t index = 0;                                 // in RunResult::summary
  };
  // The events heard since the last full step that are expected where the charts are now (or
  // were, for a chart that left the state in this step: the event may be what moved it).
  void markExpected() {
    const std::vector<EventRecord>& events = run_->result.events;
    for (; events_seen_ < events.size(); ++events_seen_) {
      const std::string& text = events[events_seen_].event;
      for (Entry& e : entries_) {
        const std::vector<SummarySpec::Expected>& expected = e.spec->expected;
        for (std::size_t k = 0; k < expected.size(); ++k) {
          const ChartState& chart = *e.expected_charts[k];
          if (isEvent(text, expected[k].event) &&
              (startsWith(chart.state, expected[k].state) || (chart.changed && startsWith(chart.previous, expected[k].state)))) {
            e.expected_events.push_back(events_seen_);
            break;
          }
        }
      }
    }
  }

  // A Count entry: its events, those heard where expected on their own row ("e_x x2, e_y x1").
  static void countEvents(const Entry& e, RunResult& result) {
    const SummarySpec& s = *e.spec;
    SummaryValue& v = result.summary[e.index];
    std::vector<std::pair<std::string, int>> expected;  // event, times heard where expected
    for (std::size_t i = 0; i < result.events.size(); ++i) {
      const EventRecord& event = result.events[i];
      const std::string name = event.event.substr(0, event.event.find(' '));
      if (std::find(s.events.begin(), s.events.end(), name) == s.events.end()) continue;
      if (!std::binary_search(e.expected_events.begin(), e.expected_events.end(), i)) {
        v.values.push_back(1.0), v.times.push_back(event.time);
        continue;
      }
      SummaryValue& x = result.summary[e.expected_index];
      x.values.push_back(1.0), x.times.push_back(event.time);
      auto seen = std::find_if(expected.begin(), expected.end(), [&](const auto& p) { return p.first == name; });
      if (seen == expected.end()) expected.emplace_back(name, 1);
      else ++seen->second;
    }
    v.text = std::to_string(v.values.size());
    if (s.expected.empty()) return;
    std::string& text = result.summary[e.expected_index].text;
    for (const auto& [name, times] : expected)
      text += (text.empty() ? "" : ", ") + name + " x" + std::to_string(times);
    if (text.empty()) text = "none";
  }

  // "e_x" or "e_x payload" is the event e_x.
  static bool isEvent(const std::string& text, const std::string& name) {
    return text.compare(0, name.size(), name) == 0 && (text.size() == name.size() || text[name.size()] == ' ');
  }

  static constexpr std::size_t kExpectedReserve = 64;  // expected events per run before the list grows
  ObserverContext* run_ = nullptr;
  std::vector<Entry> entries_;
  std::size_t events_seen_ = 0;  // RunResult::events looked at by markExpected
};

}  // namespace

ObserverRegistry::Kind summaryObserver() {
  return {"summary", "values sampled when a chart enters or leaves a state, or counts of events", "cobra",
          [](const Section& section) -> std::unique_ptr<Observer> {
            std::vector<SummarySpec>& summary = section.spec().summary;
            section.reader().items([&](Reader& s) {
              SummarySpec value;
              value.name = s.string("name", true);
              value.unit = s.string("unit", false);
              value.scale = s.number("scale", 1.0);
              value.of = s.string("of", false);
              value.say = s.boolean("say", false);
              if (s.has("count")) {
                value.kind = SummarySpec::Kind::Count;
                value.events = s.strings("count");
                s.list("expected", [&](Reader& x) {
                  SummarySpec::Expected expected;
                  expected.event = x.string("event", true);
                  std::tie(expected.chart, expected.state) = detail::chartState(x, x.string("during", true));
                  if (std::find(value.events.begin(), value.events.end(), expected.event) == value.events.end())
                    x.fail("event '" + expected.event + "' is not one of `count`");
                  value.expected.push_back(std::move(expected));
                }, "event");
              } else {
                value.kind = s.has("distance") ? SummarySpec::Kind::Distance : SummarySpec::Kind::Port;
                value.ports = s.strings(s.has("distance") ? "distance" : "port");
                if (value.kind == SummarySpec::Kind::Distance && value.ports.size() != 2)
                  s.fail("`distance` must name two Frame ports");
                if (value.kind == SummarySpec::Kind::Port && value.ports.size() != 1)
                  s.fail("give one of count = { events }, distance = { two Frame ports }, port = \"Comp.port\"");
                const bool enter = s.has("on_enter"), leave = s.has("on_leave");
                if (enter == leave) s.fail("give one of on_enter = \"chart:state\", on_leave = \"chart:state\" (when to sample)");
                value.leave = leave;
                std::tie(value.chart, value.state) = detail::chartState(s, s.string(leave ? "on_leave" : "on_enter", true));
              }
              value.where = s.where();
              summary.push_back(std::move(value));
            });
            return std::make_unique<SummaryObserver>();
          }};
}

}  // namespace cobra::run
