// The editor's palette: every component type of every package cobra can load, each made once
// and introspected (studio/PROTOCOL.md, GET /api/editor/palette).

#include <charconv>

#include "cobra/core/data_type.hpp"
#include "cobra/deploy/suggest.hpp"
#include "cobra/studio/component_generator.hpp"
#include "cobra/studio/json.hpp"
#include "editor_internal.hpp"

namespace cobra::studio::editor {
namespace {

/// "[lo, hi]" as the JSON array [lo, hi]; null when unrestricted or not two numbers.
std::string rangeJson(const std::string& range) {
  if (range.size() < 2 || range.front() != '[' || range.back() != ']') return "null";
  const std::string inner = range.substr(1, range.size() - 2);
  const auto comma = inner.find(',');
  if (comma == std::string::npos) return "null";
  double bounds[2];
  const std::string parts[2] = {inner.substr(0, comma), inner.substr(comma + 1)};
  for (int i = 0; i < 2; ++i) {
    const std::string t = parts[i].substr(parts[i].find_first_not_of(' '));
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), bounds[i]);
    if (ec != std::errc() || end != t.data() + t.size()) return "null";
  }
  std::string out = "[";
  json::appendNumber(out, bounds[0]);
  out += ", ";
  json::appendNumber(out, bounds[1]);
  return out + "]";
}

}  // namespace

const core::PortInfo* PaletteType::port(const std::string& name) const {
  for (const core::PortInfo& p : info.ports)
    if (p.name == name) return &p;
  return nullptr;
}
const core::PropertyInfo* PaletteType::property(const std::string& name) const {
  for (const core::PropertyInfo& p : info.properties)
    if (p.name == name) return &p;
  return nullptr;
}
std::vector<std::string> PaletteType::portNames() const {
  std::vector<std::string> names;
  for (const core::PortInfo& p : info.ports) names.push_back(p.name);
  return names;
}
std::vector<std::string> PaletteType::propertyNames() const {
  std::vector<std::string> names;
  for (const core::PropertyInfo& p : info.properties) names.push_back(p.name);
  return names;
}

Palette::Palette(std::unique_ptr<deploy::PackageRegistry> packages) : packages_(std::move(packages)) {
  known_packages_ = packages_->knownPackages();
  for (const std::string& package : known_packages_) {
    try {
      packages_->load(package);
    } catch (const std::exception& e) {
      errors_.push_back(e.what());
    }
  }
  for (const std::string& name : packages_->typeNames()) {
    const deploy::ComponentType& t = packages_->type(name);
    try {
      const auto instance = makeConfigured(name, name, {});
      types_.emplace(name, PaletteType{name, t.package, t.doc, core::describe(*instance)});
    } catch (const std::exception& e) {
      errors_.push_back("component type '" + name + "' (package " + t.package + "): cannot be made to introspect it: " + e.what());
    }
  }
}

const PaletteType* Palette::find(const std::string& type) const {
  const auto it = types_.find(type);
  return it == types_.end() ? nullptr : &it->second;
}

const PaletteType& Palette::get(const std::string& component, const std::string& type) const {
  if (const PaletteType* t = find(type)) return *t;
  throw Refusal(422, "component '" + component + "': unknown component type '" + type + "'" +
                         deploy::suggestionText(type, typeNames(), "types"));
}

std::unique_ptr<core::Component> Palette::make(const std::string& type, const std::string& name) const {
  return packages_->create(type, name);
}

std::unique_ptr<core::Component> Palette::makeConfigured(
    const std::string& type, const std::string& name, const std::vector<std::pair<std::string, std::string>>& values) const {
  auto component = packages_->create(type, name);
  for (const auto& [property, text] : values) component->property(property).setFromText(text);
  if (component->role() != core::Role::Bridge) (void)component->configure();  // failing: its ports as made
  return component;
}

std::vector<std::string> Palette::typeNames() const {
  std::vector<std::string> names;
  for (const auto& [name, t] : types_) names.push_back(name);
  return names;
}

std::string Palette::json() const {
  std::string out = "{\"packages\":[";
  for (std::size_t i = 0; i < known_packages_.size(); ++i) out += (i ? "," : "") + json::quoted(known_packages_[i]);
  out += "],\"errors\":[";
  for (std::size_t i = 0; i < errors_.size(); ++i) out += (i ? "," : "") + json::quoted(errors_[i]);
  out += "],\"types\":[";
  bool first_type = true;
  for (const auto& [name, t] : types_) {
    out += first_type ? "" : ",";
    first_type = false;
    out += "{\"type\":" + json::quoted(name) + ",\"package\":" + json::quoted(t.package) + ",\"role\":" +
           json::quoted(std::string(core::toString(t.info.role))) + ",\"doc\":" +
           json::quoted(t.info.doc.empty() ? t.doc : t.info.doc) + ",\"ports\":[";
    for (std::size_t i = 0; i < t.info.ports.size(); ++i) {
      const core::PortInfo& p = t.info.ports[i];
      out += std::string(i ? "," : "") + "{\"name\":" + json::quoted(p.name) + ",\"direction\":" +
             (p.direction == core::PortDirection::Input ? "\"in\"" : "\"out\"") + ",\"type\":" + json::quoted(p.type) +
             ",\"kind\":" + (p.kind == core::DataKind::Logic ? "\"logic\"" : "\"pure\"") +
             ",\"event\":" + (p.event_port ? "true" : "false") + ",\"unit\":" + json::quoted(p.unit) +
             ",\"doc\":" + json::quoted(p.doc) + "}";
    }
    out += "],\"properties\":[";
    for (std::size_t i = 0; i < t.info.properties.size(); ++i) {
      const core::PropertyInfo& p = t.info.properties[i];
      out += std::string(i ? "," : "") + "{\"name\":" + json::quoted(p.name) + ",\"type\":" + json::quoted(p.type) +
             ",\"unit\":" + json::quoted(p.unit) + ",\"doc\":" + json::quoted(p.doc) + ",\"range\":" + rangeJson(p.range) +
             ",\"default\":" + json::quoted(p.value) + ",\"read_only\":" + (p.read_only ? "true" : "false") + "}";
    }
    out += "],\"operations\":[";
    for (std::size_t i = 0; i < t.info.operations.size(); ++i) {
      const core::OperationInfo& o = t.info.operations[i];
      out += std::string(i ? "," : "") + "{\"name\":" + json::quoted(o.name) + ",\"signature\":" + json::quoted(o.signature) +
             ",\"doc\":" + json::quoted(o.doc) + "}";
    }
    out += "]}";
  }
  // The registered data types, cobra's own and the loaded packages' (a record with its fields):
  // what the new-component dialog offers ("generate": the generator can write a port or property
  // of it) and the inspector shows.
  out += "],\"data_types\":[";
  bool first_data_type = true;
  for (const core::TypeInfo* d : core::TypeRegistry::all()) {
    out += first_data_type ? "" : ",";
    first_data_type = false;
    out += "{\"name\":" + json::quoted(std::string(d->name)) + ",\"kind\":" +
           (d->kind == core::DataKind::Logic ? "\"logic\"" : "\"pure\"") + ",\"cpp\":" + json::quoted(std::string(d->cpp)) +
           ",\"unit\":" + json::quoted(std::string(d->unit)) + ",\"format\":" + json::quoted(std::string(d->format)) +
           ",\"generate\":" + (generatorKnows(*d) ? "true" : "false") + ",\"fields\":[";
    for (std::size_t i = 0; i < d->fields.size(); ++i) {
      const core::FieldInfo& f = d->fields[i];
      out += std::string(i ? "," : "") + "{\"name\":" + json::quoted(std::string(f.name)) + ",\"type\":" +
             json::quoted(std::string(f.type->name)) + ",\"unit\":" + json::quoted(std::string(f.unit)) +
             ",\"doc\":" + json::quoted(std::string(f.doc)) + "}";
    }
    out += "]}";
  }
  return out + "]}";
}

}  // namespace cobra::studio::editor
