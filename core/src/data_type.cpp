#include "cobra/core/data_type.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>

#include <cxxabi.h>

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

#include "cobra/core/error.hpp"
#include "cobra/text/trim.hpp"

namespace cobra::core {
namespace {

using text::trim;

/// Removes one leading '+' (from_chars does not take it); false when a sign follows it ("+-1").
bool dropPlus(std::string_view& text) {
  if (text.empty() || text.front() != '+') return true;
  text.remove_prefix(1);
  return text.empty() || (text.front() != '+' && text.front() != '-');
}

bool parseNumber(std::string_view text, double& out) {
  text = trim(text);
  if (text.empty() || !dropPlus(text)) return false;
  double value = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size()) return false;
  out = value;
  return true;
}

/// Parses "[a, b, c]" (brackets optional, commas or spaces between numbers).
bool parseList(std::string_view text, std::vector<double>& out) {
  text = trim(text);
  if (!text.empty() && text.front() == '[') {
    if (text.back() != ']') return false;
    text = trim(text.substr(1, text.size() - 2));
  }
  std::vector<double> values;
  while (!text.empty()) {
    const auto sep = text.find_first_of(", \t");
    double v = 0.0;
    if (!parseNumber(text.substr(0, sep), v)) return false;
    values.push_back(v);
    if (sep == std::string_view::npos) break;
    text = trim(text.substr(sep));
    if (!text.empty() && text.front() == ',') text = trim(text.substr(1));
    else if (text.empty()) break;
  }
  out = std::move(values);
  return true;
}

bool parseFixedList(std::string_view text, std::size_t count, std::vector<double>& out) {
  return parseList(text, out) && out.size() == count;
}

std::string formatNumber(double v) {
  // Shortest text that reads back to the same double. Negative zero prints as 0: it is the same
  // quantity, and a computed value (a quaternion component of a half turn) may come out with
  // either sign, which would make printed text unstable across a parse.
  if (v == 0.0) v = 0.0;
  char buffer[32];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, v);
  return ec == std::errc() ? std::string(buffer, end) : std::string("?");
}

std::string formatList(const double* values, std::size_t count) {
  std::string text = "[";
  for (std::size_t i = 0; i < count; ++i) {
    if (i > 0) text += ", ";
    text += formatNumber(values[i]);
  }
  return text + "]";
}

struct Registry {
  std::mutex mutex;
  std::map<std::string_view, TypeInfo, std::less<>> by_name;
};

Registry& registry() {
  static Registry r;
  return r;
}

void registerBuiltins() {
  static const bool done = [] {
    forEachType(BuiltinDataTypes{}, [](auto type) { typeInfo<typename decltype(type)::type>(); });
    return true;
  }();
  (void)done;
}

}  // namespace

std::string_view toString(DataKind kind) { return kind == DataKind::Pure ? "pure data" : "logic data"; }

namespace {

// "cobra::Colour": the C++ type of `info` as written (demangled), for messages.
std::string cppName(const TypeInfo& info) {
  int status = 0;
  const std::unique_ptr<char, void (*)(void*)> demangled(abi::__cxa_demangle(info.id.name(), nullptr, nullptr, &status),
                                                         std::free);
  return status == 0 && demangled ? std::string(demangled.get()) : std::string(info.id.name());
}

}  // namespace

void TypeRegistry::add(const TypeInfo& info) {
  auto& r = registry();
  std::lock_guard lock(r.mutex);
  const auto [it, added] = r.by_name.emplace(info.name, info);
  // The same type again is no conflict: each shared library (a package) instantiating typeInfo<T>
  // registers T once more. Another type under the name would make every port of the name ambiguous
  // (a deployment file, the studio and a recording name types by it), so it is refused, as the
  // Lua and CSV registries refuse one (types/).
  if (!added && it->second.id != info.id)
    throw Error("data type '" + std::string(info.name) + "' is registered twice, by C++ types " + cppName(it->second) +
                " and " + cppName(info) + "; give one of them another DataTypeTraits<T>::name");
}

const TypeInfo* TypeRegistry::find(std::string_view name) {
  registerBuiltins();
  auto& r = registry();
  std::lock_guard lock(r.mutex);
  const auto it = r.by_name.find(name);
  return it == r.by_name.end() ? nullptr : &it->second;
}

std::vector<const TypeInfo*> TypeRegistry::all() {
  registerBuiltins();
  auto& r = registry();
  std::lock_guard lock(r.mutex);
  std::vector<const TypeInfo*> out;
  for (const auto& [name, info] : r.by_name) out.push_back(&info);
  return out;
}

std::string DataTypeTraits<double>::print(const double& value) { return formatNumber(value); }
bool DataTypeTraits<double>::parse(std::string_view text, double& out) { return parseNumber(text, out); }

std::string DataTypeTraits<int>::print(const int& value) { return std::to_string(value); }
bool DataTypeTraits<int>::parse(std::string_view text, int& out) {
  text = trim(text);
  if (!dropPlus(text)) return false;
  int value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size()) return false;
  out = value;
  return true;
}

std::string DataTypeTraits<bool>::print(const bool& value) { return value ? "true" : "false"; }
bool DataTypeTraits<bool>::parse(std::string_view text, bool& out) {
  text = trim(text);
  if (text == "true") out = true;
  else if (text == "false") out = false;
  else return false;
  return true;
}

std::string DataTypeTraits<std::string>::print(const std::string& value) { return value; }
bool DataTypeTraits<std::string>::parse(std::string_view text, std::string& out) {
  out = std::string(text);
  return true;
}

std::string DataTypeTraits<std::vector<double>>::print(const std::vector<double>& value) {
  return formatList(value.data(), value.size());
}
bool DataTypeTraits<std::vector<double>>::parse(std::string_view text, std::vector<double>& out) {
  return parseList(text, out);
}

std::string DataTypeTraits<KDL::Vector>::print(const KDL::Vector& value) { return formatList(value.data, 3); }
bool DataTypeTraits<KDL::Vector>::parse(std::string_view text, KDL::Vector& out) {
  std::vector<double> v;
  if (!parseFixedList(text, 3, v)) return false;
  out = KDL::Vector(v[0], v[1], v[2]);
  return true;
}

namespace {
bool quaternionFrom(const double* q, KDL::Rotation& out) {
  const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (std::abs(norm - 1.0) > 1e-6) return false;  // a quaternion that is not unit is a typo
  // Rounded decimals are unit only to ~1e-6: normalised, the rotation matrix is orthonormal.
  out = KDL::Rotation::Quaternion(q[0] / norm, q[1] / norm, q[2] / norm, q[3] / norm);
  return true;
}
std::vector<double> quaternionOf(const KDL::Rotation& r) {
  std::vector<double> q(4);
  r.GetQuaternion(q[0], q[1], q[2], q[3]);
  return q;
}
}  // namespace

std::string DataTypeTraits<KDL::Rotation>::print(const KDL::Rotation& value) {
  const auto q = quaternionOf(value);
  return formatList(q.data(), 4);
}
bool DataTypeTraits<KDL::Rotation>::parse(std::string_view text, KDL::Rotation& out) {
  std::vector<double> v;
  return parseFixedList(text, 4, v) && quaternionFrom(v.data(), out);
}

std::string DataTypeTraits<KDL::Frame>::print(const KDL::Frame& value) {
  auto all = std::vector<double>{value.p.x(), value.p.y(), value.p.z()};
  const auto q = quaternionOf(value.M);
  all.insert(all.end(), q.begin(), q.end());
  return formatList(all.data(), all.size());
}
bool DataTypeTraits<KDL::Frame>::parse(std::string_view text, KDL::Frame& out) {
  std::vector<double> v;
  KDL::Rotation r;
  if (!parseFixedList(text, 7, v) || !quaternionFrom(v.data() + 3, r)) return false;
  out = KDL::Frame(r, KDL::Vector(v[0], v[1], v[2]));
  return true;
}

std::string DataTypeTraits<KDL::Twist>::print(const KDL::Twist& value) {
  const double v[6] = {value.vel.x(), value.vel.y(), value.vel.z(), value.rot.x(), value.rot.y(), value.rot.z()};
  return formatList(v, 6);
}
bool DataTypeTraits<KDL::Twist>::parse(std::string_view text, KDL::Twist& out) {
  std::vector<double> v;
  if (!parseFixedList(text, 6, v)) return false;
  out = KDL::Twist(KDL::Vector(v[0], v[1], v[2]), KDL::Vector(v[3], v[4], v[5]));
  return true;
}

std::string DataTypeTraits<KDL::Wrench>::print(const KDL::Wrench& value) {
  const double v[6] = {value.force.x(), value.force.y(), value.force.z(),
                       value.torque.x(), value.torque.y(), value.torque.z()};
  return formatList(v, 6);
}
bool DataTypeTraits<KDL::Wrench>::parse(std::string_view text, KDL::Wrench& out) {
  std::vector<double> v;
  if (!parseFixedList(text, 6, v)) return false;
  out = KDL::Wrench(KDL::Vector(v[0], v[1], v[2]), KDL::Vector(v[3], v[4], v[5]));
  return true;
}

std::string DataTypeTraits<KDL::JntArray>::print(const KDL::JntArray& value) {
  return formatList(value.data.data(), value.rows());
}
bool DataTypeTraits<KDL::JntArray>::parse(std::string_view text, KDL::JntArray& out) {
  std::vector<double> v;
  if (!parseList(text, v)) return false;
  out.resize(static_cast<unsigned>(v.size()));
  std::copy(v.begin(), v.end(), out.data.data());
  return true;
}

std::string DataTypeTraits<TaskState>::print(const TaskState& value) { return value.path.str(); }
bool DataTypeTraits<TaskState>::parse(std::string_view text, TaskState& out) {
  text = trim(text);
  if (text.empty() || text.size() > decltype(out.path)::capacity() || text.find_first_of(" \t") != std::string_view::npos)
    return false;
  out.path = text;
  return true;
}

std::string DataTypeTraits<Event>::print(const Event& value) {
  std::string text = value.name.str();
  if (!value.source.empty()) text += " from " + value.source.str();
  return text + " at " + formatNumber(std::chrono::duration<double>(value.stamp).count()) + " s";
}
bool DataTypeTraits<Event>::parse(std::string_view text, Event& out) {
  // A bare name ("e_done"), or everything print writes: "e_done from Planner at 1.5 s".
  std::vector<std::string_view> words;
  for (text = trim(text); !text.empty(); text = trim(text.substr(std::min(text.size(), text.find_first_of(" \t")))))
    words.push_back(text.substr(0, text.find_first_of(" \t")));
  constexpr std::size_t capacity = decltype(out.name)::capacity();
  if (words.empty() || words[0].size() > capacity) return false;
  Event event{words[0], {}, std::chrono::nanoseconds(0)};
  std::size_t i = 1;
  if (i < words.size() && words[i] == "from") {
    if (i + 1 >= words.size() || words[i + 1].size() > capacity) return false;
    event.source = words[i + 1];
    i += 2;
  }
  if (i < words.size() && words[i] == "at") {
    double seconds = 0.0;
    // |stamp| below 9e18 ns (285 years) fits the nanosecond count.
    if (i + 2 >= words.size() || words[i + 2] != "s" || !parseNumber(words[i + 1], seconds) ||
        !(std::abs(seconds) < 9e9))
      return false;
    event.stamp = std::chrono::nanoseconds(std::llround(seconds * 1e9));
    i += 3;
  }
  if (i != words.size()) return false;
  out = event;
  return true;
}

}  // namespace cobra::core
