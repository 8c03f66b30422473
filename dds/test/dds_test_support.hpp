#pragma once
// Helpers of the dds tests: a transport registered for one test, an event, and polling with a deadline.

#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <thread>

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

#include "cobra/core/event.hpp"
#include "cobra/core/transport.hpp"
#include "cobra/dds/dds_transport.hpp"

namespace cobra::dds::test {

/// A DdsTransport registered as `name` on `domain` for the life of the object. Each test uses
/// its own domain id: ctest runs tests in parallel, and DDS would match their topics otherwise.
struct RegisteredTransport {
  RegisteredTransport(const std::string& transport_name, int domain, const std::string& participant)
      : name(transport_name), transport(registerDdsTransport({domain, participant, false}, transport_name)) {}
  ~RegisteredTransport() { core::TransportRegistry::remove(name); }
  RegisteredTransport(const RegisteredTransport&) = delete;
  RegisteredTransport& operator=(const RegisteredTransport&) = delete;

  /// A policy of kind `base` over this transport on `topic`.
  core::ConnPolicy policy(const std::string& topic, core::ConnPolicy base = core::ConnPolicy::data()) const {
    base.transport = name;
    base.topic = topic;
    return base;
  }

  std::string name;
  std::shared_ptr<DdsTransport> transport;
};

/// An event named `name` from source "test", as the tests send them across.
inline core::Event event(const std::string& name) {
  core::Event e;
  e.name.assign(name);
  e.source = "test";
  return e;
}

/// Polls `done` every millisecond until it is true or `timeout` passed; returns its last value.
inline bool pollUntil(const std::function<bool()>& done, std::chrono::milliseconds timeout = std::chrono::seconds(5)) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!done()) {
    if (std::chrono::steady_clock::now() >= deadline) return done();
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return true;
}

}  // namespace cobra::dds::test
