// Switch requests from supervisors: queued in their steps, carried out between steps.
#include "cobra/deploy/configurator_client.hpp"

#include <algorithm>

#include "cobra/core/error.hpp"
#include "cobra/deploy/configurator.hpp"

namespace cobra::deploy {

bool ConfiguratorClient::requestSwitch(SwitchRequest::Kind kind, std::string_view name) noexcept {
  Configurator* configurator = configurator_.load(std::memory_order_acquire);
  if (configurator == nullptr || name.size() > decltype(SwitchRequest::name)::capacity()) return false;
  const std::size_t tail = tail_.load(std::memory_order_relaxed);
  if (tail - head_.load(std::memory_order_acquire) >= kQueueCapacity) return false;
  queue_[tail % kQueueCapacity] = SwitchRequest{kind, name};
  tail_.store(tail + 1, std::memory_order_release);
  configurator->wakeService();
  return true;
}

bool ConfiguratorClient::takeRequest(SwitchRequest& out) noexcept {
  const std::size_t head = head_.load(std::memory_order_relaxed);
  if (head == tail_.load(std::memory_order_acquire)) return false;
  out = queue_[head % kQueueCapacity];
  head_.store(head + 1, std::memory_order_release);
  return true;
}

void Configurator::attachClient(core::Component& component) {
  const std::lock_guard lock(mutex_);
  auto* client = dynamic_cast<ConfiguratorClient*>(&component);
  if (client == nullptr || components_.find(component.name()) != &component)
    throw core::Error("component '" + component.name() +
                      "' cannot ask this configurator for switches: it must be one of its components and a "
                      "ConfiguratorClient (a supervisor)");
  if (std::any_of(clients_.begin(), clients_.end(), [&](const auto& c) { return c.first == &component; })) return;
  clients_.emplace_back(&component, client);
  client->configurator_.store(this, std::memory_order_release);
  if (options_.mode == ClockMode::RealTime && !service_thread_.joinable())
    service_thread_ = std::thread([this] { serviceLoop(); });
}

void Configurator::wakeService() noexcept {
  service_wakeups_.fetch_add(1, std::memory_order_release);
  service_wakeups_.notify_one();
}

void Configurator::serviceLoop() {
  while (!service_stopping_.load()) {
    const std::uint32_t seen = service_wakeups_.load(std::memory_order_acquire);
    serviceRequests();
    if (service_stopping_.load()) break;
    service_wakeups_.wait(seen, std::memory_order_acquire);  // returns at once if a request came meanwhile
  }
}

std::string Configurator::lastWarningWith(std::string_view text) const {
  const std::lock_guard lock(mutex_);
  for (auto it = warnings_.rbegin(); it != warnings_.rend(); ++it)
    if (it->find(text) != std::string::npos) return *it;
  return {};
}

bool Configurator::serviceRequests() {
  const std::lock_guard lock(mutex_);
  bool any = false;
  // By index: a switch may attach nothing new, but stay safe if a callback adds a client.
  for (std::size_t i = 0; i < clients_.size(); ++i) {
    auto [component, client] = clients_[i];
    SwitchRequest request;
    while (client->takeRequest(request)) {
      any = true;
      const std::string name = request.name.str();
      try {
        if (request.kind == SwitchRequest::Kind::Deployment) {
          for (const LintViolation& v : applyDeployment(name)) warnings_.push_back(v.message);
        } else {
          applyConfiguration(name);
        }
        client->onRequestDone(request, true, {});
      } catch (const std::exception& e) {
        const std::string why = component->name() + " asked for " +
                                (request.kind == SwitchRequest::Kind::Deployment ? "deployment '" : "configuration '") +
                                name + "': " + e.what();
        warnings_.push_back(why);
        client->onRequestDone(request, false, why);
      }
    }
  }
  return any;
}

}  // namespace cobra::deploy
