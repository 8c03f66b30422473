#include "cobra/components/reporting/reporter.hpp"

#include <algorithm>

#include "file_writer.hpp"
#include "row_queue.hpp"
#include "source.hpp"

namespace cobra::components {

using reporting_detail::FileWriter;
using reporting_detail::RowQueue;
using reporting_detail::RowWriter;
using reporting_detail::Source;

Reporter::Reporter(std::string name)
    : Component(std::move(name), core::Role::Bridge, "Records output ports of other components to a CSV file"),
      file_path_("file_path", this->name() + ".csv", "",
                 "CSV file written at configure (truncated; relative paths from the working directory)") {
  addProperty(file_path_);
  addProperty(queue_rows_.range(1, 1'000'000));
  addProperty(flush_period_.range(0.0, 3600.0));
  addProperty(rows_dropped_.readOnly());
}

Reporter::~Reporter() {
  if (isRunning()) (void)stop();
}

std::string Reporter::where() const { return "component '" + name() + "'"; }

std::string Reporter::notPreOperational() const {
  const core::State s = state();
  return "the reporter is " + std::string(core::toString(s)) + "; report ports before configure (" +
         (s == core::State::Running   ? "stop and clean it up first" :
          s == core::State::Stopped   ? "clean it up first" :
          s == core::State::Exception ? "recover it first" :
                                        "make a new Reporter") +
         ")";
}

void Reporter::refuse(const core::PortBase& output, const std::string& why) const {
  throw core::Error(where() + ": cannot report " + output.fullName() + ": " + why);
}

void Reporter::reportPort(core::PortBase& port, std::size_t elements) {
  if (state() != core::State::PreOperational)
    refuse(port, notPreOperational());
  auto* output = dynamic_cast<core::OutputPortBase*>(&port);
  if (port.direction() != core::PortDirection::Output || output == nullptr)
    refuse(port, "it is an input port; report the output port that writes it");
  for (const auto& source : sources_)
    if (&source->output() == output) refuse(port, "it is already reported; report each port once");

  // The reader belongs to the Reporter, so the runtime changes its connections only between
  // two updates of the Reporter (never while updateHook reads it).
  std::string reader_name = output->fullName();
  std::replace(reader_name.begin(), reader_name.end(), '.', ':');
  if (findPort(reader_name) != nullptr)
    refuse(port, "the reporter already has a port named '" + reader_name + "'; rename one of the components or ports");
  std::unique_ptr<Source> source;
  try {
    source = reporting_detail::makeSource(*output, std::move(reader_name), elements);
  } catch (const core::Error& e) {
    refuse(port, e.what());
  }
  try {
    output->connectTo(source->reader(), core::ConnPolicy::data());
  } catch (const core::Error& e) {
    refuse(port, std::string("the connection was refused: ") + e.what());
  }
  sources_.reserve(sources_.size() + 1);  // so nothing can throw once the port is registered
  addPort(source->reader());
  sources_.push_back(std::move(source));
}

void Reporter::reportPort(const core::ComponentRegistry& registry, std::string_view path, std::size_t elements) {
  const auto dot = path.find('.');
  if (dot == std::string_view::npos || dot == 0 || dot + 1 == path.size())
    throw core::Error(where() + ": cannot report \"" + std::string(path) +
                      "\": name the port as Component.port, e.g. Sine.out");
  core::Component& component = registry.get(path.substr(0, dot));
  reportPort(component.port(path.substr(dot + 1)), elements);
}

void Reporter::reportComponent(core::Component& component, bool include_events, std::string* left_out) {
  const std::string what = "cannot report component '" + component.name() + "'";
  if (state() != core::State::PreOperational)
    throw core::Error(where() + ": " + what + ": " + notPreOperational());
  std::vector<core::PortBase*> chosen;
  std::string need_length;
  for (core::PortBase* port : component.ports()) {
    if (port->direction() != core::PortDirection::Output) continue;
    if (port == &component.events() && !include_events) continue;
    const bool reported = std::any_of(sources_.begin(), sources_.end(),
                                      [&](const auto& source) { return &source->output() == port; });
    if (reported) continue;
    if (reporting_detail::needsLength(port->type())) {
      need_length += (need_length.empty() ? "" : ", ") + (left_out != nullptr ? component.name() + "." : "") +
                     port->name() + " (" + std::string(port->type().name) + ")";
      continue;
    }
    chosen.push_back(port);
  }
  if (left_out != nullptr) *left_out = need_length;
  if (!need_length.empty() && left_out == nullptr)
    throw core::Error(where() + ": " + what + ": the length of " + need_length +
                      " is not part of its type; report it first with reportPort(port, number of elements)");
  if (chosen.empty())
    throw core::Error(where() + ": " + what + ": it has no output port left to report" +
                      (include_events ? "" : " (its events port is reported only with include_events = true)"));
  for (core::PortBase* port : chosen) reportPort(*port);
}

std::vector<std::string> Reporter::columns() const {
  std::vector<std::string> headers = {"time [s]"};
  for (const auto& source : sources_) headers.insert(headers.end(), source->headers().begin(), source->headers().end());
  return headers;
}

std::vector<std::string> Reporter::reportedPorts() const {
  std::vector<std::string> paths;
  for (const auto& source : sources_) paths.push_back(source->path());
  return paths;
}

bool Reporter::configureHook() {
  if (sources_.empty()) throw core::Error("no ports to report; call reportPort or reportComponent before configure");
  writer_.reset();  // closes the file of an earlier configuration
  queue_.reset();
  auto writer = std::make_unique<FileWriter>(file_path_());
  std::string header;
  for (const std::string& cell : columns()) header += (header.empty() ? "" : ",") + cell;
  writer->writeNow(header + "\n");
  std::size_t row_bytes = RowWriter::kMaxTimeBytes + 1;  // + the newline
  for (const auto& source : sources_) row_bytes += source->maxBytes();
  queue_ = std::make_unique<RowQueue>(static_cast<std::size_t>(queue_rows_()), row_bytes);
  writer_ = std::move(writer);
  rows_dropped_.setFromOwner(0);
  return true;
}

bool Reporter::startHook() {
  const auto period = std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::duration<double>(flush_period_()));
  writer_->start(*queue_, period);
  return true;
}

void Reporter::updateHook() {
  // Every port is read at every update, so that each keeps its latest value for later rows.
  bool fresh = false;
  for (const auto& source : sources_) fresh = (source->sample() == core::FlowStatus::NewData) || fresh;
  if (!fresh) return;
  char* buffer = queue_->beginRow();
  if (buffer == nullptr) {  // the writer thread is behind: drop rather than wait
    rows_dropped_.setFromOwner(rows_dropped_() + 1);
    return;
  }
  RowWriter row(buffer, queue_->rowBytes());
  row.time(now());
  for (const auto& source : sources_) source->format(row);
  row.endLine();
  queue_->commitRow(row.size());
}

void Reporter::stopHook() {
  // The activity no longer steps the update here, so the queue gets nothing new: the writer
  // thread drains it completely, flushes, and ends.
  if (writer_) writer_->stop();
}

void Reporter::cleanupHook() {
  writer_.reset();
  queue_.reset();
}

}  // namespace cobra::components
