#include "common/blas_threads.h"

#include <dlfcn.h>

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

std::recursive_mutex& turns() {
    static std::recursive_mutex m;
    return m;
}

}  // namespace

ScopedBlasThreads::ScopedBlasThreads(int threads) : turn_(turns()) {
    const SetThreads set = set_threads();
    const GetThreads get = get_threads();
    if (!set || !get) return;
    previous_ = get();
    if (previous_ != threads)
        set(threads);
    else
        previous_ = 0;
}

ScopedBlasThreads::~ScopedBlasThreads() {
    if (previous_ > 0) set_threads()(previous_);
}

}  // namespace quadcage::detail
