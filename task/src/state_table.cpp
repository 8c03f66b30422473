#include "cobra/task/state_table.hpp"

#include <algorithm>
#include <stdexcept>

#include "cobra/task/statements.hpp"

namespace cobra::task {
namespace {

/// Number of dot-separated components of `path` up to (excluding) character `end`.
std::size_t componentsBefore(std::string_view path, std::size_t end) {
  return static_cast<std::size_t>(std::count(path.begin(), path.begin() + static_cast<std::ptrdiff_t>(end), '.')) + 1;
}

/// Calls `match(end)` for every place where the components of `want` appear contiguously in
/// `path`, `end` being the character just after the match. Allocates nothing (Frame Generators
/// and the applications' scripted actors call it from their real-time paths).
template <class F>
void forEachMatch(std::string_view path, std::string_view want, F&& match) {
  for (std::size_t start = 0; start <= path.size();) {
    const std::size_t end = start + want.size();
    if (end <= path.size() && path.compare(start, want.size(), want) == 0 && (end == path.size() || path[end] == '.'))
      match(end);
    const std::size_t dot = path.find('.', start);
    if (dot == std::string_view::npos) break;
    start = dot + 1;
  }
}

Datum parseDatum(Statement& s, const std::string& key, const std::string& text) {
  Datum d;
  const std::size_t sign = text.find_first_of("+-");
  d.name = text.substr(0, sign);
  if (d.name.empty()) s.fail("value of '" + key + "' is '" + text + "', expected NAME or NAME+M or NAME-M");
  if (sign != std::string::npos) {
    d.offset = s.parseNumber(key, std::string_view(text).substr(sign + (text[sign] == '+' ? 1 : 0)), "m");
  }
  return d;
}
Datum parseDatum(Statement& s, const std::string& key) { return parseDatum(s, key, s.raw(key)); }

/// `A|B|C`: the alternatives of one arm's goal.
std::vector<Datum> parseAlternatives(Statement& s, const std::string& key) {
  std::vector<Datum> out;
  const std::string& text = s.raw(key);
  for (std::size_t start = 0;;) {
    const std::size_t bar = text.find('|', start);
    out.push_back(parseDatum(s, key, text.substr(start, bar - start)));
    if (bar == std::string::npos) return out;
    start = bar + 1;
  }
}

/// `A..B`: a straight motion from datum A to datum B.
DatumMotion parseMotion(Statement& s, const std::string& key) {
  const std::string& text = s.raw(key);
  const std::size_t dots = text.find("..");
  if (dots == std::string::npos)
    s.fail("value of '" + key + "' is '" + text + "', expected FROM..TO (two datums: where the motion starts and ends)");
  return {parseDatum(s, key, text.substr(0, dots)), parseDatum(s, key, text.substr(dots + 2))};
}

}  // namespace

const StateRow* StateTable::find(std::string_view path) const {
  const StateRow* best = nullptr;
  std::size_t best_end = 0, best_length = 0;
  for (const StateRow& row : rows) {
    const std::size_t length = componentsBefore(row.state, row.state.size());
    forEachMatch(path, row.state, [&](std::size_t end_char) {
      const std::size_t end = componentsBefore(path, end_char);
      if (!best || end > best_end || (end == best_end && length > best_length)) {
        best = &row;
        best_end = end;
        best_length = length;
      }
    });
  }
  return best;
}

const KDL::Frame* StateTable::pose(std::string_view name) const {
  for (const auto& [n, f] : poses) {
    if (n == name) return &f;
  }
  return nullptr;
}

bool pathContains(std::string_view path, std::string_view state) {
  bool found = false;
  forEachMatch(path, state, [&](std::size_t) { found = true; });
  return found;
}

KDL::Frame alongZ(const KDL::Frame& pose, double offset) {
  return KDL::Frame(pose.M, pose.p + pose.M.UnitZ() * offset);
}

StateTable parseStateTable(std::string_view text, std::string_view source, const TableVocabulary& vocabulary) {
  std::string reserved;  // "entry, target, ..., hold"
  for (const std::string& d : vocabulary.datums) reserved += d + ", ";
  reserved += "hold";
  const auto datum = [&](const std::string& name) {
    return name == "hold" || std::find(vocabulary.datums.begin(), vocabulary.datums.end(), name) != vocabulary.datums.end();
  };
  const std::string& a0 = vocabulary.arms[0];
  const std::string& a1 = vocabulary.arms[1];
  const std::string usage = "state PATH " + a0 + "=DATUM[|DATUM...] " + a1 + "=DATUM[|DATUM...] [then_" + a0 +
                            "=DATUM] [then_" + a1 + "=DATUM] [room_for_" + a0 + "=DATUM..DATUM] [room_for_" + a1 +
                            "=DATUM..DATUM]";
  StateTable table;
  for (Statement& s : statements(text, source)) {
    if (s.words[0] == "pose") {
      if (s.words.size() != 2) s.fail("expected 'pose NAME xyz=X,Y,Z rpy=R,P,Y'");
      const std::string& name = s.words[1];
      if (datum(name)) s.fail("pose name '" + name + "' is reserved (" + reserved + ")");
      if (name.find_first_of("+-|") != std::string::npos)
        s.fail("pose name '" + name + "' holds + - or |, which a datum reads as an offset or an alternative");
      if (table.pose(name)) s.fail("pose '" + name + "' is defined twice");
      table.poses.emplace_back(name, s.frame());
      s.finish(2, "pose NAME xyz=X,Y,Z rpy=R,P,Y");
    } else if (s.words[0] == "state") {
      StateRow row;
      if (s.words.size() > 1) row.state = s.words[1];
      for (std::size_t arm = 0; arm < 2; ++arm) row.goal(arm) = parseAlternatives(s, vocabulary.arms[arm]);
      for (std::size_t arm = 0; arm < 2; ++arm)
        if (s.has("then_" + vocabulary.arms[arm])) row.then(arm) = parseDatum(s, "then_" + vocabulary.arms[arm]);
      for (std::size_t arm = 0; arm < 2; ++arm)
        if (s.has("room_for_" + vocabulary.arms[arm])) row.roomFor(arm) = parseMotion(s, "room_for_" + vocabulary.arms[arm]);
      row.line = s.line;
      s.finish(2, usage.c_str());
      if (row.goal(0).size() > 1 && row.goal(1).size() > 1)
        s.fail("both arms list alternatives (A|B); list them for one arm, the other's goal is the same for each");
      std::vector<const Datum*> datums;
      for (const std::vector<Datum>& arm : row.goals)
        for (const Datum& d : arm) datums.push_back(&d);
      for (const Datum* d : {&row.then(0), &row.then(1), &row.roomFor(0).from, &row.roomFor(0).to,
                             &row.roomFor(1).from, &row.roomFor(1).to})
        if (!d->name.empty()) datums.push_back(d);
      for (const Datum* d : datums) {
        if (!datum(d->name) && table.pose(d->name) == nullptr)
          s.fail("unknown datum '" + d->name + "' (expected " + reserved + " or a pose defined above)");
      }
      for (const StateRow& other : table.rows) {
        if (other.state == row.state) s.fail("state '" + row.state + "' is already at line " + std::to_string(other.line));
      }
      table.rows.push_back(std::move(row));
    } else {
      s.fail("unknown statement '" + s.words[0] + "' (expected pose or state)");
    }
  }
  return table;
}

}  // namespace cobra::task
