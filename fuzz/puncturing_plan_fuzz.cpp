// libFuzzer target: the text formats of the puncturing task's data (cobra::puncturing,
// apps/puncturing/lib/include/cobra/puncturing/plan.hpp): preoperative information, cryoablation
// plan, probe plan, the Frame Generator's state table and the scripted surgeon. Every input goes
// through all five parsers (each refuses the others' statements), so the scenario files serve as
// seeds as they are. Checks that each parser either accepts the text or refuses it with
// std::invalid_argument whose message names the source and, when it names a line, a line of the
// text; that what the three printed formats accept prints to text that parses back to the same
// data (numbers exactly, rotations printed as roll, pitch, yaw within 1e-9); that accepted state
// tables and surgeon scripts hold what the formats promise; and that nothing crashes.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "cobra/puncturing/plan.hpp"
#include "fuzz_support.hpp"

namespace {

namespace p = cobra::puncturing;
constexpr std::string_view kSource = "fuzz.txt";

using cobra::fuzz::identical;
using cobra::fuzz::sameFrame;

bool same(const p::PreoperativeInfo& a, const p::PreoperativeInfo& b) {
  if (!sameFrame(a.abdomen_in_task, b.abdomen_in_task) || !identical(a.tumour_center, b.tumour_center) ||
      a.tumour_radius != b.tumour_radius || !identical(a.entry_center, b.entry_center) || a.entry_radius != b.entry_radius ||
      a.forbidden.size() != b.forbidden.size())
    return false;
  for (std::size_t i = 0; i < a.forbidden.size(); ++i) {
    const auto &x = a.forbidden[i], &y = b.forbidden[i];
    if (x.name != y.name || !identical(x.a, y.a) || !identical(x.b, y.b) || x.radius != y.radius) return false;
  }
  return true;
}

/// Runs `parse` on `text`: the parsed value, or nothing when it refuses the text with a located error.
template <class Parse>
auto parsed(Parse parse, std::string_view text) -> std::optional<decltype(parse(text, kSource))> {
  try {
    return parse(text, kSource);
  } catch (const std::invalid_argument& e) {
    cobra::fuzz::requireLocated(e.what(), kSource, text);
    return std::nullopt;
  }
}

/// parse(print(value)) must succeed (the printed text is valid) and give what `equal` accepts.
template <class T, class Parse, class Print, class Equal>
void roundTrip(const T& value, Parse parse, Print print, Equal equal) {
  try {
    if (!equal(parse(print(value), "printed"), value)) std::abort();
  } catch (const std::invalid_argument&) {
    std::abort();
  }
}

bool known(const p::StateTable& table, const p::Datum& d) {
  for (const char* datum : {"entry", "target", "probe", "next_entry", "next_target", "next_probe", "hold"})
    if (d.name == datum) return true;
  return table.pose(d.name) != nullptr;
}

/// A goal: at least one alternative, each a known datum.
bool known(const p::StateTable& table, const std::vector<p::Datum>& alternatives) {
  if (alternatives.empty()) return false;
  for (const p::Datum& d : alternatives)
    if (!known(table, d)) return false;
  return true;
}

/// An optional datum (then_*, room_for_*): none, or a known one.
bool noneOrKnown(const p::StateTable& table, const p::Datum& d) { return d.name.empty() || known(table, d); }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);

  if (const auto info = parsed(p::parsePreoperative, text)) {
    roundTrip(*info, p::parsePreoperative, [](const p::PreoperativeInfo& i) { return p::print(i); },
              [](const p::PreoperativeInfo& a, const p::PreoperativeInfo& b) { return same(a, b); });
  }
  if (const auto needles = parsed(p::parseCryoPlan, text)) {
    roundTrip(*needles, p::parseCryoPlan, p::printCryoPlan, [](const auto& a, const auto& b) {
      if (a.size() != b.size()) return false;
      for (std::size_t i = 0; i < a.size(); ++i)
        if (a[i].name != b[i].name || !identical(a[i].entry, b[i].entry) || !identical(a[i].target, b[i].target) || a[i].roll != b[i].roll)
          return false;
      return true;
    });
  }
  if (const auto probes = parsed(p::parseProbePlan, text)) {
    roundTrip(*probes, p::parseProbePlan, p::printProbePlan, [](const auto& a, const auto& b) {
      if (a.size() != b.size()) return false;
      for (std::size_t i = 0; i < a.size(); ++i)
        if (a[i].needle != b[i].needle || !sameFrame(a[i].pose, b[i].pose)) return false;
      return true;
    });
  }
  // parseStateTable is overloaded (the vocabulary): the puncturing one, as the frame generator reads it.
  constexpr auto parse_puncturing_table = static_cast<p::StateTable (*)(std::string_view, std::string_view)>(
      p::parseStateTable);
  if (const auto table = parsed(parse_puncturing_table, text)) {
    int previous = 0;
    for (const p::StateRow& row : table->rows) {
      if (row.state.empty() || row.line <= previous || !known(*table, row.goal(0)) || !known(*table, row.goal(1)) ||
          !noneOrKnown(*table, row.then(0)) || !noneOrKnown(*table, row.then(1)) ||
          !noneOrKnown(*table, row.roomFor(0).from) || !noneOrKnown(*table, row.roomFor(0).to) ||
          !noneOrKnown(*table, row.roomFor(1).from) || !noneOrKnown(*table, row.roomFor(1).to))
        std::abort();
      if (table->find(row.state) == nullptr) std::abort();  // a row's own state finds a row
      previous = row.line;
    }
  }
  if (const auto script = parsed(p::parseSurgeonScript, text)) {
    const auto& events = p::surgeonEvents();
    for (const p::SurgeonAction& a : script->actions) {
      if (std::find(events.begin(), events.end(), a.event) == events.end() || a.at < 0.0 || a.after < 0.0 ||
          a.times < 0)
        std::abort();
      if (a.trigger == p::SurgeonAction::Trigger::OnState && ((a.chart != "needle" && a.chart != "us") || a.state.empty()))
        std::abort();
    }
  }
  return 0;
}
