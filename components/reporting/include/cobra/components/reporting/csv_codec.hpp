#pragma once
/// @file
/// How a value becomes CSV cells: `CsvCodec<T>`, found at compile time, and the registry of the
/// reported types that `registerCsvType<T>()` fills.
///
/// A codec names the columns of a port of its type and writes one value into a row:
/// @code
/// template <> struct cobra::components::CsvCodec<MyType> {
///   static constexpr bool kNeedsLength = false;  // true: the column count is given to reportPort
///   /// Appends the columns of a port whose unit is `unit` (`elements`: reportPort's count, or 0).
///   static void columns(std::string_view unit, std::size_t elements, std::vector<CsvColumn>& out);
///   /// Writes exactly as many cells as `columns` gave. Real-time: allocates nothing, throws nothing.
///   static void write(RowWriter& row, const MyType& value, std::size_t elements) noexcept;
///   // Optional: the value a port's reader starts with (sized for `elements`, so reading into
///   // it allocates nothing); T{} otherwise.
///   static MyType initial(std::size_t elements);
///   // Optional, for kNeedsLength: a value's number of elements; value.size() or .rows() otherwise.
///   static std::size_t length(const MyType& value) noexcept;
/// };
/// @endcode
/// cobra's own types have leaf codecs below (columns as Reporter's documentation lists them);
/// every record (core/record.hpp) has one derived from its fields: the columns
/// `<port>.<field>[<sub>]`, each with its field's unit, each written by the field type's codec.
/// `TextCsvCodec<T>` is the one-column text form of any registered type, for a type whose values
/// have no fixed number of columns (it allocates per row: not for real-time writers).

#include <chrono>
#include <cstddef>
#include <memory>
#include <string>
#include <string_view>
#include <type_traits>
#include <typeindex>
#include <vector>

#include "cobra/core/data_type.hpp"
#include "cobra/core/port.hpp"
#include "cobra/core/record.hpp"

namespace cobra::components {

/// Appends CSV text to a fixed buffer. Never allocates; text that does not fit is cut (callers
/// size the buffer with the columns' `maxBytes`, so that only happens on a sizing bug).
///
/// Made on an array of doubles instead, it keeps one number per cell (NaN for an empty or text
/// cell), in column order: the numeric view of the same codecs, for a plot of a port's series.
class RowWriter {
 public:
  RowWriter(char* buffer, std::size_t capacity) : buffer_(buffer), capacity_(capacity) {}
  /// The numeric view: cell i goes to values[i] (cells past `count` are dropped).
  RowWriter(double* values, std::size_t count) : values_(values), capacity_(count) {}

  /// Seconds with up to 9 decimals, exact: 1500000 ns -> "0.0015".
  void time(std::chrono::nanoseconds t) noexcept;
  /// ",value" in the shortest form that reads back to the same double.
  void number(double value) noexcept;
  /// "," followed by nothing: a cell without a value.
  void empty() noexcept {
    if (values_ != nullptr) putValue(kNaN);
    else put(',');
  }
  /// ",text", CSV-quoted when it holds a comma, quote or line break, cut after `max_chars`.
  void text(std::string_view text, std::size_t max_chars = kMaxTextChars) noexcept;
  void endLine() noexcept {
    if (values_ == nullptr) put('\n');
  }
  /// Bytes written, or cells in the numeric view.
  std::size_t size() const { return size_; }

  /// Longest text cell, in characters, before it is cut (keeps rows of bounded size).
  static constexpr std::size_t kMaxTextChars = 127;
  /// Most bytes `time` writes; most bytes `number` writes (with its comma).
  static constexpr std::size_t kMaxTimeBytes = 32;
  static constexpr std::size_t kMaxNumberBytes = 26;
  /// Most bytes `text` writes for `max_chars` characters (every one a doubled quote).
  static constexpr std::size_t maxTextBytes(std::size_t max_chars = kMaxTextChars) { return 2 * max_chars + 3; }

 private:
  void put(char c) noexcept {
    if (buffer_ != nullptr && size_ < capacity_) buffer_[size_++] = c;
  }
  void put(std::string_view text) noexcept {
    for (char c : text) put(c);
  }

  void putValue(double v) noexcept {
    if (size_ < capacity_) values_[size_++] = v;
  }
  static constexpr double kNaN = __builtin_nan("");

  char* buffer_ = nullptr;
  double* values_ = nullptr;
  std::size_t capacity_;
  std::size_t size_ = 0;
};

/// One column of a port: the suffix after "Comp.port" (".x", "[2]", ".pose.qx" or ""), its unit
/// ("" for none) and whether its cells are numbers (plottable) or text.
struct CsvColumn {
  std::string suffix;
  std::string unit;
  bool numeric = true;
};

template <class T>
inline constexpr bool kNoCsvCodec = false;

/// The CSV codec of `T`. Not defined for a type that is neither one of cobra's own nor a record.
template <class T>
struct CsvCodec {
  static_assert(kNoCsvCodec<T>,
                "cobra: no CSV columns for this type: make it a record (DataTypeTraits<T> : RecordTraits<T> with "
                "fields) or specialise cobra::components::CsvCodec<T> (TextCsvCodec<T> writes its text form)");
};

/// One text column: the type's text form (DataTypeTraits::print). Allocates per row; a value
/// whose text cannot be made leaves the cell empty.
template <class T>
struct TextCsvCodec {
  static constexpr bool kNeedsLength = false;
  static void columns(std::string_view unit, std::size_t, std::vector<CsvColumn>& out) {
    out.push_back({"", std::string(unit), false});
  }
  static void write(RowWriter& row, const T& value, std::size_t) noexcept {
    try {
      row.text(core::DataTypeTraits<T>::print(value));
    } catch (...) {
      row.empty();
    }
  }
};

#define COBRA_DECLARE_CSV_CODEC_(Type, NeedsLength)                                         \
  template <>                                                                               \
  struct CsvCodec<Type> {                                                                   \
    static constexpr bool kNeedsLength = NeedsLength;                                       \
    static void columns(std::string_view unit, std::size_t elements, std::vector<CsvColumn>& out); \
    static void write(RowWriter& row, const Type& value, std::size_t elements) noexcept;    \
    static Type initial(std::size_t elements);                                              \
  }

COBRA_DECLARE_CSV_CODEC_(double, false);
COBRA_DECLARE_CSV_CODEC_(int, false);
COBRA_DECLARE_CSV_CODEC_(bool, false);
COBRA_DECLARE_CSV_CODEC_(std::string, false);
COBRA_DECLARE_CSV_CODEC_(std::vector<double>, true);
COBRA_DECLARE_CSV_CODEC_(KDL::Vector, false);
COBRA_DECLARE_CSV_CODEC_(KDL::Rotation, false);
COBRA_DECLARE_CSV_CODEC_(KDL::Frame, false);
COBRA_DECLARE_CSV_CODEC_(KDL::Twist, false);
COBRA_DECLARE_CSV_CODEC_(KDL::Wrench, false);
COBRA_DECLARE_CSV_CODEC_(KDL::JntArray, true);
COBRA_DECLARE_CSV_CODEC_(core::Event, false);
COBRA_DECLARE_CSV_CODEC_(core::TaskState, false);

#undef COBRA_DECLARE_CSV_CODEC_

namespace csv_detail {
/// The value a reader of a `T` port starts with.
template <class T>
T initial(std::size_t elements) {
  if constexpr (requires { CsvCodec<T>::initial(elements); }) return CsvCodec<T>::initial(elements);
  else return T{};
}
/// The codec of a record's field: its own, or its text form when its column count is not fixed.
template <class M>
using FieldCodec = std::conditional_t<CsvCodec<M>::kNeedsLength, TextCsvCodec<M>, CsvCodec<M>>;
/// The number of elements of a value of a type whose length is not part of it (kNeedsLength):
/// the codec's `length(value)` when it has one, else `value.size()` or `value.rows()`; 0 otherwise.
template <class T>
std::size_t lengthOf(const T& value) noexcept {
  if constexpr (requires { CsvCodec<T>::length(value); }) return CsvCodec<T>::length(value);
  else if constexpr (requires { value.size(); }) return static_cast<std::size_t>(value.size());
  else if constexpr (requires { value.rows(); }) return static_cast<std::size_t>(value.rows());
  else return 0;
}
}  // namespace csv_detail

/// Every record: the columns of each field in order, named `.<field><its suffix>`, with the
/// field's unit (or, when the field gives none, the unit its type's columns carry). A field of
/// variable length (vector<double>, KDL.JntArray) is one text column of its text form.
template <core::RecordDataType T>
struct CsvCodec<T> {
  static constexpr bool kNeedsLength = false;

  static void columns(std::string_view, std::size_t, std::vector<CsvColumn>& out) {
    core::forEachField<T>([&](const auto& f) {
      using M = typename std::decay_t<decltype(f)>::member_type;
      const std::size_t first = out.size();
      csv_detail::FieldCodec<M>::columns(f.unit, 0, out);
      for (std::size_t i = first; i < out.size(); ++i) out[i].suffix = "." + std::string(f.name) + out[i].suffix;
    });
  }

  static void write(RowWriter& row, const T& value, std::size_t) noexcept {
    core::forEachField<T>([&](const auto& f) {
      using M = typename std::decay_t<decltype(f)>::member_type;
      csv_detail::FieldCodec<M>::write(row, value.*(f.member), 0);
    });
  }

  static T initial(std::size_t) {
    T value{};
    core::forEachField<T>([&](const auto& f) {
      using M = typename std::decay_t<decltype(f)>::member_type;
      if constexpr (!CsvCodec<M>::kNeedsLength) value.*(f.member) = csv_detail::initial<M>(0);
    });
    return value;
  }
};

// ---- Sources: one reported port, and the registry of reported types ----------------------------

namespace reporting_detail {

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
  /// The reader input port (connected to the output by the Reporter).
  core::InputPortBase& reader() const { return *reader_; }

  /// Reads the port, keeping the value. Real-time safe for the types with a codec.
  virtual core::FlowStatus sample() = 0;
  /// Appends one cell per header (each preceded by a comma); empty cells before any data.
  virtual void format(RowWriter& row) const noexcept = 0;
  /// Most bytes `format` appends.
  std::size_t maxBytes() const { return max_bytes_; }
  /// The number of elements of the value last read, for a type whose length is not part of it
  /// (vector<double>, KDL.JntArray); 0 for the others and before any data.
  virtual std::size_t length() const noexcept = 0;

 protected:
  Source(core::OutputPortBase& output, std::unique_ptr<core::InputPortBase> reader,
         const std::vector<CsvColumn>& columns);

  bool has_value_ = false;  // a value was read at least once

 private:
  std::string path_;
  core::OutputPortBase* output_;
  std::unique_ptr<core::InputPortBase> reader_;
  std::vector<std::string> headers_;
  std::size_t max_bytes_ = 0;
};

/// A port of a type with a codec: the value is kept as read and written by the codec per row.
/// Made with 0 elements for a type whose length is not part of it (no columns of its own), each
/// value is written in as many cells as it has elements: for a reader that names the columns from
/// the first value (run::NumericTap); the first read sizes the value, later ones of the same
/// length allocate nothing.
template <class T>
class CodecSource final : public Source {
 public:
  CodecSource(core::OutputPortBase& output, std::unique_ptr<core::InputPortBase> reader,
              const std::vector<CsvColumn>& columns, std::size_t elements)
      : Source(output, std::move(reader), columns),
        port_(dynamic_cast<core::InputPort<T>&>(this->reader())),  // makeReader of OutputPort<T>
        value_(csv_detail::initial<T>(elements)),
        elements_(elements),
        cells_(columns.size()) {}

  core::FlowStatus sample() override {
    const core::FlowStatus status = port_.read(value_);
    if (status == core::FlowStatus::NewData) has_value_ = true;
    return status;
  }
  void format(RowWriter& row) const noexcept override {
    if (has_value_) {
      CsvCodec<T>::write(row, value_, CsvCodec<T>::kNeedsLength && elements_ == 0 ? length() : elements_);
    } else {
      for (std::size_t i = 0; i < cells_; ++i) row.empty();
    }
  }
  std::size_t length() const noexcept override {
    if constexpr (CsvCodec<T>::kNeedsLength) return has_value_ ? csv_detail::lengthOf(value_) : 0;
    else return 0;
  }

 private:
  core::InputPort<T>& port_;
  T value_;
  std::size_t elements_;
  std::size_t cells_;
};

/// The columns a port of type `T` with unit `unit` gets.
template <class T>
std::vector<CsvColumn> columnsOf(std::string_view unit, std::size_t elements) {
  std::vector<CsvColumn> columns;
  CsvCodec<T>::columns(unit, elements, columns);
  return columns;
}

template <class T>
std::unique_ptr<Source> makeCodecSource(core::OutputPortBase& output, std::unique_ptr<core::InputPortBase> reader,
                                        std::size_t elements) {
  return std::make_unique<CodecSource<T>>(output, std::move(reader), columnsOf<T>(output.unit(), elements), elements);
}

}  // namespace reporting_detail

/// How the Reporter records one registered type.
struct CsvType {
  std::string_view type_name;  ///< TypeInfo::name
  bool needs_length;           ///< reportPort must be told the number of columns
  /// The columns of a port of this type (for listings and the studio's series).
  std::vector<CsvColumn> (*columns)(std::string_view unit, std::size_t elements);
  /// A source reading `output` through `reader` (made by output.makeReader).
  std::unique_ptr<reporting_detail::Source> (*make_source)(core::OutputPortBase& output,
                                                           std::unique_ptr<core::InputPortBase> reader,
                                                           std::size_t elements);
};

/// The CSV entry of `type`, or nullptr (the Reporter writes such a port as its text form).
const CsvType* findCsvType(const core::TypeInfo& type);
/// Every registered entry, cobra's own types first, then in the order of registration.
std::vector<const CsvType*> csvTypes();
/// Adds the entry of type `id`; adding the same type again does nothing.
/// @throws core::Error when another type of the same name is registered.
void addCsvType(std::type_index id, const CsvType& entry);

/// The CSV entry of `T`, made from `CsvCodec<T>` (a compile error names T when it has none).
template <class T>
CsvType csvTypeOf() {
  return {core::typeInfo<T>().name, CsvCodec<T>::kNeedsLength, &reporting_detail::columnsOf<T>,
          &reporting_detail::makeCodecSource<T>};
}

/// Registers `T` for the Reporter: its ports are recorded in `CsvCodec<T>`'s columns. Idempotent.
template <class T>
void registerCsvType() {
  addCsvType(std::type_index(typeid(T)), csvTypeOf<T>());
}

}  // namespace cobra::components
