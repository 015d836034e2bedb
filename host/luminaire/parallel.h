#pragma once
// parallel_for: job(k) for k in [0, count) on `threads` std::threads (0 = hardware concurrency),
// dynamic scheduling; results must be written to per-k slots so the outcome is deterministic.
#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace nf::lum {

inline unsigned resolve_threads(unsigned threads) {
  return threads ? threads : std::max(1u, std::thread::hardware_concurrency());
}

template <typename F>
void parallel_for(int count, unsigned threads, F&& job) {
  threads = std::min(resolve_threads(threads), static_cast<unsigned>(std::max(count, 1)));
  std::atomic<int> next{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto work = [&] {
    for (int k = next++; k < count; k = next++) {
      try {
        job(k);
      } catch (...) {
        std::lock_guard lock(error_mutex);
        if (!error) error = std::current_exception();
        next = count;
      }
    }
  };
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace nf::lum
