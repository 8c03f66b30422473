// The text formats of the puncturing data (apps/puncturing/README.md): one statement per line,
// `#` starts a comment, words separated by blanks, parameters as key=value, vectors as X,Y,Z.
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "cobra/puncturing/plan.hpp"

namespace cobra::puncturing {
namespace {

using task::Statement;
using task::statements;

std::string number(double value) { return task::printNumber(value); }
std::string vec(const KDL::Vector& v) { return task::printVector(v); }
std::string frame(const KDL::Frame& f) { return task::printFrame(f); }

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

}  // namespace cobra::puncturing
