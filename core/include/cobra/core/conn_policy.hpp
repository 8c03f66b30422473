#pragma once
/// @file
/// Connection policies and the status values of port reads and writes.

#include <cstddef>
#include <string>

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
struct ConnPolicy {
  enum class Kind { Data, Buffer, Circular };
  Kind kind = Kind::Data;
  std::size_t size = 1;  ///< number of samples kept; 1 for `data`

  static ConnPolicy data() { return {Kind::Data, 1}; }
  /// @throws Error when n is 0.
  static ConnPolicy buffer(std::size_t n);
  /// @throws Error when n is 0.
  static ConnPolicy circular(std::size_t n);

  /// "data", "buffer(8)" or "circular(8)".
  std::string describe() const;
  friend bool operator==(const ConnPolicy&, const ConnPolicy&) = default;
};

}  // namespace cobra::core
