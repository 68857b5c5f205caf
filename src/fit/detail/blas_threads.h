#pragma once
// The BLAS thread count during the fit's factorisations (private to src/fit).
//
// CHOLMOD's supernodal factorisation runs its dense updates through BLAS and LAPACK. OpenBLAS, which
// Debian's libblas.so.3 usually resolves to, picks one thread per core by default, and its one-thread
// kernels round differently from its threaded ones: eight.off fitted at level 3 ended in other bits
// with OPENBLAS_NUM_THREADS=1 than with 2, 3 or 4. A fit's output would then depend on the machine's
// core count, not only on the input and the options. Within a ScopedBlasThreads the BLAS uses a
// fixed count, so the fit is the same on every machine with the same build, libraries and CPU model
// (OpenBLAS picks its kernels by CPU model). One thread (issue #19): with two, OpenBLAS's second
// thread spins (sched_yield) between and after the many small BLAS calls of a supernodal
// factorisation, on a 2-core machine taking a core from the fit's own threads; a profile of
// botijo's fit found it yielding for about an eighth of the fit's CPU time. On a loaded 2-core
// machine botijo's fit took 11.7-15.1 s with one thread against 14.1-18.2 s with two (solve 3.2-4.1 s
// against 4.7-5.0 s). (CHOLMOD's own OpenMP team, whose loops ask
// for CHOLMOD_OMP_NUM_THREADS = 4 threads, spins as well; omp_set_num_threads(1) around the
// factorisation did not stop it, so it is left alone.)

namespace quadcage::fit::detail {

/// BLAS threads of the fit's factorisations.
inline constexpr int kBlasThreads = 1;

/// Sets OpenBLAS's thread count to `threads` for the object's lifetime and restores it after. Does
/// nothing when the BLAS in the process is not OpenBLAS (reference BLAS and ATLAS have no threads
/// to set). OpenBLAS's count is process-wide: a concurrent BLAS call elsewhere in the process runs
/// on `threads` meanwhile.
class ScopedBlasThreads {
public:
    explicit ScopedBlasThreads(int threads = kBlasThreads);
    ~ScopedBlasThreads();
    ScopedBlasThreads(const ScopedBlasThreads&) = delete;
    ScopedBlasThreads& operator=(const ScopedBlasThreads&) = delete;

private:
    int previous_ = 0;  ///< 0: nothing to restore.
};

}  // namespace quadcage::fit::detail
