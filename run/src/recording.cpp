// The run's recorded columns (cobra/run/recording.hpp) and the small text helpers of the runner.
#include "cobra/run/recording.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "builtin_observers.hpp"

namespace cobra::run {

bool startsWith(const std::string& text, const std::string& prefix) { return text.rfind(prefix, 0) == 0; }

std::string seconds(double t) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%8.3f s", t);
  return buffer;
}

void Recording::addPort(const core::ComponentRegistry& registry, const std::string& path, const std::string& where,
                        const std::string& use) {
  for (const Port& p : ports_)
    if (p.tap->path() == path) return;
  ports_.push_back({std::make_unique<NumericTap>(registry, path, where, use), {}, 0});
}

std::size_t Recording::addDerived(const std::string& name, const std::string& unit) {
  derived_.emplace_back(name, unit);
  derived_now_.push_back(std::numeric_limits<double>::quiet_NaN());
  return derived_.size() - 1;
}

void Recording::sample(double t) {
  times_.push_back(t);
  for (Port& p : ports_) {
    p.tap->read(scratch_);
    p.width = std::max(p.width, scratch_.size());
    p.rows.push_back(scratch_);
  }
  derived_rows_.push_back(derived_now_);
  std::fill(derived_now_.begin(), derived_now_.end(), std::numeric_limits<double>::quiet_NaN());
}

std::vector<std::string> Recording::columnNames() const {
  std::vector<std::string> names;
  for (const Port& p : ports_)
    for (NumericTap::Column& c : p.tap->columns(p.width)) names.push_back(std::move(c.name));
  for (const auto& [name, unit] : derived_) names.push_back(name);
  return names;
}

bool Recording::knows(const std::string& name, std::vector<std::string>& fields) const {
  fields.clear();
  for (const auto& [derived, unit] : derived_)
    if (derived == name) return true;
  for (const Port& p : ports_) {
    const std::string& path = p.tap->path();
    if (name.rfind(path, 0) != 0) continue;
    const std::string rest = name.substr(path.size());
    const std::vector<std::string> known = p.tap->fields(0);
    if (rest.empty()) {
      if (known.size() == 1 && known[0].empty()) return true;
      fields = known.empty() ? std::vector<std::string>{"[0]", "[1]", "..."} : known;
      return false;
    }
    if (rest[0] == '[') return known.empty() && rest.back() == ']';
    if (rest[0] == '.') return std::find(known.begin(), known.end(), rest.substr(1)) != known.end();
  }
  return false;
}

std::string Recording::unitOf(const std::string& name) const {
  for (const auto& [derived, unit] : derived_)
    if (derived == name) return unit;
  for (const Port& p : ports_)
    for (const NumericTap::Column& c : p.tap->columns(p.width))
      if (c.name == name) return c.unit;
  return "";
}

bool Recording::column(const std::string& name, std::vector<double>& x, std::vector<double>& y) const {
  x.clear();
  y.clear();
  for (std::size_t d = 0; d < derived_.size(); ++d) {
    if (derived_[d].first != name) continue;
    for (std::size_t i = 0; i < times_.size(); ++i)
      if (std::isfinite(derived_rows_[i][d])) x.push_back(times_[i]), y.push_back(derived_rows_[i][d]);
    return true;
  }
  for (const Port& p : ports_) {
    const std::vector<NumericTap::Column> columns = p.tap->columns(p.width);
    for (std::size_t f = 0; f < columns.size(); ++f) {
      if (columns[f].name != name) continue;
      for (std::size_t i = 0; i < times_.size(); ++i)
        if (f < p.rows[i].size() && std::isfinite(p.rows[i][f])) x.push_back(times_[i]), y.push_back(p.rows[i][f]);
      return true;
    }
  }
  return false;
}

std::string Recording::csv() const {
  std::string out = "time [s]";
  auto header = [&](const std::string& name, const std::string& unit) {
    const std::string cell = name + (unit.empty() ? "" : " [" + unit + "]");  // a unit may hold a comma: "N, N·m"
    const bool quote = cell.find(',') != std::string::npos;
    out += "," + std::string(quote ? "\"" : "") + cell + (quote ? "\"" : "");
  };
  for (const std::string& name : columnNames()) header(name, unitOf(name));
  out += "\n";
  char number[32];
  auto put = [&](double v) {
    if (std::isfinite(v)) {
      std::snprintf(number, sizeof number, ",%.6g", v);
      out += number;
    } else {
      out += ",";
    }
  };
  for (std::size_t i = 0; i < times_.size(); ++i) {
    std::snprintf(number, sizeof number, "%.3f", times_[i]);
    out += number;
    for (const Port& p : ports_) {
      const std::size_t width = std::max<std::size_t>(p.width, 1);
      for (std::size_t f = 0; f < width; ++f) put(f < p.rows[i].size() ? p.rows[i][f] : std::nan(""));
    }
    for (const double v : derived_rows_[i]) put(v);
    out += "\n";
  }
  return out;
}

}  // namespace cobra::run
