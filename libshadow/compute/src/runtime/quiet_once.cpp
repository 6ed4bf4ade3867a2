// SPDX-License-Identifier: GPL-3.0-or-later
// pthread_once for this library's own calls, without a system call when no thread waits.
//
// CGAL's lazy exact numbers (Epeck) evaluate a node's exact value inside std::call_once, which
// libstdc++ runs through pthread_once; glibc's pthread_once ends every first run with a futex
// wake, whether or not a thread waits. A shadow computation evaluates hundreds of thousands of
// lazy nodes (docs/benchmarks.md, "System calls and rounding-mode switches"), each once and on
// one thread (Epeck objects are never shared between this library's threads), so nearly all of
// those system calls wake nobody. When the library is linked as a shared object, the linker
// sends its own references to pthread_once here (-Wl,--wrap=pthread_once, libshadow/
// CMakeLists.txt); other code in the process keeps glibc's.
//
// The protocol keeps glibc's values where they meet: 0 before the first run and 2 (glibc's
// __PTHREAD_ONCE_DONE) after it, so a flag finished by either implementation reads as finished
// by the other. While a run is in progress the value is 1, or 1 | kWaiting once a thread sleeps
// on it; only then does the finishing thread wake anyone. A run that ends by an exception puts
// the flag back to 0 (the next call runs it again, as std::call_once requires) and wakes the
// sleepers, one of which then runs it.
//
// Not for a flag that glibc's pthread_once runs at the same moment from another thread: a glibc
// waiter sleeps without saying so and would not be woken, and glibc would read 1 | kWaiting as
// a run of another fork generation and start its own. Such a flag cannot reach this code: the
// library exports none of the CGAL template code that calls pthread_once (libshadow.map), binds
// its own calls to its own functions (-Bsymbolic-functions), and its lazy objects are each made
// and evaluated by one thread (exact/exact_faces.hpp); CGAL uses std::call_once nowhere else
// (Lazy.h, Lazy_exact_nt.h). A fork while a run is in progress on another thread leaves the
// child's flag running forever (glibc would start it again); the library never forks.
// Measured: 517,830 futex calls -> 149 on `shadow-bench --sizes 100`, and the fragment route
// on the 1,000-box city 1.20-1.26 times faster (docs/benchmarks.md).
#include <pthread.h>

#include <atomic>
#include <climits>
#include <cstdint>

#include <linux/futex.h>
#include <sys/syscall.h>
#include <unistd.h>

namespace {

constexpr int kNotRun = 0;
constexpr int kRunning = 1;
constexpr int kDone = 2;  // glibc's __PTHREAD_ONCE_DONE
constexpr int kWaiting = 0x40000000;

static_assert(sizeof(pthread_once_t) == sizeof(std::atomic<int>), "pthread_once_t is an int on Linux");

std::atomic<int>& flag_of(pthread_once_t* once) { return *reinterpret_cast<std::atomic<int>*>(once); }

void wait_while(pthread_once_t* once, int value) {
  syscall(SYS_futex, reinterpret_cast<int*>(once), FUTEX_WAIT_PRIVATE, value, nullptr, nullptr, 0);
}
void wake_all(pthread_once_t* once) {
  syscall(SYS_futex, reinterpret_cast<int*>(once), FUTEX_WAKE_PRIVATE, INT_MAX, nullptr, nullptr, 0);
}

/// Ends a run: done, or (unwinding from an exception) back to not run; wakes sleepers only.
struct RunEnd {
  pthread_once_t* once;
  bool finished = false;
  ~RunEnd() {
    const int before = flag_of(once).exchange(finished ? kDone : kNotRun, std::memory_order_acq_rel);
    if (before & kWaiting) wake_all(once);
  }
};

}  // namespace

extern "C" int __wrap_pthread_once(pthread_once_t* once, void (*init)(void)) {
  std::atomic<int>& flag = flag_of(once);
  for (;;) {
    int value = flag.load(std::memory_order_acquire);
    if (value & kDone) return 0;
    if (value == kNotRun) {
      if (!flag.compare_exchange_strong(value, kRunning, std::memory_order_acquire)) continue;
      RunEnd end{once};
      init();
      end.finished = true;
      return 0;
    }
    // Another thread runs it: say that we sleep, then sleep until the value changes.
    if (!(value & kWaiting) && !flag.compare_exchange_strong(value, value | kWaiting, std::memory_order_relaxed))
      continue;
    wait_while(once, value | kWaiting);
  }
}
