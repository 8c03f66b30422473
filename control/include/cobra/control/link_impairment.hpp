#pragma once
/// @file
/// A model of an impaired communication link between master and slave (thesis §4.5.4: the
/// two-layer approach stays passive under "time delays and package loss"): every sample sent is
/// lost with probability `loss`, else it arrives after the constant `delay` plus a jitter drawn
/// uniformly in [0, jitter]. The receiver sees the newest sample that has arrived and never an
/// older one after a newer (a sample overtaken by a later one is discarded, as a UDP receiver
/// keeping sequence numbers does). Seeded: the same parameters and calls give the same arrivals.
/// Times in s. Allocation-free and noexcept after construction (the buffer is allocated there).

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace cobra::control {

struct LinkImpairmentParameters {
  double delay = 0.0;   ///< constant one-way delay, s (>= 0)
  double jitter = 0.0;  ///< extra delay drawn uniformly in [0, jitter], s (>= 0)
  double loss = 0.0;    ///< share of the samples lost, 0..1 (Bernoulli per sample)
  std::uint64_t seed = 1;      ///< seed of the loss and jitter draws
  std::size_t capacity = 4096;  ///< samples in flight at most (a send beyond it fails, counted)
};

namespace detail {
/// Throws std::invalid_argument naming the parameter and the rule it breaks.
inline void requireLinkParameters(const LinkImpairmentParameters& p) {
  auto fail = [](const char* name, const char* rule, double value) {
    throw std::invalid_argument(std::string("LinkImpairment: ") + name + " must be " + rule + ", got " +
                                std::to_string(value));
  };
  if (!(p.delay >= 0.0) || !std::isfinite(p.delay)) fail("delay", ">= 0 (s)", p.delay);
  if (!(p.jitter >= 0.0) || !std::isfinite(p.jitter)) fail("jitter", ">= 0 (s)", p.jitter);
  if (!(p.loss >= 0.0 && p.loss <= 1.0)) fail("loss", "in [0, 1] (share of samples)", p.loss);
  if (p.capacity == 0) fail("capacity", ">= 1 (samples in flight)", 0.0);
}
}  // namespace detail

/// `Sample` must be default-constructible and copy-assignable (KDL::Frame, an Eigen vector, a
/// struct of them). Send and receive times must be non-decreasing (one clock, e.g. the task's).
template <class Sample>
class LinkImpairment {
 public:
  /// @throws std::invalid_argument naming the parameter (delay, jitter, loss, capacity).
  explicit LinkImpairment(const LinkImpairmentParameters& p)
      : p_((detail::requireLinkParameters(p), p)), buffer_(p.capacity), random_(p.seed) {}

  /// Puts `sample`, sent at `time` (s), on the link. False when it is lost (counted by lost()),
  /// when the buffer is full (counted by overflowed()) or when `time` precedes the last send.
  bool send(double time, const Sample& sample) noexcept {
    if (!(time >= last_send_)) return false;
    last_send_ = time;
    // Both draws are made for every sample, so the loss pattern does not depend on the jitter.
    const bool dropped = unit_(random_) < p_.loss;
    const double extra = p_.jitter * unit_(random_);
    if (dropped) {
      ++lost_;
      return false;
    }
    if (size_ == buffer_.size()) {
      ++overflowed_;
      return false;
    }
    Entry& e = buffer_[(head_ + size_) % buffer_.size()];
    e.sent = time;
    e.arrival = time + p_.delay + extra;
    e.sample = sample;
    ++size_;
    return true;
  }

  /// The newest sample (in send order) that has arrived by `time` (s) into `out`; the older ones
  /// still in flight are discarded (counted by discardedLate()), as they would arrive after it.
  /// False, `out` untouched, when nothing new arrived.
  bool receive(double time, Sample& out) noexcept {
    // Sends are in time order and arrival >= sent + delay: no entry past the first one sent after
    // time - delay can have arrived, so the scan stops there (it covers at most the jitter window).
    std::size_t newest = size_;
    for (std::size_t i = 0; i < size_; ++i) {
      const Entry& e = buffer_[(head_ + i) % buffer_.size()];
      if (e.sent + p_.delay > time + kTolerance) break;
      if (e.arrival <= time + kTolerance) newest = i;
    }
    if (newest == size_) return false;
    for (std::size_t i = 0; i < newest; ++i)
      if (buffer_[(head_ + i) % buffer_.size()].arrival > time + kTolerance) ++late_;
    const Entry& e = buffer_[(head_ + newest) % buffer_.size()];
    out = e.sample;
    delivered_sent_ = e.sent;
    head_ = (head_ + newest + 1) % buffer_.size();
    size_ -= newest + 1;
    return true;
  }

  std::uint64_t lost() const noexcept { return lost_; }            ///< samples the link lost
  std::uint64_t discardedLate() const noexcept { return late_; }   ///< overtaken by a newer one
  std::uint64_t overflowed() const noexcept { return overflowed_; }  ///< refused: buffer full
  std::size_t inFlight() const noexcept { return size_; }
  /// Send time (s) of the last sample receive() delivered (-inf before the first): its age is
  /// the receive time minus it.
  double deliveredSendTime() const noexcept { return delivered_sent_; }

 private:
  // 1 ns, s: a delay of a whole number of periods must not gain a period from the rounding of
  // send time + delay against the receive time (0.003 + 0.05 > 0.053 in binary).
  static constexpr double kTolerance = 1e-9;
  struct Entry {
    double sent = 0.0;     // s
    double arrival = 0.0;  // s
    Sample sample{};
  };
  LinkImpairmentParameters p_;
  std::vector<Entry> buffer_;  // ring, oldest at head_, in send order
  std::size_t head_ = 0, size_ = 0;
  std::mt19937_64 random_;
  std::uniform_real_distribution<double> unit_{0.0, 1.0};
  double last_send_ = -INFINITY;
  double delivered_sent_ = -INFINITY;
  std::uint64_t lost_ = 0, late_ = 0, overflowed_ = 0;
};

}  // namespace cobra::control
