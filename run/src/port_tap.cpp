#include "cobra/run/port_tap.hpp"

#include <algorithm>
#include <stdexcept>

#include "cobra/components/reporting/csv_codec.hpp"
#include "cobra/deploy/suggest.hpp"

namespace cobra::run {

std::string readerName(const std::string& path) {
  std::string name = path;
  std::replace(name.begin(), name.end(), '.', '_');
  return name;
}

core::OutputPortBase& findOutput(const core::ComponentRegistry& registry, const std::string& path,
                                 const std::string& where, const std::string& use) {
  const auto dot = path.find('.');
  if (dot == std::string::npos)
    throw std::runtime_error(where + ": " + use + ": '" + path + "' must be written Component.port");
  const std::string component = path.substr(0, dot), port = path.substr(dot + 1);
  core::Component* c = registry.find(component);
  if (c == nullptr) {
    std::vector<std::string> names;
    for (const core::Component* each : registry.components()) names.push_back(each->name());
    throw std::runtime_error(where + ": " + use + ": unknown component '" + component + "'" +
                             deploy::suggestionText(component, names, "components"));
  }
  core::PortBase* p = c->findPort(port);
  auto* out = dynamic_cast<core::OutputPortBase*>(p);
  if (out == nullptr) {
    std::vector<std::string> outputs;
    for (const core::PortBase* each : c->ports())
      if (each->direction() == core::PortDirection::Output) outputs.push_back(each->name());
    if (p == nullptr)
      throw std::runtime_error(where + ": " + use + ": component '" + component + "' has no port '" + port + "'" +
                               deploy::suggestionText(port, outputs, "output ports"));
    std::string list;
    for (const std::string& name : outputs) list += (list.empty() ? "" : ", ") + name;
    throw std::runtime_error(where + ": " + use + ": port " + path + " is an input port; observe an output port: " +
                             list);
  }
  return *out;
}

// The port's codec source (connected to the port at setup) and a row of every cell it writes.
struct NumericTap::Source {
  const components::CsvType* type = nullptr;
  std::string unit;                                      // the port's
  std::unique_ptr<components::reporting_detail::Source> codec;
  std::vector<std::size_t> numeric;                      // the numeric cells of a fixed-column type
  std::vector<double> cells;                             // every cell of the last value
  bool has_data = false;
};

namespace {

std::string fieldOf(const std::string& suffix) { return !suffix.empty() && suffix[0] == '.' ? suffix.substr(1) : suffix; }

// The columns of `type` that are numbers (for a variable-length type: those of one element).
std::vector<components::CsvColumn> numericColumns(const components::CsvType& type, const std::string& unit) {
  std::vector<components::CsvColumn> numeric;
  for (components::CsvColumn& c : type.columns(unit, type.needs_length ? 1 : 0))
    if (c.numeric) numeric.push_back(std::move(c));
  return numeric;
}

// "double, int, ..., example.ForceSample": the registered types a NumericTap takes.
std::string tappableTypes() {
  std::string list;
  for (const components::CsvType* type : components::csvTypes())
    if (!numericColumns(*type, "").empty()) list += (list.empty() ? "" : ", ") + std::string(type->type_name);
  return list;
}

}  // namespace

NumericTap::NumericTap(const core::ComponentRegistry& registry, const std::string& path, const std::string& where,
                       const std::string& use)
    : path_(path), source_(std::make_unique<Source>()) {
  core::OutputPortBase& out = findOutput(registry, path, where, use);
  const std::string type_name(out.type().name);
  Source& s = *source_;
  s.type = components::findCsvType(out.type());
  if (s.type == nullptr)
    throw std::runtime_error(where + ": " + use + ": port " + path + " is a " + type_name +
                             ", which has no CSV codec (register it with cobra::types::registerType<T>()); "
                             "types with numeric columns: " + tappableTypes());
  s.unit = out.unit();
  if (numericColumns(*s.type, s.unit).empty())
    throw std::runtime_error(where + ": " + use + ": port " + path + " is a " + type_name +
                             ", whose CSV columns are text, not numbers; types with numeric columns: " +
                             tappableTypes());
  if (!s.type->needs_length) {
    const std::vector<components::CsvColumn> all = s.type->columns(s.unit, 0);
    for (std::size_t i = 0; i < all.size(); ++i)
      if (all[i].numeric) s.numeric.push_back(i);
    s.cells.resize(all.size());
  }
  // Elements 0: a variable-length value is written in as many cells as it has (its length).
  s.codec = s.type->make_source(out, out.makeReader(readerName(path), "cobra run recorder"), 0);
  out.connectTo(s.codec->reader(), core::ConnPolicy::data());
}

NumericTap::~NumericTap() = default;

std::vector<NumericTap::Column> NumericTap::columns(std::size_t n) const {
  const Source& s = *source_;
  std::vector<Column> out;
  for (const components::CsvColumn& c : s.type->columns(s.unit, s.type->needs_length ? n : 0))
    if (c.numeric) out.push_back({fieldOf(c.suffix), path_ + c.suffix, c.unit});
  return out;
}

std::vector<std::string> NumericTap::fields(std::size_t n) const {
  std::vector<std::string> out;
  for (Column& c : columns(n)) out.push_back(std::move(c.field));
  return out;
}

void NumericTap::read(std::vector<double>& row) {
  Source& s = *source_;
  if (s.codec->sample() == core::FlowStatus::NewData) s.has_data = true;
  if (!s.has_data) {
    row.clear();
    return;
  }
  if (s.type->needs_length) {
    row.resize(s.codec->length());  // every cell is a number
    components::RowWriter writer(row.data(), row.size());
    s.codec->format(writer);
    return;
  }
  components::RowWriter writer(s.cells.data(), s.cells.size());
  s.codec->format(writer);
  row.resize(s.numeric.size());
  for (std::size_t i = 0; i < s.numeric.size(); ++i) row[i] = s.cells[s.numeric[i]];
}

}  // namespace cobra::run
