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

// "Every core" means the cores the process may use (taskset, a cpuset), not
// every core of the machine: limited to one core, the pool has one thread.
TEST(ThreadCount, FollowsTheCpuAffinity) {
  cpu_set_t before;
  ASSERT_EQ(sched_getaffinity(0, sizeof before, &before), 0);
  EXPECT_EQ(thread_count(0), CPU_COUNT(&before));
  EXPECT_EQ(thread_count(3), 3);
  int first = 0;
  while (!CPU_ISSET(first, &before)) ++first;
  cpu_set_t one;
  CPU_ZERO(&one);
  CPU_SET(first, &one);
  ASSERT_EQ(sched_setaffinity(0, sizeof one, &one), 0);
  const int limited = thread_count(0);
  ASSERT_EQ(sched_setaffinity(0, sizeof before, &before), 0);
  EXPECT_EQ(limited, 1);
}

}  // namespace
}  // namespace cmr
