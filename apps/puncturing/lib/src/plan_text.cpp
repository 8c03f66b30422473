// The text formats of the puncturing data (apps/puncturing/README.md): one statement per line,
// `#` starts a comment, words separated by blanks, parameters as key=value, vectors as X,Y,Z.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include "cobra/puncturing/plan.hpp"

namespace cobra::puncturing {
namespace {

/// One statement: its words and key=value parameters, with where it came from.
struct Statement {
  std::string where;  // "source:line"
  int line = 0;
  std::vector<std::string> words;
  std::map<std::string, std::string> params;
  std::map<std::string, bool> used;

  [[noreturn]] void fail(const std::string& message) const { throw std::invalid_argument(where + ": " + message); }

  bool has(const std::string& key) const { return params.count(key) != 0; }
  const std::string& raw(const std::string& key) {
    const auto it = params.find(key);
    if (it == params.end()) fail("'" + words[0] + "' needs " + key + "=");
    used[key] = true;
    return it->second;
  }
  double number(const std::string& key, const char* unit) { return parseNumber(key, raw(key), unit); }
  double number(const std::string& key, double fallback, const char* unit) {
    return has(key) ? number(key, unit) : fallback;
  }
  double parseNumber(const std::string& key, std::string_view text, const char* unit) const {
    double value = 0.0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || error != std::errc() || end != text.data() + text.size() || !std::isfinite(value)) {
      fail("value of '" + key + "' is '" + std::string(text) + "', expected a number (" + unit + ")");
    }
    return value;
  }
  KDL::Vector vector(const std::string& key, const char* unit) {
    std::string_view text = raw(key);
    double xyz[3];
    for (int i = 0; i < 3; ++i) {
      const std::size_t comma = text.find(',');
      if ((i < 2) != (comma != std::string_view::npos)) fail("value of '" + key + "' must be X,Y,Z (" + unit + ")");
      xyz[i] = parseNumber(key, text.substr(0, comma), unit);
      text = comma == std::string_view::npos ? std::string_view() : text.substr(comma + 1);
    }
    return {xyz[0], xyz[1], xyz[2]};
  }
  KDL::Frame frame() {
    const KDL::Vector rpy = has("rpy") ? vector("rpy", "rad") : KDL::Vector::Zero();
    return KDL::Frame(KDL::Rotation::RPY(rpy.x(), rpy.y(), rpy.z()), vector("xyz", "m"));
  }
  double positive(const std::string& key, const char* unit) {
    const double value = number(key, unit);
    if (value <= 0.0) fail(key + " = " + raw(key) + ", expected > 0 " + unit);
    return value;
  }
  /// Every parameter was used and there are `count` words (statement included).
  void finish(std::size_t count, const char* usage) const {
    if (words.size() != count) fail("expected '" + std::string(usage) + "'");
    for (const auto& [key, value] : params) {
      if (!used.count(key)) fail("unknown key '" + key + "' in '" + words[0] + "' (expected '" + usage + "')");
    }
  }
};

std::vector<Statement> statements(std::string_view text, std::string_view source) {
  std::vector<Statement> out;
  int line_number = 0;
  std::size_t start = 0;
  while (start <= text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(start, end - start);
    start = end + 1;
    ++line_number;
    if (const std::size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    Statement s;
    s.line = line_number;
    s.where = std::string(source) + ":" + std::to_string(line_number);
    std::size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
      std::size_t j = i;
      while (j < line.size() && line[j] != ' ' && line[j] != '\t' && line[j] != '\r') ++j;
      if (j == i) break;
      const std::string_view word = line.substr(i, j - i);
      const std::size_t eq = word.find('=');
      if (eq == std::string_view::npos) {
        if (!s.params.empty()) s.fail("word '" + std::string(word) + "' after the key=value parameters");
        s.words.emplace_back(word);
      } else {
        const std::string key(word.substr(0, eq));
        if (key.empty() || s.words.empty()) s.fail("'" + std::string(word) + "' is not a statement");
        if (!s.params.emplace(key, std::string(word.substr(eq + 1))).second) s.fail("key '" + key + "' given twice");
      }
      i = j;
    }
    if (!s.words.empty()) out.push_back(std::move(s));
    if (end == text.size()) break;
  }
  return out;
}

// The shortest decimal that parses back to exactly `value`: a printed plan parses to the same
// numbers, so a value a parser's check accepts (the tumour below the skin, ...) stays accepted.
std::string number(double value) {
  char buffer[32];
  return std::string(buffer, std::to_chars(buffer, buffer + sizeof buffer, value).ptr);
}
std::string vec(const KDL::Vector& v) { return number(v.x()) + "," + number(v.y()) + "," + number(v.z()); }
std::string frame(const KDL::Frame& f) {
  double r = 0, p = 0, y = 0;
  f.M.GetRPY(r, p, y);
  return "xyz=" + vec(f.p) + " rpy=" + number(r) + "," + number(p) + "," + number(y);
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

const std::vector<std::string>& surgeonEvents() {
  static const std::vector<std::string> events = {"e_iceball_configured", "e_needle_mounted", "e_needle_removed",
                                                  "e_cryo_done",          "e_recover",        "e_take_over",
                                                  "e_teleop_done"};
  return events;
}

PreoperativeInfo parsePreoperative(std::string_view text, std::string_view source) {
  PreoperativeInfo info;
  bool tumour = false, entry = false, abdomen = false;
  for (Statement& s : statements(text, source)) {
    const std::string& what = s.words[0];
    if (what == "abdomen") {
      if (abdomen) s.fail("a second 'abdomen'");
      info.abdomen_in_task = s.frame();
      s.finish(1, "abdomen xyz=X,Y,Z rpy=R,P,Y");
      abdomen = true;
    } else if (what == "tumour") {
      if (tumour) s.fail("a second 'tumour'");
      info.tumour_center = s.vector("center", "m");
      info.tumour_radius = s.positive("radius", "m");
      s.finish(1, "tumour center=X,Y,Z radius=M");
      if (info.tumour_center.z() + info.tumour_radius >= 0.0) s.fail("the tumour reaches the skin (z = 0) or above it");
      tumour = true;
    } else if (what == "sphere" || what == "capsule") {
      ForbiddenRegion r;
      if (s.words.size() > 1) r.name = s.words[1];
      if (what == "sphere") {
        r.a = r.b = s.vector("center", "m");
      } else {
        r.a = s.vector("a", "m");
        r.b = s.vector("b", "m");
      }
      r.radius = s.positive("radius", "m");
      s.finish(2, what == "sphere" ? "sphere NAME center=X,Y,Z radius=M" : "capsule NAME a=X,Y,Z b=X,Y,Z radius=M");
      info.forbidden.push_back(std::move(r));
    } else if (what == "entry_region") {
      if (entry) s.fail("a second 'entry_region'");
      info.entry_center = s.vector("center", "m");
      info.entry_radius = s.positive("radius", "m");
      s.finish(1, "entry_region center=X,Y,Z radius=M");
      if (std::abs(info.entry_center.z()) > 1e-3) s.fail("the entry region's centre must be on the skin (z = 0 m)");
      entry = true;
    } else {
      s.fail("unknown statement '" + what + "' (expected abdomen, tumour, sphere, capsule or entry_region)");
    }
  }
  const std::string where(source);
  if (!abdomen) throw std::invalid_argument(where + ": no 'abdomen xyz=X,Y,Z rpy=R,P,Y' (A's pose in the task frame)");
  if (!tumour) throw std::invalid_argument(where + ": no 'tumour center=X,Y,Z radius=M'");
  if (!entry) throw std::invalid_argument(where + ": no 'entry_region center=X,Y,Z radius=M'");
  return info;
}

std::vector<PlannedNeedle> parseCryoPlan(std::string_view text, std::string_view source) {
  std::vector<PlannedNeedle> needles;
  for (Statement& s : statements(text, source)) {
    if (s.words[0] != "needle") s.fail("unknown statement '" + s.words[0] + "' (expected needle)");
    PlannedNeedle n;
    if (s.words.size() > 1) n.name = s.words[1];
    n.entry = s.vector("entry", "m");
    n.target = s.vector("target", "m");
    n.roll = s.number("roll", 0.0, "rad");
    n.line = s.line;
    s.finish(2, "needle NAME entry=X,Y,Z target=X,Y,Z [roll=R]");
    for (const PlannedNeedle& other : needles) {
      if (other.name == n.name) s.fail("needle '" + n.name + "' is already planned at line " + std::to_string(other.line));
    }
    if ((n.target - n.entry).Norm() < 1e-3) s.fail("needle '" + n.name + "': entry and target less than 1 mm apart");
    needles.push_back(std::move(n));
  }
  if (needles.empty()) throw std::invalid_argument(std::string(source) + ": no needle planned");
  return needles;
}

std::vector<PlannedProbe> parseProbePlan(std::string_view text, std::string_view source) {
  std::vector<PlannedProbe> probes;
  for (Statement& s : statements(text, source)) {
    if (s.words[0] != "probe") s.fail("unknown statement '" + s.words[0] + "' (expected probe)");
    PlannedProbe p;
    if (s.words.size() > 1) p.needle = s.words[1];
    p.pose = s.frame();
    p.line = s.line;
    s.finish(2, "probe NEEDLE xyz=X,Y,Z rpy=R,P,Y");
    probes.push_back(std::move(p));
  }
  if (probes.empty()) throw std::invalid_argument(std::string(source) + ": no probe pose planned");
  return probes;
}

const TableVocabulary& puncturingVocabulary() {
  static const TableVocabulary vocabulary{{"needle", "probe"},
                                          {"entry", "target", "probe", "next_entry", "next_target", "next_probe"}};
  return vocabulary;
}

StateTable parseStateTable(std::string_view text, std::string_view source) {
  return parseStateTable(text, source, puncturingVocabulary());
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
      if (row.needle.size() > 1 && row.probe.size() > 1)
        s.fail("both arms list alternatives (A|B); list them for one arm, the other's goal is the same for each");
      std::vector<const Datum*> datums;
      for (const std::vector<Datum>* arm : {&row.needle, &row.probe})
        for (const Datum& d : *arm) datums.push_back(&d);
      for (const Datum* d : {&row.then_needle, &row.then_probe, &row.room_for_needle.from, &row.room_for_needle.to,
                             &row.room_for_probe.from, &row.room_for_probe.to})
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

SurgeonScript parseSurgeonScript(std::string_view text, std::string_view source) {
  SurgeonScript script;
  const auto& known = surgeonEvents();
  for (Statement& s : statements(text, source)) {
    SurgeonAction a;
    a.line = s.line;
    if (s.words[0] == "at") {
      a.trigger = SurgeonAction::Trigger::At;
      if (s.words.size() != 3) s.fail("expected 'at SECONDS EVENT'");
      a.at = s.parseNumber("at", s.words[1], "s");
      if (a.at < 0.0) s.fail("time " + s.words[1] + " s is negative");
      a.event = s.words[2];
      s.finish(3, "at SECONDS EVENT");
    } else if (s.words[0] == "on") {
      a.trigger = SurgeonAction::Trigger::OnState;
      if (s.words.size() != 3) s.fail("expected 'on CHART.STATE EVENT [after=S] [times=N]'");
      const std::string& path = s.words[1];
      const std::size_t dot = path.find('.');
      a.chart = path.substr(0, dot);
      if (a.chart != "needle" && a.chart != "us") s.fail("chart '" + a.chart + "' is neither needle nor us");
      if (dot == std::string::npos || dot + 1 == path.size()) s.fail("'" + path + "' names no state after the chart");
      a.state = path.substr(dot + 1);
      a.after = s.number("after", 0.0, "s");
      if (a.after < 0.0) s.fail("after = " + s.raw("after") + " s is negative");
      const double times = s.number("times", 0.0, "1");
      if (times < 0.0 || times != std::floor(times) || times > 1e6) s.fail("times must be a whole number >= 0");
      a.times = static_cast<int>(times);
      a.event = s.words[2];
      s.finish(3, "on CHART.STATE EVENT [after=S] [times=N]");
    } else {
      s.fail("unknown statement '" + s.words[0] + "' (expected at or on)");
    }
    bool ok = false;
    std::string list;
    for (const std::string& e : known) {
      ok = ok || e == a.event;
      list += (list.empty() ? "" : ", ") + e;
    }
    if (!ok) s.fail("'" + a.event + "' is not a surgeon event (expected one of " + list + ")");
    script.actions.push_back(std::move(a));
  }
  return script;
}

std::string print(const PreoperativeInfo& info) {
  std::ostringstream out;
  out << "abdomen " << frame(info.abdomen_in_task) << "\n";
  out << "tumour center=" << vec(info.tumour_center) << " radius=" << number(info.tumour_radius) << "\n";
  for (const ForbiddenRegion& r : info.forbidden) {
    if (r.a == r.b) {
      out << "sphere " << r.name << " center=" << vec(r.a);
    } else {
      out << "capsule " << r.name << " a=" << vec(r.a) << " b=" << vec(r.b);
    }
    out << " radius=" << number(r.radius) << "\n";
  }
  out << "entry_region center=" << vec(info.entry_center) << " radius=" << number(info.entry_radius) << "\n";
  return out.str();
}

std::string printCryoPlan(const std::vector<PlannedNeedle>& needles) {
  std::string out;
  for (const PlannedNeedle& n : needles) {
    out += "needle " + n.name + " entry=" + vec(n.entry) + " target=" + vec(n.target) + " roll=" + number(n.roll) + "\n";
  }
  return out;
}

std::string printProbePlan(const std::vector<PlannedProbe>& probes) {
  std::string out;
  for (const PlannedProbe& p : probes) out += "probe " + p.needle + " " + frame(p.pose) + "\n";
  return out;
}

std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument(path + ": cannot be read");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace cobra::puncturing
