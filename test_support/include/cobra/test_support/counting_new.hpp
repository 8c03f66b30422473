#pragma once
// A counting replacement of the global operator new/delete, for the tests that prove the
// real-time paths allocate nothing (ARCHITECTURE §4) or measure memory. It DEFINES the replacement
// functions: include it in exactly one source file of a test executable.

#include <atomic>
#include <cstddef>
#include <cstdlib>
#include <new>

// GCC warns that malloc/free pair with operator new/delete; here that pairing is the point.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"

namespace cobra::test_support {

struct NewCounters {
  std::atomic<long> calls{0};
  std::atomic<std::size_t> bytes{0};
};

inline NewCounters& newCounters() {
  static NewCounters counters;  // constant-initialised: usable before main
  return counters;
}

/// Calls of operator new (all forms) since the program started.
inline long newCalls() { return newCounters().calls.load(); }
/// Bytes requested from operator new since the program started.
inline std::size_t newBytes() { return newCounters().bytes.load(); }

/// Number of operator new calls made while `body` runs.
template <class F>
long allocationsDuring(F&& body) {
  const long before = newCalls();
  body();
  return newCalls() - before;
}

/// Calls of operator new made by the calling thread (constant-initialised: no TLS guard).
inline long& threadNewCalls() {
  thread_local long calls = 0;
  return calls;
}

/// Number of operator new calls the calling thread made while `body` runs: for a real-time path
/// measured while other threads (a transport's, a middleware's) allocate as they please.
template <class F>
long allocationsOnThisThreadDuring(F&& body) {
  const long before = threadNewCalls();
  body();
  return threadNewCalls() - before;
}

inline void* countedAllocation(std::size_t size) noexcept {
  ++threadNewCalls();
  newCounters().calls.fetch_add(1, std::memory_order_relaxed);
  newCounters().bytes.fetch_add(size, std::memory_order_relaxed);
  return std::malloc(size == 0 ? 1 : size);
}

}  // namespace cobra::test_support

void* operator new(std::size_t size) {
  if (void* p = cobra::test_support::countedAllocation(size)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) { return operator new(size); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept { return cobra::test_support::countedAllocation(size); }
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept { return cobra::test_support::countedAllocation(size); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
