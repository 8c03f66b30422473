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
      e.index = run.result.summary.size();
      entries_.push_back(std::move(e));
      run.result.summary.push_back({s.name, s.unit, {}, {}, {}});
    }
  }

  // On a chart's entry into (or exit from) the state; in every catch-up round too (the wall
  // clock's states between two observations), since it follows chart states only.
  void step(const Moment& now) override {
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
        for (const EventRecord& event : result.events)
          if (std::find(s.events.begin(), s.events.end(), event.event.substr(0, event.event.find(' '))) != s.events.end())
            v.values.push_back(1.0), v.times.push_back(event.time);
        v.text = std::to_string(v.values.size());
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
    std::vector<std::unique_ptr<Tap<KDL::Frame>>> frames;  // Distance
    std::unique_ptr<Tap<double>> value;                    // Port
    const ChartState* chart = nullptr;                     // not Count
    std::size_t index = 0;                                 // in RunResult::summary
  };
  ObserverContext* run_ = nullptr;
  std::vector<Entry> entries_;
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
