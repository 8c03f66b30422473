// The observer registry (cobra/run/observer.hpp) and the Section face of the run table's reader.
#include <algorithm>
#include <stdexcept>

#include "cobra/deploy/package_registry.hpp"
#include "cobra/deploy/suggest.hpp"
#include "cobra/run/observer.hpp"
#include "builtin_observers.hpp"
#include "lua_reader.hpp"

namespace cobra::run {
namespace {

struct Registry {
  std::vector<ObserverRegistry::Kind> kinds;
  std::vector<std::pair<std::string, ReportWriter>> writers;
  Registry() { addBuiltinObservers(kinds); }
};

Registry& registry() {
  static Registry r;
  return r;
}

}  // namespace

void ObserverRegistry::add(std::string name, std::string doc, ObserverFactory make, std::string owner) {
  if (!make) throw std::runtime_error("ObserverRegistry::add('" + name + "'): no factory");
  std::vector<Kind>& kinds = registry().kinds;
  const auto it = std::find_if(kinds.begin(), kinds.end(), [&](const Kind& k) { return k.name == name; });
  if (it != kinds.end() && it->owner != owner)
    throw std::runtime_error("observer '" + name + "' is registered already by " + it->owner + " (" + owner +
                             " registers it again)");
  if (it != kinds.end()) *it = {std::move(name), std::move(doc), std::move(owner), std::move(make)};
  else kinds.push_back({std::move(name), std::move(doc), std::move(owner), std::move(make)});
}

void ObserverRegistry::add(deploy::PackageBuilder& package, std::string name, std::string doc, ObserverFactory make) {
  add(std::move(name), std::move(doc), std::move(make), "package '" + package.packageName() + "'");
}

const ObserverRegistry::Kind* ObserverRegistry::find(const std::string& name) {
  const std::vector<Kind>& kinds = registry().kinds;
  const auto it = std::find_if(kinds.begin(), kinds.end(), [&](const Kind& k) { return k.name == name; });
  return it == kinds.end() ? nullptr : &*it;
}

std::vector<std::string> ObserverRegistry::names() {
  std::vector<std::string> out;
  for (const Kind& k : registry().kinds) out.push_back(k.name);
  return out;
}

std::vector<ObserverRegistry::Kind> ObserverRegistry::kinds() { return registry().kinds; }

void ObserverRegistry::addReportWriter(const std::string& name, ReportWriter writer) {
  auto& writers = registry().writers;
  const auto it = std::find_if(writers.begin(), writers.end(), [&](const auto& w) { return w.first == name; });
  if (it != writers.end()) it->second = std::move(writer);
  else writers.emplace_back(name, std::move(writer));
}

std::vector<ReportWriter> ObserverRegistry::reportWriters() {
  std::vector<ReportWriter> out;
  for (const auto& [name, writer] : registry().writers) out.push_back(writer);
  return out;
}

const ChartState* ObserverContext::chart(const std::string& name) const {
  for (const ChartState* c : charts)
    if (c->spec->name == name) return c;
  return nullptr;
}

Where Section::where() const { return reader_.where(); }
const std::string& Section::path() const { return reader_.path(); }
void Section::fail(const std::string& what) const { reader_.fail(what); }
bool Section::has(const char* key) const { return reader_.has(key); }
std::string Section::string(const char* key, bool required, const std::string& fallback) const {
  return reader_.string(key, required, fallback);
}
double Section::number(const char* key, double fallback, bool positive) const {
  return reader_.number(key, fallback, positive);
}
bool Section::boolean(const char* key, bool fallback) const { return reader_.boolean(key, fallback); }
std::vector<std::string> Section::strings(const char* key) const { return reader_.strings(key); }
lua_State* Section::state() const { return reader_.state(); }

void Section::list(const char* key, const std::function<void(const Section& entry)>& each, const char* identify) const {
  reader_.list(key, [&](detail::Reader& entry) { each(Section(entry, spec_)); }, identify);
}

void Section::allowOnly(std::initializer_list<const char*> fields) const {
  if (!lua_istable(reader_.state(), -1)) fail("must be a table");
  const std::vector<std::string> known(fields.begin(), fields.end());
  for (const std::string& key : reader_.keys())
    if (std::find(known.begin(), known.end(), key) == known.end())
      fail("unknown field '" + key + "'" + deploy::suggestionText(key, known, "fields"));
}

}  // namespace cobra::run
