#include "source.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <charconv>
#include <mutex>
#include <optional>
#include <typeindex>
#include <utility>

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

#include "cobra/components/reporting/reporter.hpp"
#include "cobra/core/error.hpp"

namespace cobra::components {

// ---- RowWriter --------------------------------------------------------------------------------

void RowWriter::time(std::chrono::nanoseconds t) noexcept {
  if (values_ != nullptr) {
    putValue(std::chrono::duration<double>(t).count());
    return;
  }
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
  if (values_ != nullptr) {
    putValue(value);
    return;
  }
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
  if (values_ != nullptr) {
    putValue(kNaN);
    return;
  }
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

namespace reporting_detail {
std::string csvCell(std::string_view text) {
  if (!needsQuotes(text)) return std::string(text);
  std::string quoted = "\"";
  for (char c : text) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + "\"";
}
}  // namespace reporting_detail

// ---- Leaf codecs of cobra's own types --------------------------------------------------------

namespace {
void numbered(std::size_t elements, std::string_view unit, std::vector<CsvColumn>& out) {
  for (std::size_t i = 0; i < elements; ++i) out.push_back({"[" + std::to_string(i) + "]", std::string(unit)});
}
void named(std::initializer_list<const char*> suffixes, std::string_view unit, std::vector<CsvColumn>& out) {
  for (const char* s : suffixes) out.push_back({s, std::string(unit)});
}
/// `count` cells from `values` (of `size`): shorter values leave the rest empty, longer are cut.
void cells(RowWriter& row, const double* values, std::size_t size, std::size_t count) noexcept {
  for (std::size_t i = 0; i < count; ++i) {
    if (i < size) row.number(values[i]);
    else row.empty();
  }
}
void quaternion(RowWriter& row, const KDL::Rotation& r) noexcept {
  double q[4] = {0.0, 0.0, 0.0, 1.0};
  r.GetQuaternion(q[0], q[1], q[2], q[3]);
  cells(row, q, 4, 4);
}
}  // namespace

void CsvCodec<double>::columns(std::string_view unit, std::size_t, std::vector<CsvColumn>& out) { out.push_back({"", std::string(unit)}); }
void CsvCodec<double>::write(RowWriter& row, const double& v, std::size_t) noexcept { row.number(v); }
double CsvCodec<double>::initial(std::size_t) { return 0.0; }

void CsvCodec<int>::columns(std::string_view unit, std::size_t, std::vector<CsvColumn>& out) { out.push_back({"", std::string(unit)}); }
void CsvCodec<int>::write(RowWriter& row, const int& v, std::size_t) noexcept { row.number(static_cast<double>(v)); }
int CsvCodec<int>::initial(std::size_t) { return 0; }

void CsvCodec<bool>::columns(std::string_view unit, std::size_t, std::vector<CsvColumn>& out) { out.push_back({"", std::string(unit)}); }
void CsvCodec<bool>::write(RowWriter& row, const bool& v, std::size_t) noexcept { row.number(v ? 1.0 : 0.0); }
bool CsvCodec<bool>::initial(std::size_t) { return false; }

void CsvCodec<std::string>::columns(std::string_view unit, std::size_t, std::vector<CsvColumn>& out) {
  out.push_back({"", std::string(unit), false});
}
void CsvCodec<std::string>::write(RowWriter& row, const std::string& v, std::size_t) noexcept { row.text(v); }
std::string CsvCodec<std::string>::initial(std::size_t) {
  std::string initial;
  initial.reserve(256);  // copying a shorter string into it then allocates nothing
  return initial;
}

void CsvCodec<std::vector<double>>::columns(std::string_view unit, std::size_t elements, std::vector<CsvColumn>& out) {
  numbered(elements, unit, out);
}
void CsvCodec<std::vector<double>>::write(RowWriter& row, const std::vector<double>& v, std::size_t elements) noexcept {
  cells(row, v.data(), v.size(), elements);
}
std::vector<double> CsvCodec<std::vector<double>>::initial(std::size_t elements) { return std::vector<double>(elements); }

void CsvCodec<KDL::JntArray>::columns(std::string_view unit, std::size_t elements, std::vector<CsvColumn>& out) {
  numbered(elements, unit, out);
}
void CsvCodec<KDL::JntArray>::write(RowWriter& row, const KDL::JntArray& q, std::size_t elements) noexcept {
  cells(row, q.data.data(), q.rows(), elements);
}
KDL::JntArray CsvCodec<KDL::JntArray>::initial(std::size_t elements) { return KDL::JntArray(static_cast<unsigned>(elements)); }

void CsvCodec<KDL::Vector>::columns(std::string_view unit, std::size_t, std::vector<CsvColumn>& out) {
  named({".x", ".y", ".z"}, unit, out);
}
void CsvCodec<KDL::Vector>::write(RowWriter& row, const KDL::Vector& v, std::size_t) noexcept { cells(row, v.data, 3, 3); }
KDL::Vector CsvCodec<KDL::Vector>::initial(std::size_t) { return KDL::Vector::Zero(); }

void CsvCodec<KDL::Rotation>::columns(std::string_view, std::size_t, std::vector<CsvColumn>& out) {
  named({".qx", ".qy", ".qz", ".qw"}, "1", out);
}
void CsvCodec<KDL::Rotation>::write(RowWriter& row, const KDL::Rotation& r, std::size_t) noexcept { quaternion(row, r); }
KDL::Rotation CsvCodec<KDL::Rotation>::initial(std::size_t) { return KDL::Rotation::Identity(); }

void CsvCodec<KDL::Frame>::columns(std::string_view, std::size_t, std::vector<CsvColumn>& out) {
  named({".x", ".y", ".z"}, "m", out);
  named({".qx", ".qy", ".qz", ".qw"}, "1", out);
}
void CsvCodec<KDL::Frame>::write(RowWriter& row, const KDL::Frame& f, std::size_t) noexcept {
  cells(row, f.p.data, 3, 3);
  quaternion(row, f.M);
}
KDL::Frame CsvCodec<KDL::Frame>::initial(std::size_t) { return KDL::Frame::Identity(); }

void CsvCodec<KDL::Twist>::columns(std::string_view, std::size_t, std::vector<CsvColumn>& out) {
  named({".vx", ".vy", ".vz"}, "m/s", out);
  named({".wx", ".wy", ".wz"}, "rad/s", out);
}
void CsvCodec<KDL::Twist>::write(RowWriter& row, const KDL::Twist& t, std::size_t) noexcept {
  cells(row, t.vel.data, 3, 3);
  cells(row, t.rot.data, 3, 3);
}
KDL::Twist CsvCodec<KDL::Twist>::initial(std::size_t) { return KDL::Twist::Zero(); }

void CsvCodec<KDL::Wrench>::columns(std::string_view, std::size_t, std::vector<CsvColumn>& out) {
  named({".fx", ".fy", ".fz"}, "N", out);
  named({".tx", ".ty", ".tz"}, "N·m", out);
}
void CsvCodec<KDL::Wrench>::write(RowWriter& row, const KDL::Wrench& w, std::size_t) noexcept {
  cells(row, w.force.data, 3, 3);
  cells(row, w.torque.data, 3, 3);
}
KDL::Wrench CsvCodec<KDL::Wrench>::initial(std::size_t) { return KDL::Wrench::Zero(); }

void CsvCodec<core::Event>::columns(std::string_view unit, std::size_t, std::vector<CsvColumn>& out) {
  out.push_back({"", std::string(unit), false});
}
void CsvCodec<core::Event>::write(RowWriter& row, const core::Event& e, std::size_t) noexcept { row.text(e.name.view()); }
core::Event CsvCodec<core::Event>::initial(std::size_t) { return core::Event{}; }

void CsvCodec<core::TaskState>::columns(std::string_view unit, std::size_t, std::vector<CsvColumn>& out) {
  out.push_back({"", std::string(unit), false});
}
void CsvCodec<core::TaskState>::write(RowWriter& row, const core::TaskState& s, std::size_t) noexcept {
  row.text(s.path.view());
}
core::TaskState CsvCodec<core::TaskState>::initial(std::size_t) { return core::TaskState{}; }

// ---- Sources and the registry ----------------------------------------------------------------

namespace reporting_detail {

namespace {
std::vector<std::string> headersOf(const core::OutputPortBase& output, const std::vector<CsvColumn>& columns) {
  std::vector<std::string> headers;
  for (const CsvColumn& c : columns)
    headers.push_back(csvCell(output.fullName() + c.suffix + (c.unit.empty() ? "" : " [" + c.unit + "]")));
  return headers;
}
std::size_t maxBytesOf(const std::vector<CsvColumn>& columns) {
  std::size_t bytes = 0;
  for (const CsvColumn& c : columns) bytes += c.numeric ? RowWriter::kMaxNumberBytes : RowWriter::maxTextBytes();
  return bytes;
}
}  // namespace

Source::Source(core::OutputPortBase& output, std::unique_ptr<core::InputPortBase> reader,
               const std::vector<CsvColumn>& columns)
    : path_(output.fullName()),
      output_(&output),
      reader_(std::move(reader)),
      headers_(headersOf(output, columns)),
      max_bytes_(maxBytesOf(columns)) {}

namespace {

/// A type without a CSV codec: its text form, through the type-erased `readText` (allocates).
class TextSource final : public Source {
 public:
  TextSource(core::OutputPortBase& output, std::unique_ptr<core::InputPortBase> reader)
      : Source(output, std::move(reader), {{"", output.unit(), false}}) {
    text_.reserve(RowWriter::kMaxTextChars + 1);
  }
  core::FlowStatus sample() override {
    const core::FlowStatus status = reader().readText(text_);
    if (status == core::FlowStatus::NewData) has_value_ = true;
    return status;
  }
  std::size_t length() const noexcept override { return 0; }
  void format(RowWriter& row) const noexcept override {
    if (has_value_) row.text(text_);
    else row.empty();
  }

 private:
  std::string text_;
};

/// Append-only, fixed capacity: entries never move; a reader scans the first `count` entries
/// without a lock (the count is published after the entry is written).
struct Registry {
  static constexpr std::size_t kCapacity = 256;
  std::mutex write_mutex;
  std::array<std::optional<std::type_index>, kCapacity> ids{};
  std::array<CsvType, kCapacity> entries{};
  std::atomic<std::size_t> count{0};
};

Registry& rawRegistry() {
  static Registry r;
  return r;
}

/// The registry, with cobra's own types (core::BuiltinDataTypes) added at its first use.
void add(std::type_index id, const CsvType& entry);

Registry& registry() {
  static const bool seeded = [] {
    core::forEachType(core::BuiltinDataTypes{}, [](auto type) {
      using T = typename decltype(type)::type;
      add(std::type_index(typeid(T)), csvTypeOf<T>());
    });
    return true;
  }();
  (void)seeded;
  return rawRegistry();
}

void add(std::type_index id, const CsvType& entry) {
  auto& r = rawRegistry();
  std::lock_guard lock(r.write_mutex);
  const std::size_t n = r.count.load(std::memory_order_relaxed);
  for (std::size_t i = 0; i < n; ++i) {
    if (*r.ids[i] == id) return;
    if (r.entries[i].type_name == entry.type_name)
      throw core::Error("cobra: two types are registered for CSV as '" + std::string(entry.type_name) +
                        "'; give one of them another DataTypeTraits<T>::name");
  }
  if (n == Registry::kCapacity)
    throw core::Error("cobra: the CSV type registry is full; cannot add " + std::string(entry.type_name));
  r.ids[n] = id;
  r.entries[n] = entry;
  r.count.store(n + 1, std::memory_order_release);
}

}  // namespace

bool needsLength(const core::TypeInfo& type) {
  const CsvType* entry = findCsvType(type);
  return entry != nullptr && entry->needs_length;
}

std::unique_ptr<Source> makeSource(core::OutputPortBase& output, std::string reader_name, std::size_t elements) {
  const core::TypeInfo& type = output.type();
  const std::string type_name(type.name);
  const CsvType* entry = findCsvType(type);
  const bool needs = entry != nullptr && entry->needs_length;
  if (needs && elements == 0)
    throw core::Error("it is a " + type_name +
                      ", whose length is not part of its type; give its number of elements, e.g. reportPort(port, 6)");
  if (!needs && elements != 0)
    throw core::Error("it is a " + type_name + ", whose columns are fixed by its type; give no number of elements (" +
                      std::to_string(elements) +
                      " was given; a number is for a type whose length is not part of it, such as vector<double> "
                      "or KDL.JntArray)");
  auto reader = output.makeReader(std::move(reader_name), "reads " + output.fullName() + " for the report");
  if (entry == nullptr) return std::make_unique<TextSource>(output, std::move(reader));
  return entry->make_source(output, std::move(reader), elements);
}

}  // namespace reporting_detail

void addCsvType(std::type_index id, const CsvType& entry) {
  (void)reporting_detail::registry();  // cobra's own types first
  reporting_detail::add(id, entry);
}

std::vector<const CsvType*> csvTypes() {
  auto& r = reporting_detail::registry();
  const std::size_t n = r.count.load(std::memory_order_acquire);
  std::vector<const CsvType*> entries;
  for (std::size_t i = 0; i < n; ++i) entries.push_back(&r.entries[i]);
  return entries;
}

const CsvType* findCsvType(const core::TypeInfo& type) {
  auto& r = reporting_detail::registry();
  const std::size_t n = r.count.load(std::memory_order_acquire);
  for (std::size_t i = 0; i < n; ++i)
    if (*r.ids[i] == type.id) return &r.entries[i];
  return nullptr;
}

}  // namespace cobra::components
