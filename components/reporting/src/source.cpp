#include "source.hpp"

#include <array>
#include <charconv>
#include <typeindex>
#include <utility>

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

#include "cobra/components/reporting/reporter.hpp"
#include "cobra/core/error.hpp"

namespace cobra::components::reporting_detail {

// ---- RowWriter --------------------------------------------------------------------------------

void RowWriter::time(std::chrono::nanoseconds t) noexcept {
  std::int64_t ns = t.count();
  if (ns < 0) {
    put('-');
    ns = -ns;  // |t| < 2^63 ns: the clocks start near zero
  }
  std::array<char, 24> digits{};
  auto [end, ec] = std::to_chars(digits.data(), digits.data() + digits.size(), ns / 1'000'000'000);
  put(std::string_view(digits.data(), static_cast<std::size_t>(end - digits.data())));
  std::int64_t fraction = ns % 1'000'000'000;
  if (fraction == 0) return;
  // Nine decimals, then the trailing zeros dropped: exact, and as short as the value allows.
  std::array<char, 9> decimals{};
  for (std::size_t i = decimals.size(); i-- > 0;) {
    decimals[i] = static_cast<char>('0' + fraction % 10);
    fraction /= 10;
  }
  std::size_t length = decimals.size();
  while (decimals[length - 1] == '0') --length;
  put('.');
  put(std::string_view(decimals.data(), length));
  (void)ec;
}

void RowWriter::number(double value) noexcept {
  std::array<char, 32> text{};
  const auto [end, ec] = std::to_chars(text.data(), text.data() + text.size(), value);
  put(',');
  if (ec == std::errc()) put(std::string_view(text.data(), static_cast<std::size_t>(end - text.data())));
}

namespace {
bool needsQuotes(std::string_view text) { return text.find_first_of(",\"\r\n") != std::string_view::npos; }

/// `text` cut after `max_chars` bytes, backing off so that no UTF-8 sequence is split.
std::string_view cut(std::string_view text, std::size_t max_chars) {
  if (text.size() <= max_chars) return text;
  std::size_t length = max_chars;
  while (length > 0 && (static_cast<unsigned char>(text[length]) & 0xC0U) == 0x80U) --length;
  return text.substr(0, length);
}
}  // namespace

void RowWriter::text(std::string_view text, std::size_t max_chars) noexcept {
  text = cut(text, max_chars);
  put(',');
  if (!needsQuotes(text)) {
    put(text);
    return;
  }
  put('"');
  for (char c : text) {
    if (c == '"') put('"');
    put(c);
  }
  put('"');
}

std::string csvCell(std::string_view text) {
  if (!needsQuotes(text)) return std::string(text);
  std::string quoted = "\"";
  for (char c : text) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + "\"";
}

// ---- Sources ----------------------------------------------------------------------------------

Source::Source(core::OutputPortBase& output, std::unique_ptr<core::InputPortBase> reader,
               std::vector<std::string> headers)
    : path_(output.fullName()), output_(&output), reader_(std::move(reader)), headers_(std::move(headers)) {}

namespace {

/// A column: suffix after "Comp.port" (".x", "[2]" or "") and its unit.
struct Column {
  std::string suffix;
  std::string unit;
};

std::vector<std::string> headersOf(const core::OutputPortBase& output, const std::vector<Column>& columns) {
  std::vector<std::string> headers;
  for (const Column& c : columns)
    headers.push_back(csvCell(output.fullName() + c.suffix + (c.unit.empty() ? "" : " [" + c.unit + "]")));
  return headers;
}

template <class T>
core::InputPort<T>& typed(core::InputPortBase& reader) {
  // makeReader of an OutputPort<T> always makes an InputPort<T>.
  return dynamic_cast<core::InputPort<T>&>(reader);
}

/// Numeric values: the value is flattened into doubles when it is read, formatted per row.
template <class T>
class FlatSource final : public Source {
 public:
  /// Writes at most `n` elements of the value to `out`; returns how many the value has.
  using Flatten = std::size_t (*)(const T& value, double* out, std::size_t n);

  FlatSource(core::OutputPortBase& output, std::unique_ptr<core::InputPortBase> reader,
             const std::vector<Column>& columns, T initial, Flatten flatten)
      : Source(output, std::move(reader), headersOf(output, columns)),
        port_(typed<T>(this->reader())),
        value_(std::move(initial)),
        cells_(columns.size(), 0.0),
        flatten_(flatten) {}

  core::FlowStatus sample() override {
    const core::FlowStatus status = port_.read(value_);
    if (status == core::FlowStatus::NewData) {
      count_ = std::min(flatten_(value_, cells_.data(), cells_.size()), cells_.size());
      has_value_ = true;
    }
    return status;
  }
  void format(RowWriter& row) const noexcept override {
    for (std::size_t i = 0; i < cells_.size(); ++i) {
      if (has_value_ && i < count_) row.number(cells_[i]);
      else row.empty();
    }
  }
  std::size_t maxBytes() const override { return cells_.size() * RowWriter::kMaxNumberBytes; }

 private:
  core::InputPort<T>& port_;
  T value_;
  std::vector<double> cells_;
  std::size_t count_ = 0;
  Flatten flatten_;
};

/// Text values: one column. `Text` gives the cell text of a value without allocating.
template <class T>
class TextSource final : public Source {
 public:
  using Text = std::string_view (*)(const T& value);

  TextSource(core::OutputPortBase& output, std::unique_ptr<core::InputPortBase> reader, T initial, Text text)
      : Source(output, std::move(reader), headersOf(output, {{"", output.unit()}})),
        port_(typed<T>(this->reader())),
        value_(std::move(initial)),
        text_(text) {}

  core::FlowStatus sample() override {
    const core::FlowStatus status = port_.read(value_);
    if (status == core::FlowStatus::NewData) has_value_ = true;
    return status;
  }
  void format(RowWriter& row) const noexcept override {
    if (has_value_) row.text(text_(value_), Reporter::kMaxTextChars);
    else row.empty();
  }
  std::size_t maxBytes() const override { return RowWriter::maxTextBytes(Reporter::kMaxTextChars); }

 private:
  core::InputPort<T>& port_;
  T value_;
  Text text_;
};

/// Any other registered type: its text form, through the type-erased `readText` (allocates).
class GenericSource final : public Source {
 public:
  GenericSource(core::OutputPortBase& output, std::unique_ptr<core::InputPortBase> reader)
      : Source(output, std::move(reader), headersOf(output, {{"", output.unit()}})) {
    text_.reserve(Reporter::kMaxTextChars + 1);
  }
  core::FlowStatus sample() override {
    const core::FlowStatus status = reader().readText(text_);
    if (status == core::FlowStatus::NewData) has_value_ = true;
    return status;
  }
  void format(RowWriter& row) const noexcept override {
    if (has_value_) row.text(text_, Reporter::kMaxTextChars);
    else row.empty();
  }
  std::size_t maxBytes() const override { return RowWriter::maxTextBytes(Reporter::kMaxTextChars); }

 private:
  std::string text_;
};

std::size_t put(double* out, std::size_t n, std::initializer_list<double> values) {
  std::size_t i = 0;
  for (double v : values)
    if (i < n) out[i++] = v;
  return values.size();
}

std::size_t flattenRotation(const KDL::Rotation& r, double* out, std::size_t n) {
  double qx = 0.0, qy = 0.0, qz = 0.0, qw = 1.0;
  r.GetQuaternion(qx, qy, qz, qw);
  return put(out, n, {qx, qy, qz, qw});
}

std::vector<Column> indexed(std::size_t elements, const std::string& unit) {
  std::vector<Column> columns;
  for (std::size_t i = 0; i < elements; ++i) columns.push_back({"[" + std::to_string(i) + "]", unit});
  return columns;
}

template <class T>
bool isType(const core::TypeInfo& type) {
  return type.id == std::type_index(typeid(T));
}

const std::vector<Column> kQuaternion = {{".qx", "1"}, {".qy", "1"}, {".qz", "1"}, {".qw", "1"}};

}  // namespace

bool needsLength(const core::TypeInfo& type) {
  return isType<std::vector<double>>(type) || isType<KDL::JntArray>(type);
}

std::unique_ptr<Source> makeSource(core::OutputPortBase& output, std::string reader_name, std::size_t elements) {
  const core::TypeInfo& type = output.type();
  const std::string type_name(type.name);
  if (needsLength(type) && elements == 0)
    throw core::Error("it is a " + type_name +
                      ", whose length is not part of its type; give its number of elements, e.g. reportPort(port, 6)");
  if (!needsLength(type) && elements != 0)
    throw core::Error("it is a " + type_name + ", whose columns are fixed by its type; give no number of elements (" +
                      std::to_string(elements) + " was given; only vector<double> and KDL.JntArray take one)");

  auto reader = output.makeReader(std::move(reader_name), "reads " + output.fullName() + " for the report");
  const std::string& unit = output.unit();
  using Out = std::unique_ptr<Source>;

  if (isType<double>(type))
    return Out(new FlatSource<double>(output, std::move(reader), {{"", unit}}, 0.0,
                                      [](const double& v, double* out, std::size_t n) { return put(out, n, {v}); }));
  if (isType<int>(type))
    return Out(new FlatSource<int>(output, std::move(reader), {{"", unit}}, 0, [](const int& v, double* out, std::size_t n) {
      return put(out, n, {static_cast<double>(v)});
    }));
  if (isType<bool>(type))
    return Out(new FlatSource<bool>(output, std::move(reader), {{"", unit}}, false,
                                    [](const bool& v, double* out, std::size_t n) { return put(out, n, {v ? 1.0 : 0.0}); }));
  if (isType<std::vector<double>>(type))
    return Out(new FlatSource<std::vector<double>>(
        output, std::move(reader), indexed(elements, unit), std::vector<double>(elements),
        [](const std::vector<double>& v, double* out, std::size_t n) {
          for (std::size_t i = 0; i < v.size() && i < n; ++i) out[i] = v[i];
          return v.size();
        }));
  if (isType<KDL::JntArray>(type))
    return Out(new FlatSource<KDL::JntArray>(output, std::move(reader), indexed(elements, unit),
                                             KDL::JntArray(static_cast<unsigned>(elements)),
                                             [](const KDL::JntArray& v, double* out, std::size_t n) {
                                               const std::size_t rows = v.rows();
                                               for (std::size_t i = 0; i < rows && i < n; ++i)
                                                 out[i] = v(static_cast<unsigned>(i));
                                               return rows;
                                             }));
  if (isType<KDL::Vector>(type))
    return Out(new FlatSource<KDL::Vector>(output, std::move(reader), {{".x", unit}, {".y", unit}, {".z", unit}},
                                           KDL::Vector::Zero(), [](const KDL::Vector& v, double* out, std::size_t n) {
                                             return put(out, n, {v.x(), v.y(), v.z()});
                                           }));
  if (isType<KDL::Rotation>(type))
    return Out(new FlatSource<KDL::Rotation>(output, std::move(reader), kQuaternion, KDL::Rotation::Identity(),
                                             flattenRotation));
  if (isType<KDL::Frame>(type)) {
    std::vector<Column> columns = {{".x", "m"}, {".y", "m"}, {".z", "m"}};
    columns.insert(columns.end(), kQuaternion.begin(), kQuaternion.end());
    return Out(new FlatSource<KDL::Frame>(output, std::move(reader), columns, KDL::Frame::Identity(),
                                          [](const KDL::Frame& f, double* out, std::size_t n) {
                                            // n is 7, the number of columns above
                                            put(out, n, {f.p.x(), f.p.y(), f.p.z()});
                                            return 3 + flattenRotation(f.M, out + 3, n - 3);
                                          }));
  }
  if (isType<KDL::Twist>(type))
    return Out(new FlatSource<KDL::Twist>(
        output, std::move(reader),
        {{".vx", "m/s"}, {".vy", "m/s"}, {".vz", "m/s"}, {".wx", "rad/s"}, {".wy", "rad/s"}, {".wz", "rad/s"}},
        KDL::Twist::Zero(), [](const KDL::Twist& t, double* out, std::size_t n) {
          return put(out, n, {t.vel.x(), t.vel.y(), t.vel.z(), t.rot.x(), t.rot.y(), t.rot.z()});
        }));
  if (isType<KDL::Wrench>(type))
    return Out(new FlatSource<KDL::Wrench>(
        output, std::move(reader),
        {{".fx", "N"}, {".fy", "N"}, {".fz", "N"}, {".tx", "N·m"}, {".ty", "N·m"}, {".tz", "N·m"}},
        KDL::Wrench::Zero(), [](const KDL::Wrench& w, double* out, std::size_t n) {
          return put(out, n, {w.force.x(), w.force.y(), w.force.z(), w.torque.x(), w.torque.y(), w.torque.z()});
        }));
  if (isType<std::string>(type)) {
    std::string initial;
    initial.reserve(256);  // copying a shorter string into it then allocates nothing
    return Out(new TextSource<std::string>(output, std::move(reader), std::move(initial),
                                           [](const std::string& s) { return std::string_view(s); }));
  }
  if (isType<core::Event>(type))
    return Out(new TextSource<core::Event>(output, std::move(reader), core::Event{},
                                           [](const core::Event& e) { return e.name.view(); }));
  return Out(new GenericSource(output, std::move(reader)));
}

}  // namespace cobra::components::reporting_detail
