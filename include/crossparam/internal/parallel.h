// SPDX-License-Identifier: GPL-3.0-or-later
// Minimal parallelism with std::thread: a loop over an index range, cut into one contiguous chunk per thread,
// and two independent calls side by side. Each body must only write what belongs to it; the first exception
// thrown in any thread is rethrown to the caller once all threads have finished.
#ifndef CROSSPARAM_INTERNAL_PARALLEL_H
#define CROSSPARAM_INTERNAL_PARALLEL_H

#include <algorithm>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace crossparam {
namespace internal {

/// The number of threads to use for a request of `n` (0: one per hardware thread).
inline unsigned thread_count(unsigned n) {
  if (n > 0) return n;
  return std::max(1u, std::thread::hardware_concurrency());
}

/// Calls body(i) for every i in [0, n), on up to `threads` threads; ranges too small to be worth a thread run
/// on the caller's.
template <class Body>
void parallel_for(std::size_t n, unsigned threads, const Body& body) {
  constexpr std::size_t min_per_thread = 2048;
  const std::size_t t = std::min<std::size_t>(threads, n / min_per_thread);
  if (t <= 1) {
    for (std::size_t i = 0; i < n; ++i) body(i);
    return;
  }
  std::exception_ptr error;
  std::mutex mutex;
  auto run = [&](std::size_t begin, std::size_t end) {
    try {
      for (std::size_t i = begin; i < end; ++i) body(i);
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex);
      if (!error) error = std::current_exception();
    }
  };
  const std::size_t chunk = (n + t - 1) / t;
  std::vector<std::thread> pool;
  for (std::size_t k = 1; k < t; ++k) pool.emplace_back(run, k * chunk, std::min(n, (k + 1) * chunk));
  run(0, std::min(n, chunk));
  for (std::thread& th : pool) th.join();
  if (error) std::rethrow_exception(error);
}

/// Calls a() and b(), on two threads if `threads` is at least 2 (b on a new one), else one after the other.
/// The first exception thrown is rethrown once both have finished.
template <class A, class B>
void parallel_invoke(unsigned threads, const A& a, const B& b) {
  if (threads < 2) {
    a();
    b();
    return;
  }
  std::exception_ptr error_b;
  std::thread other([&] {
    try {
      b();
    } catch (...) {
      error_b = std::current_exception();
    }
  });
  std::exception_ptr error_a;
  try {
    a();
  } catch (...) {
    error_a = std::current_exception();
  }
  other.join();
  if (error_a) std::rethrow_exception(error_a);
  if (error_b) std::rethrow_exception(error_b);
}

} // namespace internal
} // namespace crossparam

#endif // CROSSPARAM_INTERNAL_PARALLEL_H
