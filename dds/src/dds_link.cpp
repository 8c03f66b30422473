#include "cobra/dds/dds_link.hpp"

#include <fastdds/dds/core/status/LivelinessChangedStatus.hpp>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>

#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <filesystem>
#include <iostream>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

#include "cobra/core/error.hpp"
#include "cobra/core/lockstep_clock.hpp"
#include "cobra/text/number.hpp"
#include "cobra_msgs/msg/LinkMeetingPubSubTypes.h"
#include "event_queue.hpp"
#include "cobra/dds/detail/participant.hpp"

namespace cobra::dds {
namespace fdds = eprosima::fastdds::dds;
namespace rtps = eprosima::fastrtps::rtps;
using Clock = std::chrono::steady_clock;

namespace {

constexpr const char* kMeetingTopic = "rt/cobra/link";
constexpr const char* kMeetingType = "cobra_msgs::msg::dds_::LinkMeeting_";
/// Announcement stamps that are not instants: the hello when a link starts, and the farewell of
/// a wall-clock link that leaves (done = true when its run completed: its peers record it done;
/// false when it left otherwise, on an error or a safe stop: its peers lose it at once).
constexpr std::int64_t kHello = -1;
constexpr std::int64_t kFarewell = -2;

/// "a, b,c" -> {"a", "b", "c"}.
std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    const auto first = item.find_first_not_of(" \t");
    if (first == std::string::npos) continue;
    out.push_back(item.substr(first, item.find_last_not_of(" \t") - first + 1));
  }
  return out;
}

eprosima::fastrtps::Duration_t duration(double seconds) {
  return eprosima::fastrtps::Duration_t(static_cast<long double>(seconds));
}

std::string text(const rtps::GUID_t& guid) {
  std::ostringstream out;
  out << guid;
  return out.str();
}

/// A meeting period for messages: "1 ms", "every instant" for 0.
std::string periodText(std::int64_t period_ns) {
  return period_ns == 0 ? std::string("instant") : text::number(static_cast<double>(period_ns) * 1e-6) + " ms";
}

/// The DdsLink of this process whose participant the "dds" transport uses.
struct Current {
  std::mutex mutex;
  const DdsLink* link = nullptr;
  std::shared_ptr<DdsTransport> transport;
};
Current& current() {
  static Current c;
  return c;
}

}  // namespace

/// The meeting topic's writer and reader, what the peers announced, and their liveliness.
class DdsLink::Meeting final : public fdds::DataReaderListener {
 public:
  struct Settings {
    std::string self;
    std::vector<std::string> peers;
    double lease;
    double join_timeout;
    double meeting_timeout;  ///< s, > 0
    std::int64_t period_ns;  ///< meets at the instants that are multiples of it; 0: at every one
    double lapse_grace;      ///< s a lapsed peer's liveliness may take to come back; 0: lost at once
  };

  Meeting(DdsLink& link, detail::Participant& participant, Settings settings)
      : link_(link), participant_(participant), settings_(std::move(settings)), started_(Clock::now()) {
    for (const auto& name : settings_.peers) peers_[name];
    type_ = fdds::TypeSupport(new cobra_msgs::msg::LinkMeetingPubSubType());
    fdds::DomainParticipant* p = participant_.entity();
    if (p->find_type(kMeetingType).empty() && type_.register_type(p) != ReturnCode_t::RETCODE_OK)
      throw core::Error(std::string("cannot register the DDS type ") + kMeetingType);
    topic_ = p->create_topic(kMeetingTopic, kMeetingType, fdds::TOPIC_QOS_DEFAULT);
    if (topic_ == nullptr) throw core::Error(std::string("cannot create the DDS topic ") + kMeetingTopic);

    // Reliable, and kept for a peer that joins late (its first meeting still sees the last ones).
    // AUTOMATIC liveliness: Fast DDS asserts it every lease/4 from its own thread, whatever the
    // components do.
    fdds::DataWriterQos wq = participant_.publisher()->get_default_datawriter_qos();
    wq.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
    wq.durability().kind = fdds::TRANSIENT_LOCAL_DURABILITY_QOS;
    wq.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
    wq.history().depth = 16;
    wq.liveliness().kind = fdds::AUTOMATIC_LIVELINESS_QOS;
    wq.liveliness().lease_duration = duration(settings_.lease);
    wq.liveliness().announcement_period = duration(settings_.lease / 4);
    wq.reliable_writer_qos().times.heartbeatPeriod = duration(0.002);  // a lost announcement stalls a meeting this long
    wq.reliable_writer_qos().times.initialHeartbeatDelay = duration(0.001);
    wq.reliable_writer_qos().times.nackResponseDelay = duration(0.001);
    writer_ = participant_.publisher()->create_datawriter(topic_, wq, nullptr, fdds::StatusMask::none());
    fdds::DataReaderQos rq = participant_.subscriber()->get_default_datareader_qos();
    rq.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
    rq.durability().kind = fdds::TRANSIENT_LOCAL_DURABILITY_QOS;
    rq.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
    rq.history().depth = 16;
    rq.liveliness().kind = fdds::AUTOMATIC_LIVELINESS_QOS;
    // Fast DDS checks each writer's liveliness against the reader's lease: the processes of
    // one run use one lease (a writer offering a longer one than a reader requests never matches).
    rq.liveliness().lease_duration = duration(settings_.lease);
    rq.reliable_reader_qos().times.heartbeatResponseDelay = duration(0.001);
    reader_ = participant_.subscriber()->create_datareader(
        topic_, rq, this, fdds::StatusMask::data_available() << fdds::StatusMask::liveliness_changed());
    if (writer_ == nullptr || reader_ == nullptr) {
      close();
      throw core::Error(std::string("Fast DDS refused the writer or reader of ") + kMeetingTopic);
    }
    if (settings_.lapse_grace > 0.0) confirmer_ = std::thread([this] { confirmLapses(); });
  }

  /// The hello: peers learn this process's name and reader ends before its first instant.
  void hello() {
    started_ = Clock::now();
    greeted_ = true;
    announce(kHello, false);
  }

  ~Meeting() override { close(); }

  void close() noexcept {
    stopConfirming();
    fdds::DomainParticipant* p = participant_.entity();
    // Wall clock: no meeting says when a peer is done, so the farewell says it, before the
    // writer goes: done when this process's run completed (setDone(true)), else not (an error, a
    // safe stop, a time limit), and its peers lose it without waiting for its liveliness to
    // lapse. A lockstep link's peers learn it at the meetings (setDone), and keep that path alone.
    if (writer_ != nullptr && greeted_ && !participant_.lockstep()) {
      try {
        announce(kFarewell, done_.load());
      } catch (const std::exception& e) {
        std::cerr << "cobra dds: participant '" << settings_.self << "' could not say farewell: " << e.what() << std::endl;
      }
    }
    // The peers may still need a retransmission of the last announcement (a lost packet is
    // resent within ms); a lost peer never acknowledges, hence the bound.
    if (writer_ != nullptr) writer_->wait_for_acknowledgments(duration(std::min(settings_.lease, 0.2)));
    {
      std::lock_guard lock(callback_mutex_);  // waits for a listener call in progress
      closed_ = true;
    }
    if (reader_ != nullptr) {
      reader_->set_listener(nullptr);
      participant_.subscriber()->delete_datareader(reader_);
    }
    if (writer_ != nullptr) participant_.publisher()->delete_datawriter(writer_);
    if (topic_ != nullptr) p->delete_topic(topic_);
    reader_ = nullptr;
    writer_ = nullptr;
    topic_ = nullptr;
  }

  void setDone(bool done) {
    done_.store(done);
    std::lock_guard lock(mutex_);
    if (!done) told_done_ = false;
  }

  bool peersDone() const {
    std::lock_guard lock(mutex_);
    // Leaving before this process's done was told would leave a peer waiting for it to find it
    // lost; with every peer lost, nobody waits.
    const bool all_lost = std::all_of(peers_.begin(), peers_.end(), [](const auto& p) { return p.second.lost; });
    return (told_done_ || all_lost) &&
           std::all_of(peers_.begin(), peers_.end(), [](const auto& p) { return p.second.lost || p.second.done; });
  }

  std::vector<std::string> lost() const {
    std::lock_guard lock(mutex_);
    return lost_;
  }

  std::vector<std::string> joined() const {
    std::lock_guard lock(mutex_);
    return joined_;
  }

  void reached(std::chrono::nanoseconds t) {
    if (settings_.period_ns > 0 && t.count() % settings_.period_ns != 0) return;  // not a meeting instant
    std::vector<cobra_msgs::msg::LinkWriter> writers;
    flushWriters(writers);
    const bool done = done_.load();
    announce(t.count(), done, std::move(writers));
    waitForPeers(t.count());
    if (done) {
      std::lock_guard lock(mutex_);
      told_done_ = true;
    }
  }

  // DataReaderListener: the peers' announcements and liveliness (Fast DDS's threads).
  void on_data_available(fdds::DataReader* reader) override {
    std::lock_guard closing(callback_mutex_);
    if (closed_) return;
    takeAnnouncements(reader);
  }

  void on_liveliness_changed(fdds::DataReader*, const fdds::LivelinessChangedStatus& status) override {
    std::lock_guard closing(callback_mutex_);
    if (closed_ || status.alive_count_change == 0) return;
    if (status.alive_count_change > 0) {  // asserted again: a lapse within the grace was a stall
      std::lock_guard lock(mutex_);
      if (const auto it = names_.find(text(rtps::iHandle2GUID(status.last_publication_handle))); it != names_.end())
        lapsed_.erase(it->second);
      return;
    }
    // A peer that said farewell was acknowledged before its writer went: Fast DDS calls
    // on_data_available from the thread that received the farewell, before it acknowledges it, so
    // the peer is done here already. (Samples are not taken here: this callback comes from Fast
    // DDS's liveliness machinery, whose locks this code does not know.)
    // Lapsed (killed, unreachable) or its writer gone (the process left): lost, unless it said
    // it was done.
    const std::string guid = text(rtps::iHandle2GUID(status.last_publication_handle));
    std::string name;
    {
      std::lock_guard lock(mutex_);
      if (auto it = names_.find(guid); it != names_.end()) name = it->second;
    }
    if (name.empty()) name = participant_.participantName(rtps::iHandle2GUID(status.last_publication_handle).guidPrefix);
    if (name.empty()) return;
    if (settings_.lapse_grace <= 0.0) return lose(name, "its liveliness lapsed");
    std::lock_guard lock(mutex_);
    lapsed_.emplace(name, Clock::now());  // confirmed by confirmLapses unless it comes back
  }

 private:
  struct Peer {
    bool seen = false;  // its hello (or a meeting) arrived
    std::vector<std::string> readers;  // "topic|type" of its reader ends, as it last said
    bool lost = false;
    bool done = false;
    Clock::time_point heard{};
    struct Announced {
      bool done;
      std::vector<cobra_msgs::msg::LinkWriter> writers;
    };
    std::map<std::int64_t, Announced> announced;  // by instant (ns)
  };

  /// Takes the announcements `reader` holds; called under callback_mutex_.
  void takeAnnouncements(fdds::DataReader* reader) {
    cobra_msgs::msg::LinkMeeting sample;
    fdds::SampleInfo info;
    std::vector<std::string> joined;
    std::vector<std::pair<std::string, std::string>> losses;  // name, why
    {
      std::lock_guard lock(mutex_);
      while (reader->take_next_sample(&sample, &info) == ReturnCode_t::RETCODE_OK) {
        if (!info.valid_data || sample.participant() == settings_.self) continue;
        names_[text(info.sample_identity.writer_guid())] = sample.participant();
        const auto peer = peers_.find(sample.participant());
        if (peer == peers_.end()) continue;  // a process of another run on this domain
        Peer& p = peer->second;
        if (sample.period_ns() != settings_.period_ns && !p.lost) {
          // Each would wait at instants the other never meets at: refuse the peer at once.
          losses.emplace_back(sample.participant(),
                              "it meets every " + periodText(sample.period_ns()) + ", participant '" +
                                  settings_.self + "' every " + periodText(settings_.period_ns) +
                                  ": give both DdsLinks the same meeting_period");
          continue;
        }
        p.heard = Clock::now();
        if (!p.seen) joined.push_back(sample.participant()), joined_.push_back(sample.participant());
        p.seen = true;
        p.readers = sample.readers();
        if (sample.stamp_ns() >= 0) p.announced[sample.stamp_ns()] = {sample.done(), sample.writers()};
        if (sample.stamp_ns() == kFarewell && sample.done()) p.done = true;  // its run completed
        if (sample.stamp_ns() == kFarewell && !sample.done() && !p.done)
          losses.emplace_back(sample.participant(), "it left before its run completed (its link's farewell said "
                                                    "not done: an error, a safe stop or a time limit there)");
      }
    }
    changed_.notify_all();
    for (const auto& name : joined) link_.emit("e_peer_joined", name);
    for (const auto& [name, why] : losses) lose(name, why);
  }

  void announce(std::int64_t stamp, bool done, std::vector<cobra_msgs::msg::LinkWriter> writers = {}) {
    cobra_msgs::msg::LinkMeeting sample;
    sample.participant(settings_.self);
    sample.stamp_ns(stamp);
    sample.done(done);
    sample.period_ns(settings_.period_ns);
    sample.writers(std::move(writers));
    participant_.withEnds([&](const auto&, const std::vector<detail::ReaderEndHook*>& readers) {
      for (const detail::ReaderEndHook* r : readers) sample.readers().push_back(r->info().topic + "|" + r->info().type_name);
    });
    writer_->write(&sample);
  }

  /// Sends what every writer end holds, first waiting (at most join_timeout from the link's
  /// start) until it is matched with the readers the peers said they have on its topic: a
  /// sample sent before would be lost. The first time, waits for every peer's hello.
  void flushWriters(std::vector<cobra_msgs::msg::LinkWriter>& announced) {
    const auto deadline = started_ + std::chrono::duration_cast<Clock::duration>(
                                         std::chrono::duration<double>(settings_.join_timeout));
    while (Clock::now() < deadline && !allSeen()) std::this_thread::sleep_for(std::chrono::microseconds(200));
    participant_.withEnds([&](const std::vector<detail::WriterEndHook*>& writers, const auto&) {
      for (detail::WriterEndHook* w : writers) {
        const detail::EndpointInfo& info = w->info();
        const int expected = readersOf(info.topic + "|" + info.type_name);
        for (;;) {
          fdds::PublicationMatchedStatus status;
          w->writer()->get_publication_matched_status(status);
          if (status.current_count >= expected || Clock::now() >= deadline) break;
          std::this_thread::sleep_for(std::chrono::microseconds(200));
        }
        w->flush();
        cobra_msgs::msg::LinkWriter entry;
        entry.topic(info.topic);
        entry.guid(text(w->writer()->guid()));
        entry.last_sequence(w->published());
        announced.push_back(std::move(entry));
      }
    });
  }

  bool allSeen() const {
    std::lock_guard lock(mutex_);
    return std::all_of(peers_.begin(), peers_.end(), [](const auto& p) { return p.second.seen || p.second.lost; });
  }

  /// How many reader ends the live peers said they have with `topic_type` ("topic|type").
  int readersOf(const std::string& topic_type) const {
    std::lock_guard lock(mutex_);
    long count = 0;
    for (const auto& [name, p] : peers_)
      if (!p.lost) count += std::count(p.readers.begin(), p.readers.end(), topic_type);
    return static_cast<int>(count);
  }

  /// True when every reader end of this process on a topic `writers` announce has received from
  /// them up to the announced sequence numbers (writers it cannot match are not waited for).
  bool receivedAll(const std::vector<cobra_msgs::msg::LinkWriter>& writers,
                   const std::vector<detail::ReaderEndHook*>& readers) const {
    for (const auto& w : writers) {
      if (w.last_sequence() == 0) continue;
      rtps::GUID_t guid;
      std::istringstream(w.guid()) >> guid;
      for (const detail::ReaderEndHook* r : readers)
        if (r->info().topic == w.topic() && participant_.mayMatchRemoteWriter(w.guid(), r->info()) &&
            r->received(guid) < w.last_sequence())
          return false;
    }
    return true;
  }

  void waitForPeers(std::int64_t t) {
    const auto wait_start = Clock::now();
    for (;;) {
      std::vector<std::pair<std::string, std::string>> losses;  // name, why
      bool ready = true;
      std::map<rtps::GUID_t, std::int64_t> bounds;
      participant_.withEnds([&](const auto&, const std::vector<detail::ReaderEndHook*>& readers) {
        std::lock_guard lock(mutex_);
        const auto now = Clock::now();
        for (auto& [name, p] : peers_) {
          if (p.lost) continue;
          const auto it = p.announced.find(t);
          if (it != p.announced.end() && receivedAll(it->second.writers, readers)) {
            for (const auto& w : it->second.writers) {
              rtps::GUID_t guid;
              std::istringstream(w.guid()) >> guid;
              bounds[guid] = w.last_sequence();
            }
            continue;
          }
          ready = false;
          if (!p.seen) {
            if (now - started_ > std::chrono::duration<double>(settings_.join_timeout))
              losses.emplace_back(name, "it never came to participant '" + settings_.self + "' in DDS domain " +
                                            std::to_string(participant_.entity()->get_domain_id()) + " (join_timeout " +
                                            text::number(settings_.join_timeout) +
                                            " s): is it running, with the same DdsLink.domain, and reachable "
                                            "(DdsLink.initial_peers when multicast does not route)?");
          } else if (now - std::max(p.heard, wait_start) > std::chrono::duration<double>(settings_.meeting_timeout)) {
            losses.emplace_back(name, "it missed the meeting at t = " + text::number(static_cast<double>(t) * 1e-9) +
                                          " s for " + text::number(settings_.meeting_timeout) + " s");
          }
        }
        if (ready) {
          for (detail::ReaderEndHook* r : readers) r->release(bounds);
          participant_.noteReleased(bounds);
          // A peer is done once it said so at a meeting this process passed too: both then
          // leave after the same instant.
          for (auto& [name, p] : peers_) {
            if (const auto it = p.announced.find(t); it != p.announced.end()) p.done = it->second.done;
            p.announced.erase(p.announced.begin(), p.announced.upper_bound(t));
          }
        }
      });
      for (const auto& [name, why] : losses) lose(name, why);
      if (ready) return;
      if (!losses.empty()) continue;
      std::unique_lock lock(mutex_);
      changed_.wait_for(lock, std::chrono::microseconds(100));
    }
  }

  /// The confirming thread (lapse_grace > 0): a peer whose liveliness lapsed and did not come
  /// back within the grace is lost. A lapse that comes back was a stall of either process (its
  /// threads held up past the lease, e.g. at a run's start), not a lost peer.
  void confirmLapses() {
    participant_.raiseThisThread();
    const auto grace = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(settings_.lapse_grace));
    std::unique_lock lock(mutex_);
    while (!stop_confirming_) {
      changed_.wait_for(lock, std::chrono::milliseconds(1));
      std::vector<std::string> confirmed;
      for (auto it = lapsed_.begin(); it != lapsed_.end();)
        if (Clock::now() - it->second >= grace) confirmed.push_back(it->first), it = lapsed_.erase(it);
        else ++it;
      if (confirmed.empty()) continue;
      lock.unlock();
      for (const std::string& name : confirmed)
        lose(name, "its liveliness lapsed (lease " + text::number(settings_.lease) + " s) and did not come back within " +
                       text::number(settings_.lapse_grace) + " s");
      lock.lock();
    }
  }

  void stopConfirming() noexcept {
    {
      std::lock_guard lock(mutex_);
      stop_confirming_ = true;
    }
    changed_.notify_all();
    if (confirmer_.joinable()) confirmer_.join();
  }

  void lose(const std::string& name, const std::string& why) {
    {
      std::lock_guard lock(mutex_);
      const auto it = peers_.find(name);
      if (it == peers_.end() || it->second.lost) return;
      it->second.lost = true;
      // It left after saying it was done: no loss. Its last announcement (done) may not have been
      // met yet here when its process ends: its liveliness can lapse first.
      const auto& announced = it->second.announced;
      if (it->second.done || std::any_of(announced.begin(), announced.end(), [](const auto& a) { return a.second.done; }))
        return;
      lost_.push_back(name);
    }
    std::cerr << "cobra dds: participant '" << settings_.self << "' lost its peer '" << name << "': " << why << std::endl;
    changed_.notify_all();
    link_.emit("e_peer_lost", name);
  }

  DdsLink& link_;
  detail::Participant& participant_;
  Settings settings_;
  Clock::time_point started_;
  fdds::TypeSupport type_;
  fdds::Topic* topic_ = nullptr;
  fdds::DataWriter* writer_ = nullptr;
  fdds::DataReader* reader_ = nullptr;
  std::atomic<bool> done_{false};
  std::mutex callback_mutex_;  // held by the listener's calls; close() takes it to end them
  bool closed_ = false;        // under callback_mutex_
  bool greeted_ = false;       // hello() sent: the peers know this link
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::map<std::string, Peer> peers_;         // by participant name
  bool told_done_ = false;                    // a meeting passed with this process done (under mutex_)
  std::map<std::string, std::string> names_;  // participant name by meeting writer GUID (text)
  std::vector<std::string> lost_;
  std::vector<std::string> joined_;  // the peers heard from, in that order
  std::map<std::string, Clock::time_point> lapsed_;  // liveliness lapsed, not yet lost: since when (under mutex_)
  bool stop_confirming_ = false;                     // under mutex_
  std::thread confirmer_;                            // lapse_grace > 0: confirmLapses
};

/// The events of foreign threads on their way to the link's step (event_queue.hpp).
struct DdsLink::ForeignEvents {
  static constexpr std::size_t kCapacity = 256;  // events between two steps of the link
  detail::EventQueue<kCapacity> queue;
};

DdsLink::DdsLink(std::string name)
    : Component(std::move(name), core::Role::Bridge,
                "the link of this process to the others of a run over Fast DDS: the dds transport's participant, "
                "peer liveliness, lockstep clock meetings"),
      foreign_events_(std::make_unique<ForeignEvents>()) {
  addProperty(domain_.range(0, 232));
  addProperty(participant_);
  addProperty(peers_);
  addProperty(lease_.range(1e-3, 3600.0));
  addProperty(join_timeout_.range(0.0, 3600.0));
  addProperty(meeting_timeout_.range(0.0, 3600.0));
  addProperty(initial_peers_);
  addProperty(drop_share_.range(0.0, 1.0));
  addProperty(poll_.range(1e-6, 1.0));
  addProperty(meeting_period_.range(0.0, 1.0));
  addProperty(priority_.range(0, 99));
  addProperty(udp_only_);
  addProperty(lapse_grace_.range(0.0, 3600.0));
  for (core::Property<std::string>* p : {&security_folder_, &security_ca_, &security_certificate_, &security_key_,
                                         &security_governance_, &security_permissions_, &security_permissions_ca_})
    addProperty(*p);
  addOperation(
      "lostPeers",
      std::function<std::string()>([this] {
        std::string out;
        for (const auto& peer : lostPeers()) out += (out.empty() ? "" : ",") + peer;
        return out;
      }),
      "the peers lost so far, comma-separated, in the order they were lost");
  addOperation(
      "joinedPeers",
      std::function<std::string()>([this] {
        std::string out;
        for (const auto& peer : meeting_ ? meeting_->joined() : std::vector<std::string>{})
          out += (out.empty() ? "" : ",") + peer;
        return out;
      }),
      "the peers heard from so far (their hello or an announcement), comma-separated, in the order they joined");
}

DdsLink::~DdsLink() { cleanupHook(); }

bool DdsLink::configureHook() {
  if (transport_) return true;  // configured again: the participant stays (clean up to change it)
  {
    std::lock_guard lock(current().mutex);
    if (current().link != nullptr && current().link != this)
      return refuse("another DdsLink ('" + current().link->name() + "') is configured in this process; one per process");
  }
  if (participant_.get().empty()) return refuse("property 'participant' is empty: name this process, e.g. \"needle\"");
  const std::vector<std::string> peers = splitList(peers_.get());
  if (std::find(peers.begin(), peers.end(), participant_.get()) != peers.end())
    return refuse("property 'peers' lists this process's own participant '" + participant_.get() + "'");
  DdsTransport::Options options;
  options.domain = domain_.get();
  options.participant = participant_.get();
  options.initial_peers = splitList(initial_peers_.get());
  options.drop_share = drop_share_.get();
  options.poll = poll_.get();
  options.priority = priority_.get();
  options.udp_only = udp_only_.get();
  // Relative paths from the deployment's folder (security_folder), absolute ones as they are.
  const auto path = [&](const core::Property<std::string>& p) {
    if (p.get().empty() || security_folder_.get().empty()) return p.get();
    return (std::filesystem::path(security_folder_.get()) / p.get()).lexically_normal().string();
  };
  options.security = {path(security_ca_), path(security_certificate_), path(security_key_),
                      path(security_governance_), path(security_permissions_), path(security_permissions_ca_)};
  try {
    transport_ = std::make_shared<DdsTransport>(options);
    transport_->participant_->setEventSink([this](const core::Event& e) { emit(e.name.str(), e.source.str()); });
    meeting_ = std::make_unique<Meeting>(*this, *transport_->participant_,
                                         Meeting::Settings{participant_.get(), peers, lease_.get(), join_timeout_.get(),
                                                           meeting_timeout_.get() > 0.0 ? meeting_timeout_.get() : lease_.get(),
                                                           std::llround(meeting_period_.get() * 1e9), lapse_grace_.get()});
  } catch (const std::exception& e) {
    meeting_.reset();
    transport_.reset();
    return refuse(e.what());
  }
  transport_->participant_->setLockstep(lockstep());
  std::lock_guard lock(current().mutex);
  current().link = this;
  current().transport = transport_;
  return true;
}

bool DdsLink::lockstep() const {
  return dynamic_cast<const core::LockstepActivity*>(&activity()) != nullptr && !splitList(peers_.get()).empty();
}

bool DdsLink::startHook() {
  transport_->participant_->setLockstep(lockstep());
  meeting_->hello();
  return true;
}

void DdsLink::cleanupHook() {
  {
    std::lock_guard lock(current().mutex);
    if (current().link == this) {
      current().link = nullptr;
      current().transport.reset();
    }
  }
  meeting_.reset();
  if (transport_) transport_->participant_->setEventSink(nullptr);
  transport_.reset();
}

void DdsLink::reached(std::chrono::nanoseconds t) noexcept {
  if (!meeting_) return;
  try {
    meeting_->reached(t);
  } catch (const std::exception& e) {
    std::cerr << "cobra dds: " << name() << ": clock meeting at t = " << text::number(static_cast<double>(t.count()) * 1e-9)
              << " s failed: " << e.what() << std::endl;
  }
}

void DdsLink::setDone(bool done) noexcept {
  if (meeting_) meeting_->setDone(done);
}

bool DdsLink::peersDone() const noexcept { return !meeting_ || meeting_->peersDone(); }

std::vector<std::string> DdsLink::lostPeers() const { return meeting_ ? meeting_->lost() : std::vector<std::string>{}; }

std::shared_ptr<DdsTransport> DdsLink::transport() const { return transport_; }

void DdsLink::emit(const std::string& event, const std::string& source) {
  core::Event e;
  e.name.assign(event);
  e.source.assign(source);
  e.stamp = now();  // run time, as every component's events (the activity's clock; any thread)
  if (!foreign_events_->queue.push(e))
    std::cerr << "cobra dds: " << name() << ": " << ForeignEvents::kCapacity << " events wait for the link's next step; "
              << event << " (" << source << ") dropped: give the link a periodic activity" << std::endl;
}

void DdsLink::updateHook() {
  core::Event e;
  while (foreign_events_->queue.pop(e)) events().write(e);
}

std::uint64_t DdsLink::droppedEvents() const noexcept { return foreign_events_->queue.dropped(); }

namespace {

/// The "dds" transport of a process with a DdsLink: each connection goes to the configured
/// link's participant.
class LinkedTransport final : public core::Transport {
 public:
  void check(const core::ConnPolicy& policy) const override {
    DdsTransport::ddsTopic(policy.topic);
    if (auto t = configured()) t->check(policy);
  }
  void makeWriterEnd(core::OutputPortBase& output, const core::ConnPolicy& policy, core::PortBase* peer) override {
    required(output)->makeWriterEnd(output, policy, peer);
  }
  void makeReaderEnd(core::InputPortBase& input, const core::ConnPolicy& policy, core::PortBase* peer) override {
    required(input)->makeReaderEnd(input, policy, peer);
  }

 private:
  static std::shared_ptr<DdsTransport> configured() {
    std::lock_guard lock(current().mutex);
    return current().transport;
  }
  static std::shared_ptr<DdsTransport> required(const core::PortBase& port) {
    if (auto t = configured()) return t;
    throw core::Error("cannot connect " + port.fullName() +
                      " over transport \"dds\": no DdsLink is configured in this process; create one (package "
                      "cobra_dds, type DdsLink) and configure it before making dds connections");
  }
};

}  // namespace

void registerLinkedTransport() {
  static std::once_flag once;
  std::call_once(once, [] {
    core::TransportRegistry::add("dds", "Fast DDS, through the DdsLink of this process", "cobra_dds",
                                 std::make_shared<LinkedTransport>());
  });
}

}  // namespace cobra::dds
