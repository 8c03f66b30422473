#pragma once
/// @file
/// Connection policies and the status values of port reads and writes.

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace cobra::core {

/// Result of `InputPort::read`: nothing ever arrived, the last value again, or a value not read
/// before.
enum class FlowStatus { NoData, OldData, NewData };

/// Result of `OutputPort::write`. `Dropped` means at least one `buffer(n)` connection was full
/// and that connection kept its older samples (the new one was lost for that reader).
enum class WriteStatus { Written, Dropped, NotConnected };

std::string toString(FlowStatus status);
std::string toString(WriteStatus status);

/// How one connection between an output and an input port stores samples.
/// - `data()`: the reader sees the latest value only (a newer write replaces an unread one).
/// - `buffer(n)`: a FIFO of n samples; when full, new samples are dropped until the reader reads.
/// - `circular(n)`: a FIFO of n samples; when full, the oldest unread sample is overwritten.
/// A policy that names a `transport` carries the connection through it (see transport.hpp);
/// kind and size keep their meaning at each end.
struct ConnPolicy {
  enum class Kind { Data, Buffer, Circular };
  Kind kind = Kind::Data;
  std::size_t size = 1;  ///< number of samples kept; 1 for `data`
  std::string transport;  ///< "" for a connection in this process, else a registered transport ("dds")
  std::string topic;      ///< the transport's name of the connection (DDS: the topic, e.g. "needle/pose")
  /// Transport settings as key and text value, checked by the transport (DDS: its QoS, e.g.
  /// {"reliability", "best_effort"}, {"depth", "8"}, {"lease", "0.1"}).
  std::vector<std::pair<std::string, std::string>> options;

  static ConnPolicy data() { return ConnPolicy{}; }
  /// @throws Error when n is 0.
  static ConnPolicy buffer(std::size_t n);
  /// @throws Error when n is 0.
  static ConnPolicy circular(std::size_t n);

  /// "data", "buffer(8)" or "circular(8)", followed by " over dds topic 'x'" when a transport
  /// carries it.
  std::string describe() const;
  friend bool operator==(const ConnPolicy&, const ConnPolicy&) = default;
};

}  // namespace cobra::core
