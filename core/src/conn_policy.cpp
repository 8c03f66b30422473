#include "cobra/core/conn_policy.hpp"

#include "cobra/core/error.hpp"

namespace cobra::core {

std::string toString(FlowStatus status) {
  switch (status) {
    case FlowStatus::NoData: return "NoData";
    case FlowStatus::OldData: return "OldData";
    case FlowStatus::NewData: return "NewData";
  }
  return "?";
}

std::string toString(WriteStatus status) {
  switch (status) {
    case WriteStatus::Written: return "Written";
    case WriteStatus::Dropped: return "Dropped";
    case WriteStatus::NotConnected: return "NotConnected";
  }
  return "?";
}

ConnPolicy ConnPolicy::buffer(std::size_t n) {
  if (n == 0) throw Error("connection policy buffer(n) needs n >= 1 samples, got 0");
  return {Kind::Buffer, n};
}

ConnPolicy ConnPolicy::circular(std::size_t n) {
  if (n == 0) throw Error("connection policy circular(n) needs n >= 1 samples, got 0");
  return {Kind::Circular, n};
}

std::string ConnPolicy::describe() const {
  switch (kind) {
    case Kind::Data: return "data";
    case Kind::Buffer: return "buffer(" + std::to_string(size) + ")";
    case Kind::Circular: return "circular(" + std::to_string(size) + ")";
  }
  return "?";
}

}  // namespace cobra::core
