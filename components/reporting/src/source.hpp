#pragma once
// Internal to the Reporter: one reported port (its reader, the value last read and how that
// value becomes CSV cells), and the bounded row formatter the update writes into.

#include <chrono>
#include <cstddef>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "cobra/core/port.hpp"

namespace cobra::components::reporting_detail {

/// Appends CSV text to a fixed buffer. Never allocates; text that does not fit is cut (callers
/// size the buffer with `Source::maxBytes`, so that only happens on a sizing bug).
class RowWriter {
 public:
  RowWriter(char* buffer, std::size_t capacity) : buffer_(buffer), capacity_(capacity) {}

  /// Seconds with up to 9 decimals, exact: 1500000 ns -> "0.0015".
  void time(std::chrono::nanoseconds t) noexcept;
  /// ",value" in the shortest form that reads back to the same double.
  void number(double value) noexcept;
  /// "," followed by nothing: a cell without a value.
  void empty() noexcept { put(','); }
  /// ",text", CSV-quoted when it holds a comma, quote or line break, cut after `max_chars`.
  void text(std::string_view text, std::size_t max_chars) noexcept;
  void endLine() noexcept { put('\n'); }
  std::size_t size() const { return size_; }

  /// Most bytes `time` writes; most bytes `number` writes (with its comma).
  static constexpr std::size_t kMaxTimeBytes = 32;
  static constexpr std::size_t kMaxNumberBytes = 26;
  /// Most bytes `text` writes for `max_chars` characters (every one a doubled quote).
  static constexpr std::size_t maxTextBytes(std::size_t max_chars) { return 2 * max_chars + 3; }

 private:
  void put(char c) noexcept {
    if (size_ < capacity_) buffer_[size_++] = c;
  }
  void put(std::string_view text) noexcept {
    for (char c : text) put(c);
  }

  char* buffer_;
  std::size_t capacity_;
  std::size_t size_ = 0;
};

/// Quotes a CSV cell when it holds a comma, a quote or a line break (for the header).
std::string csvCell(std::string_view text);

/// One reported port: a reader of its type, the value last read, and its columns.
class Source {
 public:
  virtual ~Source() = default;
  Source(const Source&) = delete;
  Source& operator=(const Source&) = delete;

  /// "Comp.port" of the reported output.
  const std::string& path() const { return path_; }
  const core::OutputPortBase& output() const { return *output_; }
  /// Header cells, "Comp.port.x [m]", one per column.
  const std::vector<std::string>& headers() const { return headers_; }
  /// The reader input port (connected to the output by `connect`).
  core::InputPortBase& reader() const { return *reader_; }

  /// Reads the port, keeping the value. Real-time safe for the built-in types.
  virtual core::FlowStatus sample() = 0;
  /// Appends one cell per header (each preceded by a comma); empty cells before any data.
  virtual void format(RowWriter& row) const noexcept = 0;
  /// Most bytes `format` appends.
  virtual std::size_t maxBytes() const = 0;

 protected:
  Source(core::OutputPortBase& output, std::unique_ptr<core::InputPortBase> reader, std::vector<std::string> headers);

  bool has_value_ = false;  // a value was read at least once

 private:
  std::string path_;
  core::OutputPortBase* output_;
  std::unique_ptr<core::InputPortBase> reader_;
  std::vector<std::string> headers_;
};

/// True for the types whose number of columns `reportPort` must be told (vector<double>, JntArray).
bool needsLength(const core::TypeInfo& type);

/// A Source reading `output` through a new reader port called `reader_name` (not yet connected).
/// @param elements the number of columns for the types of `needsLength`, otherwise 0.
/// @throws core::Error (message without the Reporter's name) when `elements` does not fit the type.
std::unique_ptr<Source> makeSource(core::OutputPortBase& output, std::string reader_name, std::size_t elements);

}  // namespace cobra::components::reporting_detail
