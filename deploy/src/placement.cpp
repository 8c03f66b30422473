#include "cobra/deploy/placement.hpp"

#include <algorithm>

#include "cobra/core/error.hpp"
#include "cobra/deploy/suggest.hpp"

namespace cobra::deploy {
namespace {

void checkPattern(const std::string& pattern, const SourceLocation& where, const std::string& list) {
  const auto star = pattern.find('*');
  if (pattern.empty() || pattern == "*" || (star != std::string::npos && star + 1 != pattern.size()))
    throw core::Error(where.text() + ": placement " + list + ": pattern '" + pattern +
                      "' must be a component name or a prefix followed by '*' (e.g. \"Needle*\")");
}

}  // namespace

bool matchesPlacementPattern(const std::string& pattern, const std::string& name) {
  if (!pattern.empty() && pattern.back() == '*') return name.rfind(pattern.substr(0, pattern.size() - 1), 0) == 0;
  return pattern == name;
}

Placement::Placement(PlacementSpec spec, std::string host) : spec_(std::move(spec)), host_(std::move(host)) {
  if (spec_.hosts.empty())
    throw core::Error(spec_.where.text() + ": placement has no hosts; give hosts = { name = { \"Component\", ... } }");
  std::vector<std::string> names;
  for (const PlacementSpec::Host& h : spec_.hosts) {
    names.push_back(h.name);
    for (const std::string& p : h.patterns) checkPattern(p, h.where, "host '" + h.name + "'");
  }
  for (const std::string& p : spec_.everywhere) checkPattern(p, spec_.where, "everywhere");
  if (std::find(names.begin(), names.end(), host_) == names.end()) {
    std::string list;
    for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
    throw core::Error(spec_.where.text() + ": this process's host '" + host_ + "' is not a host of the placement (" +
                      list + ")" + suggestionText(host_, names, "hosts"));
  }
}

std::string Placement::hostOf(const std::string& component, const SourceLocation& where) const {
  std::vector<std::pair<std::string, SourceLocation>> found;  // host ("" everywhere), where placed
  for (const PlacementSpec::Host& h : spec_.hosts)
    if (std::any_of(h.patterns.begin(), h.patterns.end(), [&](const std::string& p) { return matchesPlacementPattern(p, component); }))
      found.emplace_back(h.name, h.where);
  if (std::any_of(spec_.everywhere.begin(), spec_.everywhere.end(),
                  [&](const std::string& p) { return matchesPlacementPattern(p, component); }))
    found.emplace_back("", spec_.where);
  if (found.size() == 1) return found.front().first;
  const std::string head = where.text() + ": component '" + component + "' is placed on ";
  if (found.empty())
    throw core::Error(head + "no host of the placement (" + spec_.where.text() +
                      "): add it, or a pattern matching it, to one host's list or to everywhere");
  std::string places;
  for (const auto& [h, at] : found)
    places += (places.empty() ? "" : " and ") + (h.empty() ? std::string("everywhere") : "host '" + h + "'") + " (" +
              at.text() + ")";
  throw core::Error(head + std::to_string(found.size()) + " sites: " + places + "; place each component once");
}

Placement::Site Placement::siteOf(const std::string& component, const SourceLocation& where) const {
  const std::string h = hostOf(component, where);
  if (h.empty()) return Site::Everywhere;
  return h == host_ ? Site::Local : Site::Remote;
}

core::ConnPolicy Placement::crossHostPolicy(const core::ConnPolicy& local, const std::string& output) const {
  core::ConnPolicy policy = local;
  policy.transport = spec_.transport;
  std::string topic = output;
  std::replace(topic.begin(), topic.end(), '.', '/');
  policy.topic = topic;
  policy.options = spec_.qos;
  return policy;
}

}  // namespace cobra::deploy
