#pragma once
/// @file
/// Typed data-flow ports: `OutputPort<T>` writes, `InputPort<T>` reads, through connections
/// that each own a lock-free channel (see channel.hpp). Many readers per writer.

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "cobra/core/channel.hpp"
#include "cobra/core/conn_policy.hpp"
#include "cobra/core/data_type.hpp"
#include "cobra/core/error.hpp"

namespace cobra::core {

class Component;

enum class PortDirection { Input, Output };

/// What every port has: name, documentation, unit, type, direction, owner and connections.
class PortBase {
 public:
  /// Most connections one port can have (fixed so that writing never allocates).
  static constexpr std::size_t kMaxConnections = 32;

  PortBase(std::string name, std::string doc, std::string unit, PortDirection direction, const TypeInfo& type);
  virtual ~PortBase();
  PortBase(const PortBase&) = delete;
  PortBase& operator=(const PortBase&) = delete;

  const std::string& name() const { return name_; }
  const std::string& doc() const { return doc_; }
  /// SI unit of the data ("m", "rad", "N", "1" for dimensionless, "" for logic data).
  const std::string& unit() const { return unit_; }
  PortDirection direction() const { return direction_; }
  const TypeInfo& type() const { return *type_; }
  /// True for an input port whose new data triggers its owner's update.
  bool isEventPort() const { return event_port_; }
  Component* owner() const { return owner_; }
  /// "Owner.port", or just the port name when it belongs to no component.
  std::string fullName() const;

  /// A snapshot of this port's connections.
  std::vector<std::shared_ptr<ChannelBase>> connections() const;
  bool connected() const;
  bool connectedTo(const PortBase& other) const;
  /// Removes every connection of this port (between steps of both owners).
  void disconnect();
  /// Tells the owner that new data arrived on this event port. Real-time safe.
  void notifyNewData() noexcept;
  /// For an input port that belongs to no component (an observer's reader, e.g. the runner's event
  /// log): makes it an event port whose new data sets `*flag` (release) instead of waking an owner,
  /// so that the observer reads its ports only after a flag was set rather than polling each at
  /// every step. `flag` must outlive the port's connections. Call before connecting.
  void setNewDataFlag(std::atomic<bool>* flag) noexcept {
    new_data_flag_ = flag;
    event_port_ = true;
  }
  /// Input side: one more sample was pushed into one of this port's buffered (buffer, circular)
  /// connections. A reader whose scan found them all empty scans again only once this count
  /// changed (an event port with many writers, e.g. a supervisor's, is mostly empty). Real-time
  /// safe; called by the writer after the push.
  void countBufferedWrite() noexcept { buffered_writes_.fetch_add(1, std::memory_order_release); }

 protected:
  /// Adds/removes a channel in the list the real-time path iterates; only ever called
  /// between two steps of the owner (see `changeBetweenSteps`).
  virtual void attachChannel(ChannelBase& channel) = 0;
  virtual void detachChannel(ChannelBase& channel) = 0;
  /// Runs `change` when the owner's activity is between two steps (now, when no thread steps it).
  void changeBetweenSteps(const std::function<void()>& change);

 private:
  friend class Component;
  friend void linkChannel(const std::shared_ptr<ChannelBase>& channel);
  friend void unlinkChannel(const std::shared_ptr<ChannelBase>& channel);

  std::string name_;
  std::string doc_;
  std::string unit_;
  PortDirection direction_;
  const TypeInfo* type_;
  bool event_port_ = false;
  Component* owner_ = nullptr;
  std::atomic<bool>* new_data_flag_ = nullptr;  // see setNewDataFlag

 protected:
  std::atomic<std::uint64_t> buffered_writes_{0};  // see countBufferedWrite

 private:
  mutable std::mutex links_mutex_;
  std::vector<std::shared_ptr<ChannelBase>> links_;
};

/// Registers `channel` with both its ports (checked by the caller), reader side first.
void linkChannel(const std::shared_ptr<ChannelBase>& channel);
/// Removes `channel` from both its ports, writer side first.
void unlinkChannel(const std::shared_ptr<ChannelBase>& channel);

/// Input side of a typed port, type-erased: what the console, reporter and scripts read.
class OutputPortBase;

class InputPortBase : public PortBase {
 public:
  using PortBase::PortBase;
  /// Reads like `InputPort<T>::read` and gives the value in its type's text form (empty on
  /// NoData). Not real-time safe (formats text).
  virtual FlowStatus readText(std::string& text) = 0;
  /// A new output port of this port's type (not owned by any component), e.g. for a console
  /// that writes samples or events into this input. Connect it with `connectTo`.
  virtual std::unique_ptr<OutputPortBase> makeWriter(std::string name, std::string doc) const = 0;
};

/// Output side of a typed port; type-erased entry point for the deployer, console and tools.
class OutputPortBase : public PortBase {
 public:
  using PortBase::PortBase;
  /// Connects this output to `input` with `policy`, in this process whatever `policy.transport`
  /// says (`connectPorts` honours it).
  /// @throws Error naming both ports when `input` is not an input port, the types differ, they
  /// are already connected, or a port has too many connections.
  virtual void connectTo(PortBase& input, ConnPolicy policy) = 0;
  /// A new input port of this port's type (not owned by any component), e.g. for a reporter or
  /// a console that wants to read this output. Connect it with `connectTo`.
  virtual std::unique_ptr<InputPortBase> makeReader(std::string name, std::string doc) const = 0;
  /// Parses `text` with the type's text form and writes it. Not real-time safe.
  /// @throws Error naming the port, the text and the expected form.
  virtual WriteStatus writeText(std::string_view text) = 0;
};

/// Connects `output` to `input` (any order of checks is reported as one clear message). A policy
/// that names a transport carries the connection through it (transport.hpp).
void connectPorts(PortBase& output, PortBase& input, ConnPolicy policy = ConnPolicy::data());
/// Removes the connection between `output` and `input` (both ends of one made through a
/// transport); returns false when there was none.
bool disconnectPorts(PortBase& output, PortBase& input);

namespace detail {
/// Fixed-capacity list of channels iterated on the real-time path.
template <class T>
class ChannelList {
 public:
  bool add(Channel<T>* channel) {
    if (count_ == items_.size()) return false;
    items_[count_++] = channel;
    return true;
  }
  void remove(const ChannelBase* channel) {
    for (std::size_t i = 0; i < count_; ++i) {
      if (items_[i] == channel) {
        for (std::size_t j = i + 1; j < count_; ++j) items_[j - 1] = items_[j];
        items_[--count_] = nullptr;
        return;
      }
    }
  }
  std::size_t size() const { return count_; }
  Channel<T>* operator[](std::size_t i) const { return items_[i]; }

 private:
  std::array<Channel<T>*, PortBase::kMaxConnections> items_{};
  std::size_t count_ = 0;
};
}  // namespace detail

template <RegisteredDataType T>
class InputPort;

/// Writes samples of T to every connected input. `write` is real-time safe: lock-free, no
/// allocation once the channels' slots have the data's size (see `setDataSample`).
template <RegisteredDataType T>
class OutputPort final : public OutputPortBase {
 public:
  /// @param unit SI unit of the data, documented on every port ("1" when dimensionless).
  OutputPort(std::string name, std::string doc, std::string unit, T sample = T{})
      : OutputPortBase(std::move(name), std::move(doc), std::move(unit), PortDirection::Output, typeInfo<T>()),
        sample_(std::move(sample)) {}
  ~OutputPort() override { disconnect(); }

  /// Value used to preallocate the slots of connections made from now on: give it the size of
  /// the data (e.g. a 6-element vector) so that writes never allocate.
  void setDataSample(const T& sample) { sample_ = sample; }

  /// True while some connection reads this port. Real-time safe (lock-free, unlike connected()):
  /// for the owner's update, as write(), since connections change only between its steps. A
  /// writer whose samples are costly to make (a rendered image) makes them only while read.
  bool hasReaders() const noexcept { return channels_.size() != 0; }

  WriteStatus write(const T& value) {
    if (channels_.size() == 0) return WriteStatus::NotConnected;
    WriteStatus status = WriteStatus::Written;
    for (std::size_t i = 0; i < channels_.size(); ++i) {
      Channel<T>& channel = *channels_[i];
      if (channel.push(value) == WriteStatus::Dropped) {
        status = WriteStatus::Dropped;
        continue;
      }
      if (channel.policy().kind != ConnPolicy::Kind::Data) channel.reader().countBufferedWrite();
      if (channel.reader().isEventPort()) channel.reader().notifyNewData();
    }
    return status;
  }

  void connectTo(PortBase& input, ConnPolicy policy) override;
  std::unique_ptr<InputPortBase> makeReader(std::string name, std::string doc) const override;
  WriteStatus writeText(std::string_view text) override {
    T value = sample_;
    if (!DataTypeTraits<T>::parse(text, value))
      throw Error("port " + fullName() + " is a " + std::string(type().name) + ": cannot write \"" + std::string(text) +
                  "\"; expected " + std::string(type().format));
    return write(value);
  }

 protected:
  void attachChannel(ChannelBase& channel) override {
    channels_.add(static_cast<Channel<T>*>(&channel));
  }
  void detachChannel(ChannelBase& channel) override { channels_.remove(&channel); }

 private:
  T sample_;
  detail::ChannelList<T> channels_;
};

/// Reads samples of T from its connections. `read` is real-time safe.
template <RegisteredDataType T>
class InputPort final : public InputPortBase {
 public:
  /// @param unit SI unit of the data, documented on every port ("1" when dimensionless).
  InputPort(std::string name, std::string doc, std::string unit)
      : InputPortBase(std::move(name), std::move(doc), std::move(unit), PortDirection::Input, typeInfo<T>()) {}
  ~InputPort() override { disconnect(); }

  /// Copies the next unread sample into `out` (NewData). Otherwise copies the last sample read
  /// again (OldData), or leaves `out` as it is when nothing ever arrived (NoData). With several
  /// connections, the first one in connection order that has unread data is read.
  FlowStatus read(T& out) {
    if (popNew(out)) return FlowStatus::NewData;
    return last_ == nullptr ? FlowStatus::NoData : last_->pop(out, true);
  }

  /// As `read`, but copies only a new sample: `out` is left as it is on OldData too. For readers
  /// that act on new samples only (an event log), where read's copy of the last sample again at
  /// every step is wasted. Real-time safe.
  FlowStatus readNew(T& out) {
    if (popNew(out)) return FlowStatus::NewData;
    return last_ == nullptr ? FlowStatus::NoData : FlowStatus::OldData;
  }

  FlowStatus readText(std::string& text) override {
    T value{};
    const FlowStatus status = read(value);
    text = status == FlowStatus::NoData ? std::string() : DataTypeTraits<T>::print(value);
    return status;
  }

  std::unique_ptr<OutputPortBase> makeWriter(std::string name, std::string doc) const override;

 protected:
  void attachChannel(ChannelBase& channel) override {
    if (channels_.add(static_cast<Channel<T>*>(&channel)) && channel.policy().kind == ConnPolicy::Kind::Data)
      ++data_channels_;
    quiet_known_ = false;
  }
  void detachChannel(ChannelBase& channel) override {
    for (std::size_t i = 0; i < channels_.size(); ++i) {
      if (channels_[i] != &channel) continue;
      if (channel.policy().kind == ConnPolicy::Kind::Data) --data_channels_;
      channels_.remove(&channel);
      break;
    }
    if (last_ == &channel) last_ = nullptr;
  }

 private:
  /// Pops the next new sample of the first connection that has one. When every connection is
  /// buffered, a scan that found them all empty is remembered with the write count it started
  /// from: until a writer pushes again (the count changes), there is nothing to scan for.
  bool popNew(T& out) {
    const bool counted = data_channels_ == 0;
    const std::uint64_t writes = counted ? buffered_writes_.load(std::memory_order_acquire) : 0;
    if (counted && quiet_known_ && writes == quiet_at_) return false;
    for (std::size_t i = 0; i < channels_.size(); ++i) {
      if (channels_[i]->pop(out, false) == FlowStatus::NewData) {
        last_ = channels_[i];
        return true;
      }
    }
    // A push counted after `writes` was loaded changes the count: the next call scans again.
    quiet_at_ = writes;
    quiet_known_ = counted;
    return false;
  }

  detail::ChannelList<T> channels_;
  Channel<T>* last_ = nullptr;
  std::size_t data_channels_ = 0;  // connections of the data policy (not counted by buffered_writes_)
  std::uint64_t quiet_at_ = 0;     // buffered_writes_ when a scan last found nothing
  bool quiet_known_ = false;
};

/// Throws the error for an impossible connection; defined in port.cpp.
[[noreturn]] void throwConnectionError(const PortBase& output, const PortBase& input, const std::string& why);
/// Checks everything but the types (direction, duplicates, capacity); throws Error.
void checkConnectable(const PortBase& output, const PortBase& input);

template <RegisteredDataType T>
void OutputPort<T>::connectTo(PortBase& input, ConnPolicy policy) {
  checkConnectable(*this, input);
  auto* typed = dynamic_cast<InputPort<T>*>(&input);
  if (typed == nullptr)
    throwConnectionError(*this, input,
                         "the types differ (" + std::string(type().name) + " vs " +
                             std::string(input.type().name) + "); connect ports of the same type");
  linkChannel(std::make_shared<Channel<T>>(policy, *this, *typed, sample_));
}

template <RegisteredDataType T>
std::unique_ptr<InputPortBase> OutputPort<T>::makeReader(std::string name, std::string doc) const {
  return std::make_unique<InputPort<T>>(std::move(name), std::move(doc), unit());
}

template <RegisteredDataType T>
std::unique_ptr<OutputPortBase> InputPort<T>::makeWriter(std::string name, std::string doc) const {
  return std::make_unique<OutputPort<T>>(std::move(name), std::move(doc), unit());
}

/// Typed convenience: `connect(gen.out, gain.in, ConnPolicy::buffer(8))`.
template <RegisteredDataType T>
void connect(OutputPort<T>& output, InputPort<T>& input, ConnPolicy policy = ConnPolicy::data()) {
  connectPorts(output, input, std::move(policy));
}

}  // namespace cobra::core
