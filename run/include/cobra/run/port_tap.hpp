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

// One output port read as a row of numbers, in the columns of its type's CSV codec
// (components/reporting/csv_codec.hpp): every type registered for CSV (cobra's own, a package's
// record through cobra::types::registerType<T>()) whose codec gives numeric columns. A double is
// one column named by the port; a KDL.Frame x y z qx qy qz qw; a record its fields (`force`,
// `tip.x`, ...); vector<double> and KDL.JntArray [0], [1], ..., as many as the value read has.
// A type's text columns (a string, an event, a record's variable-length field) are left out.
class NumericTap {
 public:
  /// One column: its field ("" for a port that is one number, "x", "[2]", "pose.qx"), its full
  /// name ("Comp.port.x", "Comp.port[2]") and its unit, as the CSV codec gives them (a codec that
  /// has no unit of its own for a column gives the port's).
  struct Column {
    std::string field, name, unit;
  };

  // @throws std::runtime_error "WHERE: USE: port Comp.port is a T, which has no CSV codec ...;
  //         types with numeric columns: ..." (or "... whose CSV columns are text"), or as findOutput.
  NumericTap(const core::ComponentRegistry& registry, const std::string& path, const std::string& where,
             const std::string& use);
  ~NumericTap();

  const std::string& path() const { return path_; }
  // The columns of a row of `n` values (`n` is used only by a type whose length is not part of
  // it, which has no columns for n = 0).
  std::vector<Column> columns(std::size_t n) const;
  // The fields of columns(n), in order.
  std::vector<std::string> fields(std::size_t n) const;
  // The newest value as numbers (empty before any data). No allocation after the first value
  // (of a variable-length type: after the first of each longer length).
  void read(std::vector<double>& row);

  struct Source;

 private:
  std::string path_;
  std::unique_ptr<Source> source_;
};

}  // namespace cobra::run
