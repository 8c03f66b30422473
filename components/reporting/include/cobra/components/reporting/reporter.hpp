#pragma once
/// @file
/// Reporter: a Bridge component that records output ports of other components to a CSV file
/// (in the spirit of OCL::FileReporting), without ever making a real-time writer wait.

#include <cstddef>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "cobra/components/reporting/csv_codec.hpp"
#include "cobra/core/component.hpp"
#include "cobra/core/introspection.hpp"

namespace cobra::components {

namespace reporting_detail {
class Source;
class RowQueue;
class FileWriter;
}  // namespace reporting_detail

/// Samples chosen output ports at its own activity's period and writes one CSV row per update.
///
/// **Choosing ports.** `reportPort` (or `reportComponent`) is called while the Reporter is
/// PreOperational. Each reported output gets a reader input port of its type, owned by the
/// Reporter (listed in its interface as `Comp:port`), connected with a `data` policy: the writer
/// only ever overwrites the latest value in a lock-free channel, so it never waits for the
/// Reporter, and the Reporter sees the latest value at each of its updates (values written
/// between two updates are not recorded).
///
/// **Sampling.** There is no decimation property: the Reporter samples at its activity's period.
/// Give it a `PeriodicActivity` (a low priority is fine) or put it on the `LockstepClock`. On the
/// lockstep clock, add it after the components it reports, so that a row holds the values written
/// in the same instant.
///
/// **CSV format.** The first line is the header: `time [s]` and then one column per scalar,
/// named `Comp.port [unit]`. Values with several elements are flattened into one column each:
/// - `vector<double>`, `KDL.JntArray`: `Comp.q[0] [unit]`, `Comp.q[1] [unit]`, … (the number of
///   elements is not part of these types, so it is given to `reportPort`; shorter samples leave
///   the remaining cells empty, longer ones are cut);
/// - `KDL.Vector`: `.x .y .z` in the port's unit;
/// - `KDL.Rotation`: unit quaternion `.qx .qy .qz .qw` [1];
/// - `KDL.Frame`: `.x .y .z` [m], then `.qx .qy .qz .qw` [1];
/// - `KDL.Twist`: `.vx .vy .vz` [m/s], `.wx .wy .wz` [rad/s];
/// - `KDL.Wrench`: `.fx .fy .fz` [N], `.tx .ty .tz` [N·m];
/// - a record (core/record.hpp): the columns of each field, `Comp.port.<field>[<sub>]` with the
///   field's unit (`P.reading.depth [m]`, `P.reading.pose.x [m]`, ...);
/// - `bool` is written 1 or 0; `string` as text; `Event` as the event's name; `TaskState` as its
///   path; any other registered type as its text form (text cells are CSV-quoted when needed and
///   cut after `kMaxTextChars` characters).
/// The columns of a type are its `CsvCodec<T>` (csv_codec.hpp); a package's type gets them with
/// `cobra::types::registerType<T>()`.
/// `[unit]` is left out when the unit is empty (logic data). Numbers are written in the shortest
/// form that reads back to the same double; time is the Reporter's `now()` in s, exact to the ns
/// (simulated time on the lockstep clock, so runs are reproducible).
///
/// **Rows.** An update writes a row only when at least one reported port had NewData; the other
/// ports repeat their last value, or leave their cells empty when nothing ever arrived.
///
/// **Non-blocking file I/O.** The update formats the row into a preallocated bounded queue of
/// `queue_rows` rows; a writer thread (SCHED_OTHER, nice 10; started by start, joined by stop)
/// copies rows to the file. When the queue is full the row is dropped and counted in
/// `rows_dropped`: the update never waits for the disk. For the types with a CSV codec (the
/// built-in types, records), with vectors of the declared length, the update allocates nothing, takes no lock and does no I/O; at most it
/// wakes the writer thread (one futex syscall) when the queue is half full. On the lockstep clock
/// a simulation can outrun the disk: give `queue_rows` room for the rows of a burst.
///
/// **Properties.** `file_path` (text; default `<name>.csv` in the working directory; read at
/// configure), `queue_rows` (rows, 1..1e6, default 4096; read at configure), `flush_period` (s,
/// 0..3600, default 1; read at start), `rows_dropped` (rows, read-only; reset at configure).
///
/// **Lifecycle.** configure opens (truncates) `file_path`, writes the header and allocates the
/// queue; a file that cannot be opened fails configure with the path and the system's reason.
/// start starts the writer thread; stop drains the queue into the file, flushes and joins it (so
/// after stop the file is complete); a later start appends to the same file; cleanup closes it.
class Reporter : public core::Component {
 public:
  /// Longest text cell, in characters, before it is cut (keeps rows of bounded size).
  static constexpr std::size_t kMaxTextChars = RowWriter::kMaxTextChars;

  explicit Reporter(std::string name);
  /// Stops the Reporter first when it is Running, so the writer thread is joined and the file
  /// complete before the readers go away.
  ~Reporter() override;

  /// Records `output` from the next configure on.
  /// @param elements number of columns of a `vector<double>` or `KDL.JntArray` port (required
  ///        for those types, whose length is not part of the type); 0 for every other type.
  /// @throws core::Error naming the port and what to do when `output` is not an output port, is
  ///         already reported, `elements` does not fit its type, the Reporter is not
  ///         PreOperational, or the connection is refused.
  void reportPort(core::PortBase& output, std::size_t elements = 0);
  /// Same, with the port given as "Component.port" and looked up in `registry`.
  /// @throws core::Error when the path is malformed or names no component or port.
  void reportPort(const core::ComponentRegistry& registry, std::string_view path, std::size_t elements = 0);
  /// Records every output port of `component` not reported yet, in declaration order; its
  /// `events` port only when `include_events`. Report its `vector<double>`/`KDL.JntArray` ports
  /// first with `reportPort(port, n)`: they need a length, and are refused here otherwise.
  /// `left_out` given: such ports are left out instead, named there ("Comp.port (type)", comma
  /// separated), as a component's peers are recorded wholesale (PeerReporter).
  /// @throws core::Error (before reporting anything) when a port needs a length (without
  ///         `left_out`), or when nothing is left to report.
  void reportComponent(core::Component& component, bool include_events = false, std::string* left_out = nullptr);

  /// The CSV header cells, in file order: "time [s]", then one per column.
  std::vector<std::string> columns() const;
  /// The reported ports ("Comp.port"), in column order.
  std::vector<std::string> reportedPorts() const;

 protected:
  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;
  void stopHook() override;
  void cleanupHook() override;

 private:
  [[noreturn]] void refuse(const core::PortBase& output, const std::string& why) const;
  std::string where() const;
  /// Why ports cannot be reported now, and what to do.
  std::string notPreOperational() const;

  core::Property<std::string> file_path_;
  core::Property<int> queue_rows_{"queue_rows", 4096, "1",
                                  "rows buffered between the update and the file writer thread (preallocated at "
                                  "configure); a full queue drops rows"};
  core::Property<double> flush_period_{"flush_period", 1.0, "s",
                                       "longest time a written row may wait in the file buffer before it is "
                                       "flushed to the file; 0 flushes after every batch (read at start)"};
  core::Property<int> rows_dropped_{"rows_dropped", 0, "1",
                                    "rows lost because the queue was full (the disk was slower than the "
                                    "updates); reset at configure"};

  std::vector<std::unique_ptr<reporting_detail::Source>> sources_;
  std::unique_ptr<reporting_detail::RowQueue> queue_;
  std::unique_ptr<reporting_detail::FileWriter> writer_;
};

}  // namespace cobra::components
