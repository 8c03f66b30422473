#pragma once
/// @file
/// Reading components' output ports by name, for the runner's observers and a RunObserver
/// (cobra studio): read between two instants of the clock, from the run's thread.

#include <memory>
#include <string>
#include <vector>

#include "cobra/core/component.hpp"
#include "cobra/core/introspection.hpp"
#include "cobra/core/port.hpp"

namespace cobra::run {

// The output port `path` ("Comp.port") of `registry`.
// @throws std::runtime_error "WHERE: USE: unknown component 'X'; did you mean ...", an unknown
//         port (listing the component's output ports) or an input port.
// A name for the runner's reader of port `path` ("Comp.port" -> "Comp_port": port names hold no '.').
std::string readerName(const std::string& path);

core::OutputPortBase& findOutput(const core::ComponentRegistry& registry, const std::string& path,
                                 const std::string& where, const std::string& use);

// A private connection to one output port, typed: a data connection (the newest value), or with
// `policy` a buffer whose every sample readNew gives in turn.
template <class T>
class Tap {
 public:
  // @throws std::runtime_error naming `where`, the port, its type and the type expected.
  Tap(const core::ComponentRegistry& registry, const std::string& path, const std::string& where, const std::string& use,
      const char* expected, core::ConnPolicy policy = core::ConnPolicy::data()) {
    core::OutputPortBase& out = findOutput(registry, path, where, use);
    reader_ = out.makeReader(readerName(path), "cobra run observer");
    typed_ = dynamic_cast<core::InputPort<T>*>(reader_.get());
    if (typed_ == nullptr)
      throw std::runtime_error(where + ": " + use + ": port " + path + " is a " + std::string(out.type().name) +
                               "; expected " + expected);
    out.connectTo(*reader_, policy);
  }
  // The newest value; false when the port never had data.
  bool read(T& value) { return typed_->read(value) != core::FlowStatus::NoData; }
  // True when a value was written since the last call (then copied into `value`).
  bool readNew(T& value) { return typed_->readNew(value) == core::FlowStatus::NewData; }

 private:
  std::unique_ptr<core::InputPortBase> reader_;
  core::InputPort<T>* typed_ = nullptr;
};

// One output port of a numeric type read as a row of numbers: double (1), vector<double> and
// KDL.JntArray (n: [0], [1], ...), KDL.Frame (x y z qx qy qz qw), KDL.Twist (vx vy vz wx wy wz),
// KDL.Wrench (fx fy fz tx ty tz).
class NumericTap {
 public:
  // What `record` and `plots` accept, for messages.
  static constexpr const char* kAccepted = "double, vector<double>, KDL.Frame, KDL.Twist, KDL.Wrench or KDL.JntArray";

  // @throws std::runtime_error "WHERE: USE: port Comp.port is a T; accepted: ..." for another
  //         type, or as findOutput.
  NumericTap(const core::ComponentRegistry& registry, const std::string& path, const std::string& where,
             const std::string& use);
  ~NumericTap();

  const std::string& path() const { return path_; }
  const std::string& unit() const { return unit_; }
  // The field names of a row of `n` values ("" for a double: the column is the port itself).
  std::vector<std::string> fields(std::size_t n) const;
  // The newest value as numbers (empty before any data).
  void read(std::vector<double>& row);

  struct Source;

 private:
  std::string path_;
  std::string unit_;
  std::unique_ptr<Source> source_;
};

}  // namespace cobra::run
