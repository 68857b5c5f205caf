#pragma once
// The BLAS thread count during the sparse factorisations of the fit and the layout embedding
// (private to the source tree).
//
// CHOLMOD's supernodal factorisation runs its dense updates through BLAS and LAPACK. OpenBLAS, which
// Debian's libblas.so.3 usually resolves to, picks one thread per core by default, and its one-thread
// kernels round differently from its threaded ones: eight.off fitted at level 3 ended in other bits
// with OPENBLAS_NUM_THREADS=1 than with 2, 3 or 4. A fit's output would then depend on the machine's
// core count, not only on the input and the options. Within a ScopedBlasThreads the BLAS uses a
// fixed count, so the fit is the same on every machine with the same build, libraries and CPU model
// (OpenBLAS picks its kernels by CPU model). Two threads: the count the fit was tuned on; one thread
// made botijo's level-3 factorisations 1.4x slower (solve 2.6 -> 3.7 s). With two threads set at run
// time the result was the same with the process started on one CPU (taskset), with
// OPENBLAS_NUM_THREADS=1 and with 8.

namespace quadcage::detail {

/// BLAS threads of the factorisations (the fit's small ones, under 1e9 flops, run on one:
/// fit/detail/normal_equations.cpp).
inline constexpr int kBlasThreads = 2;

/// Sets OpenBLAS's thread count to `threads` for the object's lifetime and restores it after. Does
/// nothing to the count when the BLAS in the process is not OpenBLAS (reference BLAS and ATLAS have
/// no threads to set). OpenBLAS's count is process-wide, so the scopes of the whole process share it
/// in turns: scopes asking for the same count run together, and a scope asking for another count
/// waits until none is open (no queue: it waits while scopes of the open count keep overlapping;
/// the layout's threads open one-thread scopes a solve at a time, and a level-1 score's
/// factorisations are one-thread ones too). Each factorisation then runs on the count it asked for,
/// whatever runs beside it: the layout's constructions, built side by side, and the fits that score
/// them (quad_layout.cpp) keep their bits. A thread may nest scopes of the count it holds (another
/// count there would wait for itself: InternalError). Keep the scopes round the BLAS calls alone.
class ScopedBlasThreads {
public:
    explicit ScopedBlasThreads(int threads = kBlasThreads);
    ~ScopedBlasThreads();
    ScopedBlasThreads(const ScopedBlasThreads&) = delete;
    ScopedBlasThreads& operator=(const ScopedBlasThreads&) = delete;
};

}  // namespace quadcage::detail
