#pragma once
// A minimal deterministic parallel loop on std::thread, shared by the numerical modules.

#include <algorithm>
#include <atomic>
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

/// Calls body(i) for every i in [0, n), on up to `threads` threads (0 = all cores), the threads
/// taking contiguous chunks of indices in turn as they finish the previous ones (a thread that
/// gets less of a shared CPU, or costlier indices, takes fewer). Results are deterministic as long
/// as body(i) writes only its own outputs (reduce afterwards, in index order). The first exception
/// thrown by a body is rethrown in the caller after all threads have finished.
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
    // 16 chunks per thread: small enough to even out, large enough that taking one costs nothing.
    const long long chunk = std::max(16, n / (16 * t));
    std::atomic<long long> next{0};
    auto work = [&] {
        try {
            for (long long begin; (begin = next.fetch_add(chunk)) < n;)
                for (int i = static_cast<int>(begin),
                         end = static_cast<int>(std::min<long long>(n, begin + chunk));
                     i < end; ++i)
                    body(i);
        } catch (...) {
            std::lock_guard<std::mutex> lock(error_mutex);
            if (!error) error = std::current_exception();
        }
    };
    std::vector<std::thread> pool;
    pool.reserve(t - 1);
    for (int k = 1; k < t; ++k) pool.emplace_back(work);
    work();  // the calling thread takes chunks too
    for (auto& th : pool) th.join();
    if (error) std::rethrow_exception(error);
}

}  // namespace quadcage
