#pragma once
// The two ends of a dds connection for port type T, and the binding that makes them: templates
// instantiated by registerDdsType<T>() (register_type.hpp). Not part of the API.

#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>

#include <algorithm>
#include <atomic>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

#include "cobra/core/port.hpp"
#include "cobra/core/transport.hpp"
#include "cobra/dds/codec.hpp"
#include "cobra/dds/detail/participant.hpp"
#include "cobra/dds/idl.hpp"

namespace cobra::dds::detail {

template <class T>
eprosima::fastdds::dds::TypeSupport typeSupport() {
  return eprosima::fastdds::dds::TypeSupport(new typename DdsCodec<T>::PubSub());
}

/// The sample an end hands to Fast DDS: the codec's message, converted from or to the port's
/// value; a type that travels as itself (a record) is handed over without a copy.
template <class T, bool Itself = std::is_same_v<typename DdsCodec<T>::Msg, T>>
struct MsgSlot {
  typename DdsCodec<T>::Msg msg;
  void* from(const T& value) {
    DdsCodec<T>::toMsg(value, msg);
    return &msg;
  }
  void* target(T&) { return &msg; }
  void to(T& value) const { DdsCodec<T>::fromMsg(msg, value); }
};
template <class T>
struct MsgSlot<T, true> {
  void* from(const T& value) { return const_cast<T*>(&value); }  // Fast DDS only reads it
  void* target(T& value) { return &value; }
  void to(T&) const {}
};

/// Writer's end: the port writes into the channel to `hidden_`; this end's thread looks every
/// `poll` for what arrived, converts it and publishes it (a write sets `fresh_` and makes no
/// system call: nobody waits on the flag). In lockstep the clock meeting flushes instead.
template <class T>
class WriterEnd final : public core::TransportEnd, public WriterEndHook {
 public:
  WriterEnd(std::shared_ptr<Participant> participant, std::unique_ptr<core::InputPort<T>> hidden,
            eprosima::fastdds::dds::DataWriter* writer, EndpointInfo info)
      : participant_(std::move(participant)), hidden_(std::move(hidden)), writer_(writer), info_(participant_->effective(info)) {
    hidden_->setNewDataFlag(&fresh_);
  }
  ~WriterEnd() override { close(); }

  core::InputPort<T>& hidden() { return *hidden_; }
  void start() {
    participant_->addWriterEnd(this);
    thread_ = std::thread([this] { run(); });
  }

  void close() noexcept override {
    if (writer_ == nullptr) return;
    participant_->removeWriterEnd(this);
    stop_.store(true);
    if (thread_.joinable()) thread_.join();
    participant_->deleteWriter(writer_);
    writer_ = nullptr;
  }

  void flush() noexcept override {
    fresh_.store(false);
    drain();
  }
  std::int64_t published() const noexcept override { return published_.load(); }
  eprosima::fastdds::dds::DataWriter* writer() const noexcept override { return writer_; }
  const EndpointInfo& info() const noexcept override { return info_; }

 private:
  void run() {
    participant_->raiseThisThread();
    const auto poll = participant_->poll();
    while (!stop_.load()) {
      std::this_thread::sleep_for(poll);
      if (participant_->lockstep() || !fresh_.load()) continue;
      fresh_.store(false);  // before draining: a sample written during the drain sets it again
      drain();
    }
  }

  /// Publishes what the channel holds; the thread's poll and a meeting's flush may both call it.
  void drain() noexcept {
    std::lock_guard lock(drain_mutex_);
    while (hidden_->readNew(value_) == core::FlowStatus::NewData) {
      // Keyless types, no dispose: the writer's sequence numbers are its writes, 1, 2, ...
      if (writer_->write(msg_.from(value_))) published_.fetch_add(1);
    }
  }

  std::shared_ptr<Participant> participant_;
  std::unique_ptr<core::InputPort<T>> hidden_;
  eprosima::fastdds::dds::DataWriter* writer_;
  EndpointInfo info_;
  std::mutex drain_mutex_;
  [[no_unique_address]] MsgSlot<T> msg_;  // under drain_mutex_
  T value_{};                  // under drain_mutex_
  std::atomic<std::int64_t> published_{0};
  std::atomic<bool> fresh_{false};
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

/// Reader's end: Fast DDS's listener converts each sample and writes it through `hidden_` into
/// the channel the input port reads; in lockstep it holds the samples until the clock meeting
/// releases them.
template <class T>
class ReaderEnd final : public core::TransportEnd, public eprosima::fastdds::dds::DataReaderListener, public ReaderEndHook {
 public:
  ReaderEnd(std::shared_ptr<Participant> participant, std::unique_ptr<core::OutputPort<T>> hidden, EndpointInfo info)
      : participant_(std::move(participant)), hidden_(std::move(hidden)), info_(participant_->effective(info)) {}
  ~ReaderEnd() override { close(); }

  core::OutputPort<T>& hidden() { return *hidden_; }
  /// Creates the DDS reader once the channel to the input port exists (samples may arrive at once).
  void start() {
    floor_ = participant_->released();
    participant_->addReaderEnd(this);
    reader_ = participant_->createReader(info_, typeSupport<T>(), this);
  }

  void close() noexcept override {
    {
      std::lock_guard lock(mutex_);  // waits for a listener call in progress
      if (closed_) return;
      closed_ = true;
    }
    participant_->removeReaderEnd(this);
    if (reader_ != nullptr) participant_->deleteReader(reader_);
    reader_ = nullptr;
  }

  void on_data_available(eprosima::fastdds::dds::DataReader* reader) override {
    std::lock_guard lock(mutex_);  // Fast DDS may call from several receive threads
    if (closed_) return;
    eprosima::fastdds::dds::SampleInfo info;
    const bool hold = participant_->lockstep();
    while (reader->take_next_sample(msg_.target(value_), &info) == ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data) continue;
      msg_.to(value_);
      const auto& writer = info.sample_identity.writer_guid();
      const auto sequence = info.sample_identity.sequence_number().to64long();
      std::int64_t& highest = received_[writer];  // one node per far writer, on its first sample
      highest = std::max<std::int64_t>(highest, static_cast<std::int64_t>(sequence));
      if (!hold) {
        hidden_->write(value_);
      } else if (const auto floor = floor_.find(writer);
                 floor == floor_.end() || static_cast<std::int64_t>(sequence) > floor->second) {
        held_.push_back({writer, static_cast<std::int64_t>(sequence), value_});
      }
    }
  }

  std::int64_t received(const eprosima::fastrtps::rtps::GUID_t& writer) const override {
    std::lock_guard lock(mutex_);
    const auto it = received_.find(writer);
    return it == received_.end() ? 0 : it->second;
  }

  void release(const std::map<eprosima::fastrtps::rtps::GUID_t, std::int64_t>& bounds) override {
    std::lock_guard lock(mutex_);
    std::erase_if(held_, [&](const Held& h) {
      const auto bound = bounds.find(h.writer);
      if (bound != bounds.end() && h.sequence > bound->second) return false;
      hidden_->write(h.value);
      return true;
    });
  }
  const EndpointInfo& info() const noexcept override { return info_; }

 private:
  struct Held {
    eprosima::fastrtps::rtps::GUID_t writer;
    std::int64_t sequence;
    T value;
  };
  std::shared_ptr<Participant> participant_;
  std::unique_ptr<core::OutputPort<T>> hidden_;
  EndpointInfo info_;
  eprosima::fastdds::dds::DataReader* reader_ = nullptr;
  mutable std::mutex mutex_;
  bool closed_ = false;
  [[no_unique_address]] MsgSlot<T> msg_;
  T value_{};
  std::map<eprosima::fastrtps::rtps::GUID_t, std::int64_t> received_;
  std::vector<Held> held_;  // lockstep: in arrival order
  // Lockstep: per far writer, the samples released before this end existed (never delivered).
  std::map<eprosima::fastrtps::rtps::GUID_t, std::int64_t> floor_;
};

/// How the dds transport makes the ends of a port type: filled by registerDdsType<T>().
struct Binding {
  std::string cobra_type;  ///< the cobra name, "KDL.Frame"
  std::string dds_type;    ///< the DDS type name, "geometry_msgs::msg::dds_::Pose_"
  void (*make_writer)(const std::shared_ptr<Participant>&, core::OutputPortBase&, const core::ConnPolicy&,
                      core::PortBase*, const EndpointInfo&) = nullptr;
  void (*make_reader)(const std::shared_ptr<Participant>&, core::InputPortBase&, const core::ConnPolicy&,
                      core::PortBase*, const EndpointInfo&) = nullptr;
  std::string (*idl)() = nullptr;  ///< a record's IDL (idl.hpp); nullptr for a type carried by a message
};

template <class T>
Binding binding(std::string cobra_type) {
  Binding b;
  b.cobra_type = std::move(cobra_type);
  {
    typename DdsCodec<T>::PubSub support;
    b.dds_type = support.getName();
  }
  if constexpr (core::RecordDataType<T> && std::is_same_v<typename DdsCodec<T>::Msg, T>) b.idl = &idlOf<T>;
  b.make_writer = [](const std::shared_ptr<Participant>& participant, core::OutputPortBase& output,
                     const core::ConnPolicy& policy, core::PortBase* peer, const EndpointInfo& info) {
    std::unique_ptr<core::InputPort<T>> hidden(
        static_cast<core::InputPort<T>*>(output.makeReader("dds:" + info.topic, "writer's end of a dds connection").release()));
    eprosima::fastdds::dds::DataWriter* writer = participant->createWriter(info, typeSupport<T>());
    auto end = std::make_shared<WriterEnd<T>>(participant, std::move(hidden), writer, info);
    core::attachTransportEnd(output, end->hidden(), policy, end, peer);
    end->start();
  };
  b.make_reader = [](const std::shared_ptr<Participant>& participant, core::InputPortBase& input,
                     const core::ConnPolicy& policy, core::PortBase* peer, const EndpointInfo& info) {
    std::unique_ptr<core::OutputPort<T>> hidden(
        static_cast<core::OutputPort<T>*>(input.makeWriter("dds:" + info.topic, "reader's end of a dds connection").release()));
    auto end = std::make_shared<ReaderEnd<T>>(participant, std::move(hidden), info);
    core::attachTransportEnd(input, end->hidden(), policy, end, peer);
    end->start();
  };
  return b;
}

}  // namespace cobra::dds::detail
