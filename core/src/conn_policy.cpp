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
  ConnPolicy policy;
  policy.kind = Kind::Buffer;
  policy.size = n;
  return policy;
}

ConnPolicy ConnPolicy::circular(std::size_t n) {
  if (n == 0) throw Error("connection policy circular(n) needs n >= 1 samples, got 0");
  ConnPolicy policy;
  policy.kind = Kind::Circular;
  policy.size = n;
  return policy;
}

std::string ConnPolicy::describe() const {
  std::string text = "?";
  switch (kind) {
    case Kind::Data: text = "data"; break;
    case Kind::Buffer: text = "buffer(" + std::to_string(size) + ")"; break;
    case Kind::Circular: text = "circular(" + std::to_string(size) + ")"; break;
  }
  if (!transport.empty()) text += " over " + transport + " topic '" + topic + "'";
  return text;
}

}  // namespace cobra::core
