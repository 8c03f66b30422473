// The observers' bookkeeping of a Session (session.hpp): tracking, clearance, plots and summary
// values, attached by the names of the run table and fed once per step.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "cobra/deploy/suggest.hpp"
#include "session.hpp"

namespace cobra::run {
namespace {

bool containsAny(const std::string& text, const std::vector<std::string>& any) {
  return std::any_of(any.begin(), any.end(), [&](const std::string& s) { return text.find(s) != std::string::npos; });
}

}  // namespace

core::Component* ownerOf(const core::ComponentRegistry& refs, const std::string& path, bool operation) {
  const auto dot = path.find('.');
  if (dot == std::string::npos) return nullptr;
  core::Component* owner = refs.find(path.substr(0, dot));
  if (owner == nullptr) return nullptr;
  const std::string member = path.substr(dot + 1);
  return (operation ? owner->findOperation(member) != nullptr : owner->findProperty(member) != nullptr) ? owner
                                                                                                       : nullptr;
}

std::string memberOf(const std::string& path) { return path.substr(path.find('.') + 1); }

void Session::attachTracking() {
  for (const TrackingSpec& t : spec_.tracking) {
    Tracker tracker;
    tracker.spec = t;
    const std::string at = t.where.text(), use = "run.tracking '" + t.name + "'";
    tracker.commanded = std::make_unique<Tap<KDL::Frame>>(refs_, t.commanded, at, use, "KDL.Frame");
    tracker.measured = std::make_unique<Tap<KDL::Frame>>(refs_, t.measured, at, use, "KDL.Frame");
    std::vector<double> limits = t.max_velocity_values;
    if (!t.joints.empty())
      tracker.joints = std::make_unique<Tap<KDL::JntArray>>(refs_, t.joints, at, use, "KDL.JntArray");
    if (!t.joints.empty() && limits.empty()) {
      core::Component* owner = ownerOf(refs_, t.max_velocity, false);
      if (owner == nullptr)
        throw std::runtime_error(at + ": " + use + ": max_velocity '" + t.max_velocity +
                                 "' is not a property Comp.name of the deployment");
      limits = owner->getProperty<std::vector<double>>(memberOf(t.max_velocity));
      if (limits.empty())
        throw std::runtime_error(at + ": " + use + ": " + t.max_velocity +
                                 " is empty: the joint-jump check needs the joints' velocity limits (rad/s, m/s)");
    }
    tracker.chart = t.chart.empty() ? nullptr : chartOf(t.chart);
    if (!t.chart.empty() && tracker.chart == nullptr)
      throw std::runtime_error(at + ": " + use + ": unknown chart '" + t.chart + "'");
    tracker.limits = limits.size();
    tracker.monitor = std::make_unique<TrackingMonitor>(t.name, limits, spec_.step);
    // Wall clock: the joints read at a sample were published by the robot's own thread up to one
    // of its periods before.
    if (options_.realtime) tracker.monitor->setSampleSkew(spec_.step);
    tracker.mm_column = recording_.addDerived("tracking." + t.name + ".mm", "mm");
    tracker.deg_column = recording_.addDerived("tracking." + t.name + ".deg", "deg");
    trackers_.push_back(std::move(tracker));
  }
}

void Session::attachClearance() {
  if (!spec_.clearance.declared) return;
  clearance_ = std::make_unique<ClearanceObserver>();
  ClearanceObserver& c = *clearance_;
  c.spec = spec_.clearance;
  const std::string at = c.spec.where.text();
  c.clearance = std::make_unique<Tap<double>>(refs_, c.spec.port, at, "run.clearance", "double (m)");
  for (const auto& [name, port] : c.spec.contacts) {
    c.contacts.push_back(std::make_unique<Tap<double>>(refs_, port, at, "run.clearance contact '" + name + "'", "double (m)"));
    c.contact_columns.push_back(recording_.addDerived("contact." + name, "m"));
    result_.clearance.contacts.emplace_back(name, std::numeric_limits<double>::infinity());
  }
  for (const ClearancePause& pause : c.spec.pauses) {
    c.pause_charts.push_back(chartOf(pause.chart));
    if (c.pause_charts.back() == nullptr)
      throw std::runtime_error(at + ": run.clearance pause '" + pause.name + "': unknown chart '" + pause.chart + "'");
  }
  c.paused.assign(c.spec.pauses.size(), false);
  result_.clearance.threshold = c.spec.threshold;
  if (!c.spec.threshold_operation.empty()) {
    core::Component* owner = ownerOf(refs_, c.spec.threshold_operation, true);
    if (owner == nullptr)
      throw std::runtime_error(at + ": run.clearance: threshold '" + c.spec.threshold_operation +
                               "' is not an operation Comp.name");
    result_.clearance.threshold = owner->call<double>(memberOf(c.spec.threshold_operation));
  }
  c.column = recording_.addDerived("clearance", "m");
  c.threshold_column = recording_.addDerived("clearance.threshold", "m");
}

void Session::attachPlots() {
  // A plot's ports are recorded too; every name it gives must be a column.
  for (const PlotSpec& p : spec_.plots) {
    std::vector<std::string> names = p.series;
    if (!p.x.empty()) names.push_back(p.x);
    const std::string use = "run.plots '" + p.title + "'";
    if (!p.from_chart.empty() && chartOf(p.from_chart) == nullptr)
      throw std::runtime_error(p.where.text() + ": " + use + ": from: no chart '" + p.from_chart + "' in run.charts");
    for (const PathSpec& path : p.paths) {
      names.push_back(path.x);
      names.push_back(path.y);
      for (const PathSpec::Mark& mark : path.marks)
        if (chartOf(mark.chart) == nullptr)
          throw std::runtime_error(p.where.text() + ": " + use + ": path '" + path.label + "', mark '" + mark.label +
                                   "': no chart '" + mark.chart + "' in run.charts");
    }
    for (const std::string& name : names) {
      const bool derived = startsWith(name, "tracking.") || startsWith(name, "clearance") || startsWith(name, "contact.");
      if (!derived) recording_.addPort(refs_, name.substr(0, name.find_first_of(".[", name.find('.') + 1)), p.where.text(), use);
      std::vector<std::string> fields;
      if (recording_.knows(name, fields)) continue;
      if (fields.empty())
        throw std::runtime_error(p.where.text() + ": " + use + ": no column '" + name + "'" +
                                 deploy::suggestionText(name, recording_.columnNames(), "columns"));
      std::string known;
      for (const std::string& f : fields) known += (known.empty() ? "" : ", ") + name + (f[0] == '[' ? "" : ".") + f;
      throw std::runtime_error(p.where.text() + ": " + use + ": " + name + " has several values; name one: " + known);
    }
  }
}

void Session::attachSummaries() {
  for (const SummarySpec& s : spec_.summary) {
    SummaryObserver o;
    o.spec = s;
    const std::string at = s.where.text(), use = "run.summary '" + s.name + "'";
    if (s.kind == SummarySpec::Kind::Distance)
      for (const std::string& port : s.ports)
        o.frames.push_back(std::make_unique<Tap<KDL::Frame>>(refs_, port, at, use, "KDL.Frame"));
    if (s.kind == SummarySpec::Kind::Port) o.value = std::make_unique<Tap<double>>(refs_, s.ports[0], at, use, "double");
    if (s.kind != SummarySpec::Kind::Count && chartOf(s.chart) == nullptr)
      throw std::runtime_error(at + ": " + use + ": unknown chart '" + s.chart + "'");
    summaries_.push_back(std::move(o));
    result_.summary.push_back({s.name, s.unit, {}, {}, {}});
  }
}

void Session::sampleSummaries() {
  for (std::size_t i = 0; i < summaries_.size(); ++i) {
    const SummarySpec& s = summaries_[i].spec;
    if (s.kind == SummarySpec::Kind::Count) continue;
    const Chart& c = *chartOf(s.chart);
    const bool in = startsWith(c.state, s.state), was = startsWith(c.previous, s.state);
    if (s.leave ? !(was && !in) : !(in && !was)) continue;
    double value = NAN;
    KDL::Frame a, b;
    if (s.kind == SummarySpec::Kind::Distance && summaries_[i].frames[0]->read(a) && summaries_[i].frames[1]->read(b))
      value = s.scale * (a.p - b.p).Norm();
    if (s.kind == SummarySpec::Kind::Port && summaries_[i].value->read(value)) value *= s.scale;
    if (std::isnan(value)) continue;
    result_.summary[i].values.push_back(value);
    result_.summary[i].times.push_back(t_);
    char text[64];
    std::snprintf(text, sizeof text, "%.2f", value);
    if (s.say) say("  " + s.name + ": " + text + (s.unit.empty() ? "" : " " + s.unit));
  }
}

void Session::observeFidelity() {
  static const std::string kNoState;
  const std::uint64_t switches = configurator_.switchCount();
  if (switches != tracker_switches_seen_) {
    tracker_switches_seen_ = switches;
    for (Tracker& tr : trackers_) {
      const auto& counting = tr.spec.counts_while;
      tr.counts = counting.empty() || std::find(counting.begin(), counting.end(),
                                                configurator_.currentDeployment(tr.spec.scope)) != counting.end();
    }
  }
  for (Tracker& tr : trackers_) {
    KDL::Frame commanded, measured;
    KDL::JntArray& q = tr.joint_sample;  // kept: reading into it reuses its storage
    if (!tr.commanded->read(commanded) || !tr.measured->read(measured)) continue;
    const bool have_q = tr.joints && tr.joints->read(q);
    if (have_q && q.rows() != tr.limits)
      throw std::runtime_error(tr.spec.where.text() + ": run.tracking '" + tr.spec.name + "': " + tr.spec.joints + " has " +
                               std::to_string(q.rows()) + " joints but max_velocity gives " +
                               std::to_string(tr.limits) + " limits");
    tr.monitor->step(t_, tr.counts, tr.chart ? tr.chart->state : kNoState, commanded, measured, have_q ? &q : nullptr);
  }
  if (!clearance_) return;
  ClearanceObserver& o = *clearance_;
  ClearanceFigures& figures = result_.clearance;
  for (std::size_t p = 0; p < o.spec.pauses.size(); ++p) {
    const ClearancePause& pause = o.spec.pauses[p];
    const Chart& chart = *o.pause_charts[p];
    if (!chart.changed) continue;  // the same state decides the same
    if (containsAny(chart.state, pause.from)) o.paused[p] = true;
    else if (containsAny(chart.state, pause.to)) o.paused[p] = false;
  }
  const bool counts = std::none_of(o.paused.begin(), o.paused.end(), [](bool b) { return b; });
  double d = NAN;
  if (!counts) {
    o.last = NAN;
  } else if (o.clearance->read(d)) {
    o.last = d;
    figures.seconds_sampled += dt_;
    if (std::isnan(d)) {
      ++figures.unreachable;
    } else {
      if (d <= figures.threshold) figures.seconds_below += dt_;
      if (d < figures.worst) figures.worst = d, figures.worst_at = t_, figures.worst_state = statesText();
    }
  }
  for (std::size_t k = 0; k < o.contacts.size(); ++k) {
    double contact = NAN;
    if (!o.contacts[k]->read(contact) || std::isnan(contact)) continue;
    figures.contacts[k].second = std::min(figures.contacts[k].second, contact);
    recording_.set(o.contact_columns[k], contact);
  }
}

void Session::record() {
  for (std::size_t i = 0; i < trackers_.size(); ++i) {
    const auto [mm, deg] = trackers_[i].monitor->takeWindowMaximum();
    recording_.set(trackers_[i].mm_column, mm);
    recording_.set(trackers_[i].deg_column, deg);
  }
  if (clearance_) {
    recording_.set(clearance_->column, clearance_->last);
    recording_.set(clearance_->threshold_column, result_.clearance.threshold);
  }
  recording_.sample(t_);
}

void Session::finishSummary() {
  for (std::size_t i = 0; i < summaries_.size(); ++i) {
    SummaryValue& v = result_.summary[i];
    const SummarySpec& s = summaries_[i].spec;
    if (s.kind == SummarySpec::Kind::Count) {
      for (const report::EventRecord& e : result_.events)
        if (std::find(s.events.begin(), s.events.end(), e.event.substr(0, e.event.find(' '))) != s.events.end())
          v.values.push_back(1.0), v.times.push_back(e.time);
      v.text = std::to_string(v.values.size());
      continue;
    }
    char number[32];
    for (const double value : v.values) {
      std::snprintf(number, sizeof number, "%.2f", value);
      v.text += (v.text.empty() ? "" : ", ") + std::string(number) + (s.unit.empty() ? "" : " " + s.unit);
    }
    if (v.text.empty()) v.text = "-";
    if (core::Component* owner = s.of.empty() ? nullptr : ownerOf(refs_, s.of, true))
      v.text += " (" + std::to_string(v.values.size()) + " of " + std::to_string(owner->call<int>(memberOf(s.of))) + ")";
  }
}

void Session::notePeerJoins() {
  // The link's e_peer_joined may come while this host is still loading, before the event log
  // listens to it: the run asks the link which peers it has heard from (operation joinedPeers).
  const auto* link = dynamic_cast<const core::Component*>(configurator_.clockSync());
  core::OperationBase* joined = link == nullptr ? nullptr : link->findOperation("joinedPeers");
  if (joined == nullptr) return;
  std::istringstream names(joined->invokeFromText({}));
  for (std::string name; std::getline(names, name, ',');) {
    if (std::find(joined_peers_.begin(), joined_peers_.end(), name) != joined_peers_.end()) continue;
    joined_peers_.push_back(name);
    result_.log.push_back("peer joined: '" + name + "'");
    say("peer '" + name + "' joined");
  }
}

}  // namespace cobra::run
