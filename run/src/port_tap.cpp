#include "cobra/run/port_tap.hpp"

#include <algorithm>
#include <stdexcept>

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

#include "cobra/deploy/suggest.hpp"

namespace cobra::run {
namespace {

void toRow(const double& v, std::vector<double>& row) { row.assign(1, v); }
void toRow(const std::vector<double>& v, std::vector<double>& row) { row = v; }
void toRow(const KDL::JntArray& v, std::vector<double>& row) { row.assign(v.data.data(), v.data.data() + v.rows()); }
void toRow(const KDL::Frame& f, std::vector<double>& row) {
  double x = 0, y = 0, z = 0, w = 0;
  f.M.GetQuaternion(x, y, z, w);
  row = {f.p.x(), f.p.y(), f.p.z(), x, y, z, w};
}
void toRow(const KDL::Twist& t, std::vector<double>& row) {
  row = {t.vel.x(), t.vel.y(), t.vel.z(), t.rot.x(), t.rot.y(), t.rot.z()};
}
void toRow(const KDL::Wrench& w, std::vector<double>& row) {
  row = {w.force.x(), w.force.y(), w.force.z(), w.torque.x(), w.torque.y(), w.torque.z()};
}

}  // namespace

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

struct NumericTap::Source {
  virtual ~Source() = default;
  virtual void read(std::vector<double>& row) = 0;
  virtual bool pose() const { return false; }
  virtual const char* kind() const = 0;
};

namespace {

template <class T>
struct TypedSource final : NumericTap::Source {
  explicit TypedSource(std::unique_ptr<core::InputPortBase> reader) : reader_(std::move(reader)) {
    typed_ = dynamic_cast<core::InputPort<T>*>(reader_.get());
  }
  void read(std::vector<double>& row) override {
    if (typed_->read(value_) == core::FlowStatus::NoData) {
      row.clear();
      return;
    }
    toRow(value_, row);
  }
  const char* kind() const override {
    if constexpr (std::is_same_v<T, KDL::Frame>) return "frame";
    if constexpr (std::is_same_v<T, KDL::Twist>) return "twist";
    if constexpr (std::is_same_v<T, KDL::Wrench>) return "wrench";
    if constexpr (std::is_same_v<T, double>) return "double";
    return "array";
  }
  std::unique_ptr<core::InputPortBase> reader_;
  core::InputPort<T>* typed_ = nullptr;
  T value_{};
};

template <class T>
std::unique_ptr<NumericTap::Source> tryType(core::OutputPortBase& out, const std::string& path) {
  auto reader = out.makeReader(readerName(path), "cobra run recorder");
  if (dynamic_cast<core::InputPort<T>*>(reader.get()) == nullptr) return nullptr;
  out.connectTo(*reader, core::ConnPolicy::data());
  return std::make_unique<TypedSource<T>>(std::move(reader));
}

}  // namespace

NumericTap::NumericTap(const core::ComponentRegistry& registry, const std::string& path, const std::string& where,
                       const std::string& use)
    : path_(path) {
  core::OutputPortBase& out = findOutput(registry, path, where, use);
  unit_ = out.unit();
  source_ = tryType<double>(out, path);
  if (!source_) source_ = tryType<std::vector<double>>(out, path);
  if (!source_) source_ = tryType<KDL::Frame>(out, path);
  if (!source_) source_ = tryType<KDL::Twist>(out, path);
  if (!source_) source_ = tryType<KDL::Wrench>(out, path);
  if (!source_) source_ = tryType<KDL::JntArray>(out, path);
  if (!source_)
    throw std::runtime_error(where + ": " + use + ": port " + path + " is a " + std::string(out.type().name) +
                             "; accepted: " + kAccepted);
}

NumericTap::~NumericTap() = default;

std::vector<std::string> NumericTap::fields(std::size_t n) const {
  const std::string kind = source_->kind();
  if (kind == "double") return {""};
  if (kind == "frame") return {"x", "y", "z", "qx", "qy", "qz", "qw"};
  if (kind == "twist") return {"vx", "vy", "vz", "wx", "wy", "wz"};
  if (kind == "wrench") return {"fx", "fy", "fz", "tx", "ty", "tz"};
  std::vector<std::string> out;
  for (std::size_t i = 0; i < n; ++i) out.push_back("[" + std::to_string(i) + "]");
  return out;
}

void NumericTap::read(std::vector<double>& row) { source_->read(row); }

}  // namespace cobra::run
