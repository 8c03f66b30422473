#include "cobra/run/report.hpp"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

namespace cobra::run {
namespace {

std::string csvField(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

std::string number(double v, const char* format = "%.6g") {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, format, v);
  return buffer;
}

}  // namespace

void TimelineRecorder::observe(double time, const std::string& chart, const std::string& state) {
  const auto it = std::find_if(open_.begin(), open_.end(), [&](const StateInterval& s) { return s.chart == chart; });
  if (it == open_.end()) {
    open_.push_back({chart, state, time, time});
    return;
  }
  if (time < it->begin)
    throw std::invalid_argument("timeline of chart '" + chart + "': time " + number(time) + " s is before " +
                                number(it->begin) + " s; observe in time order");
  if (it->state == state) return;
  closed_.push_back({chart, it->state, it->begin, time});
  *it = {chart, state, time, time};
}

std::vector<StateInterval> TimelineRecorder::intervals(double end_time) const {
  std::vector<StateInterval> all = closed_;
  for (const StateInterval& s : open_) all.push_back({s.chart, s.state, s.begin, std::max(s.begin, end_time)});
  std::stable_sort(all.begin(), all.end(), [](const StateInterval& a, const StateInterval& b) { return a.begin < b.begin; });
  return all;
}

std::vector<std::string> TimelineRecorder::statesEntered(const std::string& chart) const {
  std::vector<std::string> states;
  auto add = [&](const StateInterval& s) {
    if (s.chart == chart && std::find(states.begin(), states.end(), s.state) == states.end()) states.push_back(s.state);
  };
  for (const StateInterval& s : closed_) add(s);
  for (const StateInterval& s : open_) add(s);
  return states;
}

std::string eventLogCsv(const std::vector<EventRecord>& events) {
  std::string out = "time [s],source,event,state\n";
  for (const EventRecord& e : events)
    out += number(e.time, "%.9g") + "," + csvField(e.source) + "," + csvField(e.event) + "," + csvField(e.state) + "\n";
  return out;
}

}  // namespace cobra::run
