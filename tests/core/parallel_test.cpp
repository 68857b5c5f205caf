#include "quadcage/core/parallel.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

namespace quadcage {
namespace {

// Sizes around the chunking: below one thread's minimum (64 per thread), a few chunks, many.
const int kSizes[] = {0, 1, 63, 64, 129, 1000, 100003};

TEST(ParallelFor, CallsEveryIndexOnceWhateverTheThreadCount) {
    for (int threads : {0, 1, 2, 3, 7})
        for (int n : kSizes) {
            std::vector<int> calls(n, 0);
            parallel_for(n, threads, [&](int i) { ++calls[i]; });
            for (int i = 0; i < n; ++i)
                ASSERT_EQ(calls[i], 1) << "index " << i << " of " << n << ", threads " << threads;
        }
}

TEST(ParallelFor, RethrowsAnExceptionOfABodyAfterTheLoop) {
    for (int threads : {1, 2, 4}) {
        const int n = 10000;
        std::vector<char> done(n, 0);
        EXPECT_THROW(parallel_for(n, threads,
                                  [&](int i) {
                                      if (i == 5000) throw std::runtime_error("body failed");
                                      done[i] = 1;
                                  }),
                     std::runtime_error);
        EXPECT_EQ(done[5000], 0);
    }
}

}  // namespace
}  // namespace quadcage
