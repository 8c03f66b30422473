#include "cobra/task/statements.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace cobra::task {

void Statement::fail(const std::string& message) const { throw std::invalid_argument(where + ": " + message); }

const std::string& Statement::raw(const std::string& key) {
  const auto it = params.find(key);
  if (it == params.end()) fail("'" + words[0] + "' needs " + key + "=");
  used[key] = true;
  return it->second;
}

double Statement::number(const std::string& key, const char* unit) { return parseNumber(key, raw(key), unit); }

double Statement::number(const std::string& key, double fallback, const char* unit) {
  return has(key) ? number(key, unit) : fallback;
}

double Statement::parseNumber(const std::string& key, std::string_view text, const char* unit) const {
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc() || end != text.data() + text.size() || !std::isfinite(value)) {
    fail("value of '" + key + "' is '" + std::string(text) + "', expected a number (" + unit + ")");
  }
  return value;
}

KDL::Vector Statement::vector(const std::string& key, const char* unit) {
  std::string_view text = raw(key);
  double xyz[3];
  for (int i = 0; i < 3; ++i) {
    const std::size_t comma = text.find(',');
    if ((i < 2) != (comma != std::string_view::npos)) fail("value of '" + key + "' must be X,Y,Z (" + unit + ")");
    xyz[i] = parseNumber(key, text.substr(0, comma), unit);
    text = comma == std::string_view::npos ? std::string_view() : text.substr(comma + 1);
  }
  return {xyz[0], xyz[1], xyz[2]};
}

KDL::Frame Statement::frame() {
  const KDL::Vector rpy = has("rpy") ? vector("rpy", "rad") : KDL::Vector::Zero();
  return KDL::Frame(KDL::Rotation::RPY(rpy.x(), rpy.y(), rpy.z()), vector("xyz", "m"));
}

double Statement::positive(const std::string& key, const char* unit) {
  const double value = number(key, unit);
  if (value <= 0.0) fail(key + " = " + raw(key) + ", expected > 0 " + unit);
  return value;
}

void Statement::finish(std::size_t count, const char* usage) const {
  if (words.size() != count) fail("expected '" + std::string(usage) + "'");
  for (const auto& [key, value] : params) {
    if (!used.count(key)) fail("unknown key '" + key + "' in '" + words[0] + "' (expected '" + usage + "')");
  }
}

std::vector<Statement> statements(std::string_view text, std::string_view source) {
  std::vector<Statement> out;
  int line_number = 0;
  std::size_t start = 0;
  while (start <= text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(start, end - start);
    start = end + 1;
    ++line_number;
    if (const std::size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    Statement s;
    s.line = line_number;
    s.where = std::string(source) + ":" + std::to_string(line_number);
    std::size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
      std::size_t j = i;
      while (j < line.size() && line[j] != ' ' && line[j] != '\t' && line[j] != '\r') ++j;
      if (j == i) break;
      const std::string_view word = line.substr(i, j - i);
      const std::size_t eq = word.find('=');
      if (eq == std::string_view::npos) {
        if (!s.params.empty()) s.fail("word '" + std::string(word) + "' after the key=value parameters");
        s.words.emplace_back(word);
      } else {
        const std::string key(word.substr(0, eq));
        if (key.empty() || s.words.empty()) s.fail("'" + std::string(word) + "' is not a statement");
        if (!s.params.emplace(key, std::string(word.substr(eq + 1))).second) s.fail("key '" + key + "' given twice");
      }
      i = j;
    }
    if (!s.words.empty()) out.push_back(std::move(s));
    if (end == text.size()) break;
  }
  return out;
}

std::string printNumber(double value) {
  char buffer[32];
  return std::string(buffer, std::to_chars(buffer, buffer + sizeof buffer, value).ptr);
}

std::string printVector(const KDL::Vector& v) {
  return printNumber(v.x()) + "," + printNumber(v.y()) + "," + printNumber(v.z());
}

std::string printFrame(const KDL::Frame& f) {
  double r = 0, p = 0, y = 0;
  f.M.GetRPY(r, p, y);
  return "xyz=" + printVector(f.p) + " rpy=" + printNumber(r) + "," + printNumber(p) + "," + printNumber(y);
}

std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument(path + ": cannot be read");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace cobra::task
