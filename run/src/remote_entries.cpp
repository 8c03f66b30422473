#include "remote_entries.hpp"

#include "builtin_observers.hpp"

#include <utility>

namespace cobra::run {
namespace {

/// The host of the first remote name among `paths` ("" when all are local or empty).
std::string hostOfAny(const std::vector<std::string>& paths, const RemoteHostOf& remote_host) {
  for (const std::string& p : paths) {
    if (p.empty()) continue;
    const std::string host = remote_host(componentOfPath(p));
    if (!host.empty()) return host;
  }
  return "";
}

/// What the filter knows while it goes: the dropped charts and trackings, with their hosts.
struct Dropped {
  std::map<std::string, std::string> charts, trackings;  // name -> host
  std::map<std::string, std::vector<std::string>> by_host;

  std::string chartHost(const std::string& chart) const {
    const auto it = charts.find(chart);
    return it == charts.end() ? "" : it->second;
  }
  /// Drops the entries of `list` for which `host_of` gives a host, recording them as `name_of` says.
  template <class T, class HostOf, class NameOf>
  void filter(std::vector<T>& list, HostOf host_of, NameOf name_of) {
    std::erase_if(list, [&](const T& entry) {
      const std::string host = host_of(entry);
      if (host.empty()) return false;
      by_host[host].push_back(name_of(entry));
      return true;
    });
  }
};

/// The host of a plot column: a port's component, or the host of the tracking a derived column
/// ("tracking.NAME.mm") comes from.
std::string hostOfColumn(const std::string& column, const Dropped& dropped, const RemoteHostOf& remote_host) {
  if (startsWith(column, "tracking.")) {
    for (const auto& [name, host] : dropped.trackings)
      if (startsWith(column, "tracking." + name + ".")) return host;
    return "";
  }
  if (startsWith(column, "clearance") || startsWith(column, "contact.")) return "";
  return remote_host(componentOfPath(column));
}

}  // namespace

std::string componentOfPath(const std::string& path) { return path.substr(0, path.find_first_of(".[")); }

RemoteEntries dropRemoteEntries(RunSpec& spec, const RemoteHostOf& remote_host) {
  Dropped d;
  const auto quoted = [](const std::string& kind, const std::string& name) { return kind + " '" + name + "'"; };
  d.filter(
      spec.charts,
      [&](const ChartSpec& c) {
        const std::string host = remote_host(c.supervisor);
        if (!host.empty()) d.charts[c.name] = host;
        return host;
      },
      [&](const ChartSpec& c) { return quoted("run.charts", c.name); });
  d.filter(
      spec.tracking,
      [&](const TrackingSpec& t) {
        std::string host = hostOfAny({t.commanded, t.measured, t.joints, t.max_velocity}, remote_host);
        if (host.empty() && !t.chart.empty()) host = d.chartHost(t.chart);
        if (!host.empty()) d.trackings[t.name] = host;
        return host;
      },
      [&](const TrackingSpec& t) { return quoted("run.tracking", t.name); });
  d.filter(
      spec.summary,
      [&](const SummarySpec& s) {
        const std::string host = hostOfAny(s.ports, remote_host);
        return host.empty() && !s.chart.empty() ? d.chartHost(s.chart) : host;
      },
      [&](const SummarySpec& s) { return quoted("run.summary", s.name); });
  for (SummarySpec& s : spec.summary) {  // the expected count is asked of its component: local only
    if (!s.of.empty() && !remote_host(componentOfPath(s.of)).empty()) s.of.clear();
    // An event expected while another host's chart is in a state cannot be judged here: that
    // host's count says it; this host counts the event as it hears it.
    std::erase_if(s.expected, [&](const SummarySpec::Expected& e) { return !d.chartHost(e.chart).empty(); });
  }
  d.filter(
      spec.record.ports, [&](const auto& p) { return remote_host(componentOfPath(p.first)); },
      [&](const auto& p) { return "run.record " + p.first; });
  // A plot keeps its series of this host (the needle's tank beside the probe's: the needle's);
  // it goes whole when none is left, or when its x axis, paths or marks are another host's.
  std::vector<PlotSpec> plots;
  for (PlotSpec& p : spec.plots) {
    std::vector<std::string> columns;
    if (!p.x.empty()) columns.push_back(p.x);
    std::string host = d.chartHost(p.from_chart);
    for (const PathSpec& path : p.paths) {
      columns.push_back(path.x);
      columns.push_back(path.y);
      for (const PathSpec::Mark& m : path.marks)
        if (host.empty()) host = d.chartHost(m.chart);
    }
    for (const std::string& column : columns)
      if (host.empty()) host = hostOfColumn(column, d, remote_host);
    std::vector<std::string> local, remote;
    std::string series_host;
    for (const std::string& column : p.series) {
      const std::string h = hostOfColumn(column, d, remote_host);
      (h.empty() ? local : remote).push_back(column);
      if (!h.empty()) series_host = h;
    }
    if (host.empty() && local.empty() && p.paths.empty()) host = series_host;
    if (!host.empty()) {
      d.by_host[host].push_back(quoted("run.plots", p.title));
      continue;
    }
    for (const std::string& column : remote)
      d.by_host[hostOfColumn(column, d, remote_host)].push_back(quoted("run.plots", p.title) + " series " + column);
    p.series = std::move(local);
    plots.push_back(std::move(p));
  }
  spec.plots = std::move(plots);
  if (spec.clearance.declared) {
    ClearanceSpec& c = spec.clearance;
    std::string host = hostOfAny({c.port, c.threshold_operation}, remote_host);
    for (const ClearancePause& pause : c.pauses)
      if (host.empty()) host = d.chartHost(pause.chart);
    if (!host.empty()) {
      d.by_host[host].push_back("run.clearance");
      c = ClearanceSpec{};
      // The section goes with its host: its observer is not attached here.
      std::erase_if(spec.observers, [](const ObserverSection& s) { return s.name == "clearance"; });
    } else {
      d.filter(
          c.contacts, [&](const auto& contact) { return remote_host(componentOfPath(contact.second)); },
          [&](const auto& contact) { return quoted("run.clearance contact", contact.first); });
    }
  }
  StudioSpec& studio = spec.studio;
  std::string scene_host;  // the scene's host when it is another's: the robots it models go with it
  if (!studio.scene.empty())
    if (scene_host = remote_host(studio.scene); !scene_host.empty()) {
      d.by_host[scene_host].push_back("run.studio.scene " + studio.scene);
      studio.scene.clear();
    }
  d.filter(
      studio.robots,
      [&](const StudioSpec::Robot& r) {
        const std::string host = remote_host(componentOfPath(r.joints));
        // A robot drawn from a kinematics solver's chain goes with the solver when its joints are here.
        if (!r.kinematics.empty()) return host.empty() ? remote_host(r.kinematics) : host;
        return host.empty() && r.count == 0 ? scene_host : host;
      },
      [&](const StudioSpec::Robot& r) {
        const bool for_scene = remote_host(componentOfPath(r.joints)).empty() && r.kinematics.empty();
        return quoted("run.studio.robots", r.name) + (for_scene ? " (its model is the scene's)" : "");
      });
  d.filter(
      studio.extras,
      [&](const StudioSpec::Extra& e) { return hostOfAny({e.pose, e.radius, e.frame}, remote_host); },
      [&](const StudioSpec::Extra& e) { return quoted("run.studio.extras", e.name); });
  d.filter(
      studio.signals, [&](const auto& s) { return remote_host(componentOfPath(s.first)); },
      [&](const auto& s) { return "run.studio.signals " + s.first; });
  d.filter(
      studio.inputs, [&](const StudioSpec::Input& i) { return remote_host(componentOfPath(i.call)); },
      [&](const StudioSpec::Input& i) { return quoted("run.studio.inputs", i.name); });
  RemoteEntries result{{}, d.charts};
  d.filter(
      spec.actions, [&](const ActionSpec& a) { return remoteHostOfAction(a, result, remote_host); },
      [&](const ActionSpec& a) { return "run.actions " + a.text + " (" + a.where.text() + ")"; });
  result.by_host = std::move(d.by_host);
  return result;
}

std::string remoteHostOfAction(const ActionSpec& action, const RemoteEntries& dropped, const RemoteHostOf& remote_host) {
  if (action.kind != ActionSpec::Kind::Lua && !action.component.empty())
    if (const std::string host = remote_host(action.component); !host.empty()) return host;
  if (action.on.kind != Trigger::Kind::State) return "";
  const auto it = dropped.charts.find(action.on.chart);
  return it == dropped.charts.end() ? "" : it->second;
}

}  // namespace cobra::run
