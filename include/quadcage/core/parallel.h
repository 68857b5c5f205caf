#pragma once
// A minimal deterministic parallel loop on std::thread, shared by the numerical modules.

#include <algorithm>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace quadcage {

/// The number of threads to use for `requested` (0 = all hardware threads, at least 1).
inline int resolve_threads(int requested) {
    if (requested > 0) return requested;
    return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

/// Calls body(i) for every i in [0, n), on up to `threads` threads (0 = all cores), each thread
/// taking a contiguous block of indices. Results are deterministic as long as body(i) writes only
/// its own outputs (reduce afterwards, in index order). The first exception thrown by a body is
/// rethrown in the caller after all threads have finished.
template <class Body>
void parallel_for(int n, int threads, Body&& body) {
    if (n <= 0) return;
    const int t = std::min(resolve_threads(threads), std::max(1, n / 64));
    if (t <= 1) {
        for (int i = 0; i < n; ++i) body(i);
        return;
    }
    std::exception_ptr error;
    std::mutex error_mutex;
    std::vector<std::thread> pool;
    pool.reserve(t);
    for (int k = 0; k < t; ++k) {
        const int begin = static_cast<int>(static_cast<long long>(n) * k / t);
        const int end = static_cast<int>(static_cast<long long>(n) * (k + 1) / t);
        pool.emplace_back([&, begin, end] {
            try {
                for (int i = begin; i < end; ++i) body(i);
            } catch (...) {
                std::lock_guard<std::mutex> lock(error_mutex);
                if (!error) error = std::current_exception();
            }
        });
    }
    for (auto& th : pool) th.join();
    if (error) std::rethrow_exception(error);
}

}  // namespace quadcage
