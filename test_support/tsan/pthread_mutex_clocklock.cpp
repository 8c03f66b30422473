// ThreadSanitizer builds only (cmake/CobraWarnings.cmake compiles it into every target then).
//
// GCC 12's libtsan intercepts pthread_mutex_lock, _trylock and _timedlock but not glibc 2.30's
// pthread_mutex_clocklock, which std::timed_mutex::try_lock_until(steady_clock) calls. Debian's
// Fast DDS takes its timed mutexes that way, so TSan never saw those locks, only their unlocks:
// "unlock of an unlocked mutex" in StatelessWriter::send_nts, StatefulReader::processDataMsg...,
// and no happens-before through them. This definition (the executable's, which the dynamic linker
// binds before libc's) takes the lock through pthread_mutex_timedlock, which TSan intercepts, with
// the monotonic deadline turned into a real-time one. Nothing is suppressed: TSan sees the lock.
// Weak: every static library of the build carries a copy, and an executable that takes whole
// archives (the `cobra` tool) would otherwise see it defined many times; the dynamic linker binds
// a weak definition of the executable before libc's all the same.
#include <pthread.h>
#include <time.h>

#include <cerrno>
#include <cstdint>

extern "C" __attribute__((weak)) int pthread_mutex_clocklock(pthread_mutex_t* __restrict mutex, clockid_t clock,
                                       const struct timespec* __restrict deadline) noexcept {
  if (clock == CLOCK_REALTIME) return pthread_mutex_timedlock(mutex, deadline);
  if (clock != CLOCK_MONOTONIC) return EINVAL;
  timespec monotonic{}, realtime{};
  clock_gettime(CLOCK_MONOTONIC, &monotonic);
  clock_gettime(CLOCK_REALTIME, &realtime);
  constexpr std::int64_t kNs = 1'000'000'000;
  std::int64_t remaining = (deadline->tv_sec - monotonic.tv_sec) * kNs + (deadline->tv_nsec - monotonic.tv_nsec);
  if (remaining < 0) remaining = 0;
  const std::int64_t at = realtime.tv_sec * kNs + realtime.tv_nsec + remaining;
  const timespec real_deadline{static_cast<time_t>(at / kNs), static_cast<long>(at % kNs)};
  return pthread_mutex_timedlock(mutex, &real_deadline);
}
