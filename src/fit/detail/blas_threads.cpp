#include "detail/blas_threads.h"

#include <dlfcn.h>

namespace quadcage::fit::detail {

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

// The OpenMP runtime's, likewise: Debian's CHOLMOD runs parts of its factorisation in OpenMP
// parallel loops, and an idle OpenMP team spins a while before it sleeps.
SetThreads omp_set() {
    static const auto f = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "omp_set_num_threads"));
    return f;
}
GetThreads omp_get() {
    static const auto f = reinterpret_cast<GetThreads>(dlsym(RTLD_DEFAULT, "omp_get_max_threads"));
    return f;
}

}  // namespace

ScopedBlasThreads::ScopedBlasThreads(int threads) {
    if (omp_set() && omp_get()) {
        previous_omp_ = omp_get()();
        if (previous_omp_ != threads)
            omp_set()(threads);
        else
            previous_omp_ = 0;
    }
    const SetThreads set = set_threads();
    const GetThreads get = get_threads();
    if (!set || !get) return;
    previous_ = get();
    if (previous_ != threads) set(threads);
    else previous_ = 0;
}

ScopedBlasThreads::~ScopedBlasThreads() {
    if (previous_ > 0) set_threads()(previous_);
    if (previous_omp_ > 0) omp_set()(previous_omp_);
}

}  // namespace quadcage::fit::detail
