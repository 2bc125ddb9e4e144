#include "spline/parallel.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

namespace cmr {
namespace {

TEST(ParallelFor, VisitsEveryIndexOnce) {
  for (int threads : {0, 1, 2, 7}) {
    std::vector<std::atomic<int>> seen(1000);
    parallel_for(seen.size(), threads, [&](std::size_t i) { ++seen[i]; });
    for (std::size_t i = 0; i < seen.size(); ++i) ASSERT_EQ(seen[i].load(), 1) << "index " << i << ", threads " << threads;
  }
}

TEST(ParallelFor, NoJobsIsFine) {
  parallel_for(0, 4, [](std::size_t) { FAIL() << "no job should run"; });
}

TEST(ParallelFor, CarriesAWorkersExceptionToTheCaller) {
  for (int threads : {1, 2, 4}) {
    std::atomic<int> ran{0};
    EXPECT_THROW(parallel_for(10000, threads,
                              [&](std::size_t i) {
                                ++ran;
                                if (i == 17) throw std::runtime_error("job 17 failed");
                              }),
                 std::runtime_error)
        << "threads " << threads;
    EXPECT_LT(ran.load(), 10000) << "jobs kept starting after the failure, threads " << threads;
  }
}

}  // namespace
}  // namespace cmr
