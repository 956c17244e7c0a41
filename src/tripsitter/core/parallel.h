// Work shared among threads: indices handed out one at a time from a shared counter, so uneven rows
// balance themselves. Plain std::thread, so the thread sanitizer sees every synchronisation.
#pragma once

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace tripsitter::core {

// Threads `threads` asks for: itself when positive, else every hardware thread.
inline int thread_count(int threads) {
  return threads > 0 ? threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

// Calls body(i) for every i in [begin, end), on up to thread_count(threads) threads (the caller is one of
// them). Returns when all calls have returned; the first exception a call throws is rethrown here.
template <class Body>
void parallel_for(int begin, int end, int threads, const Body& body) {
  const int n = end - begin;
  if (n <= 0) return;
  const int workers = std::min(thread_count(threads), n);
  if (workers == 1) {
    for (int i = begin; i < end; ++i) body(i);
    return;
  }
  std::atomic<int> next{begin};
  std::exception_ptr error;
  std::mutex error_mutex;
  const auto work = [&] {
    try {
      for (int i = next.fetch_add(1); i < end; i = next.fetch_add(1)) body(i);
    } catch (...) {
      const std::lock_guard lock(error_mutex);
      if (!error) error = std::current_exception();
      next.store(end);
    }
  };
  std::vector<std::thread> pool;
  pool.reserve(static_cast<std::size_t>(workers - 1));
  for (int t = 1; t < workers; ++t) pool.emplace_back(work);
  work();
  for (auto& thread : pool) thread.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace tripsitter::core
