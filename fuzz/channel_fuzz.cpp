// libFuzzer target: a random sequence of writes and reads on one connection of each policy,
// checked against a std::deque model of what the reader must see (single-threaded: the
// interleavings of two threads are the stress test's job, under ThreadSanitizer).

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <deque>
#include <optional>

#include "cobra/core/port.hpp"

using namespace cobra::core;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  const std::size_t capacity = 1 + data[0] % 8;
  const int kind = data[1] % 3;
  const ConnPolicy policy = kind == 0 ? ConnPolicy::data()
                            : kind == 1 ? ConnPolicy::buffer(capacity)
                                        : ConnPolicy::circular(capacity);
  const std::size_t kept = kind == 0 ? 1 : capacity;

  OutputPort<int> out{"out", "", "1"};
  InputPort<int> in{"in", "", "1"};
  connect(out, in, policy);
  std::deque<int> model;
  std::optional<int> last;
  int next = 0;
  for (std::size_t i = 2; i < size; ++i) {
    if (data[i] & 1) {
      const WriteStatus status = out.write(next);
      if (model.size() == kept && kind == 1) {
        if (status != WriteStatus::Dropped) std::abort();
      } else {
        if (status != WriteStatus::Written) std::abort();
        if (model.size() == kept) model.pop_front();
        model.push_back(next);
      }
      ++next;
    } else {
      int value = -1;
      const FlowStatus status = in.read(value);
      if (!model.empty()) {
        if (status != FlowStatus::NewData || value != model.front()) std::abort();
        last = model.front();
        model.pop_front();
      } else if (last) {
        if (status != FlowStatus::OldData || value != *last) std::abort();
      } else if (status != FlowStatus::NoData || value != -1) {
        std::abort();
      }
    }
  }
  return 0;
}
