// Per-type capabilities shared by every module of a process (type_facets.hpp).
#include "cobra/core/type_facets.hpp"

#include <array>
#include <atomic>
#include <cstring>
#include <mutex>
#include <optional>
#include <string>

#include "cobra/core/error.hpp"

namespace cobra::core {
namespace {

struct Entry {
  std::optional<std::type_index> type;  // written before `count` is raised past this entry
  char capability[TypeFacets::max_capability + 1] = {};
  const void* facet = nullptr;
};

struct Table {
  std::mutex writer;  // serialises set(); readers never take it
  std::array<Entry, TypeFacets::capacity> entries;
  std::atomic<std::size_t> count{0};  // entries [0, count) are complete (release/acquire)
};

Table& table() {
  static Table instance;
  return instance;
}

const Entry* find(const Table& t, std::size_t n, std::type_index type, std::string_view capability) noexcept {
  for (std::size_t i = 0; i < n; ++i) {
    const Entry& e = t.entries[i];
    if (*e.type == type && capability == std::string_view(e.capability)) return &e;
  }
  return nullptr;
}

}  // namespace

bool TypeFacets::set(std::type_index type, std::string_view capability, const void* facet) {
  if (facet == nullptr) throw Error("TypeFacets::set: the facet of '" + std::string(capability) + "' is null");
  if (capability.empty() || capability.size() > max_capability)
    throw Error("TypeFacets::set: capability name '" + std::string(capability) + "' is empty or longer than " +
                std::to_string(max_capability) + " characters");
  Table& t = table();
  std::lock_guard lock(t.writer);
  const std::size_t n = t.count.load(std::memory_order_relaxed);
  if (find(t, n, type, capability) != nullptr) return false;
  if (n == capacity)
    throw Error("TypeFacets::set: the table is full (" + std::to_string(capacity) + " facets); '" +
                std::string(capability) + "' of " + type.name() + " not published");
  Entry& e = t.entries[n];
  e.type = type;
  std::memcpy(e.capability, capability.data(), capability.size());
  e.capability[capability.size()] = '\0';
  e.facet = facet;
  t.count.store(n + 1, std::memory_order_release);
  return true;
}

const void* TypeFacets::get(std::type_index type, std::string_view capability) noexcept {
  const Table& t = table();
  const Entry* e = find(t, t.count.load(std::memory_order_acquire), type, capability);
  return e == nullptr ? nullptr : e->facet;
}

std::size_t TypeFacets::size() noexcept { return table().count.load(std::memory_order_acquire); }

}  // namespace cobra::core
