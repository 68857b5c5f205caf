#include "common/blas_threads.h"

#include <dlfcn.h>

#include <condition_variable>
#include <mutex>

#include "quadcage/core/errors.h"

namespace quadcage::detail {

namespace {

// OpenBLAS's own entry points, looked up at run time: the build links the generic libblas.so.3,
// which Debian's alternatives may point at OpenBLAS, ATLAS or the reference BLAS.
using SetThreads = void (*)(int);
using GetThreads = int (*)();

// Looked up once: every factorisation of a fit opens a scope.
SetThreads set_threads() {
    static const auto f = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
    return f;
}
GetThreads get_threads() {
    static const auto f = reinterpret_cast<GetThreads>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
    return f;
}

// The scopes open in the process: how many, the count they share, and OpenBLAS's count before
// the first of them (0: nothing to restore).
struct Turns {
    std::mutex mutex;
    std::condition_variable closed;  // notified when the last scope closes
    int open = 0, threads = 0, previous = 0;
};

Turns& turns() {
    static Turns t;
    return t;
}

thread_local int open_here = 0;  // scopes this thread has open

}  // namespace

ScopedBlasThreads::ScopedBlasThreads(int threads) {
    Turns& t = turns();
    std::unique_lock<std::mutex> lock(t.mutex);
    if (open_here > 0) {
        QC_CHECK(t.threads == threads, "ScopedBlasThreads: a scope nested in one of another thread count");
    } else {
        t.closed.wait(lock, [&] { return t.open == 0 || t.threads == threads; });
    }
    if (t.open == 0) {
        t.threads = threads;
        t.previous = 0;
        const SetThreads set = set_threads();
        const GetThreads get = get_threads();
        if (set && get) {
            const int now = get();
            if (now != threads) t.previous = now, set(threads);
        }
    }
    ++t.open;
    ++open_here;
}

ScopedBlasThreads::~ScopedBlasThreads() {
    Turns& t = turns();
    {
        const std::lock_guard<std::mutex> lock(t.mutex);
        --open_here;
        if (--t.open > 0) return;
        if (t.previous > 0) set_threads()(t.previous);
        t.previous = 0;
    }
    t.closed.notify_all();
}

}  // namespace quadcage::detail
