#include "spline/parallel.hpp"

#include <gtest/gtest.h>
#include <sched.h>
#include <time.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <mutex>
#include <stdexcept>
#include <thread>
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

TEST(WorkerPool, VisitsEveryIndexOnceBatchAfterBatchOnTheSameThreads) {
  WorkerPool& pool = WorkerPool::shared();
  for (int batch = 0; batch < 200; ++batch) {
    const int threads = batch % 4 + 1;
    std::vector<std::atomic<int>> seen(static_cast<std::size_t>(batch % 7) * 50);
    pool.run(seen.size(), threads, [&](std::size_t i) { ++seen[i]; });
    for (std::size_t i = 0; i < seen.size(); ++i) ASSERT_EQ(seen[i].load(), 1) << "index " << i << ", batch " << batch;
  }
}

// Waits `us` microseconds on a core (a job that takes time, so that the
// other threads take some of the batch).
void busy_for(int us) {
  for (const auto end = std::chrono::steady_clock::now() + std::chrono::microseconds(us);
       std::chrono::steady_clock::now() < end;) {
  }
}

// The cores this process may run on (its affinity; none where it cannot be read).
cpu_set_t allowed_cores() {
  cpu_set_t allowed;
  CPU_ZERO(&allowed);
  if (sched_getaffinity(0, sizeof allowed, &allowed) != 0) CPU_ZERO(&allowed);
  return allowed;
}

// A woken worker could be queued on the caller's own busy core
// (WorkerPool::steer_off): each worker may run on every core the caller
// may but the one the caller is on when the batch begins.
TEST(WorkerPool, KeepsItsWorkersOffTheCallersCore) {
  const cpu_set_t allowed = allowed_cores();
  if (CPU_COUNT(&allowed) < 2) GTEST_SKIP() << "a single core: no other core to keep the workers on";
  WorkerPool& pool = WorkerPool::shared();
  const std::thread::id caller = std::this_thread::get_id();
  // The caller may move between cores during a batch; such a batch proves
  // nothing and is tried again.
  for (int attempt = 0; attempt < 50; ++attempt) {
    const int before = sched_getcpu();
    std::mutex m;
    std::vector<cpu_set_t> masks;  // each worker job's own affinity
    pool.run(64, 2, [&](std::size_t) {
      if (std::this_thread::get_id() != caller) {
        cpu_set_t mine;
        CPU_ZERO(&mine);
        ASSERT_EQ(sched_getaffinity(0, sizeof mine, &mine), 0);
        const std::lock_guard<std::mutex> lock(m);
        masks.push_back(mine);
      }
      busy_for(20);
    });
    if (sched_getcpu() != before || masks.empty()) continue;
    for (cpu_set_t& mine : masks) {
      EXPECT_FALSE(CPU_ISSET(before, &mine)) << "a worker may run on the caller's core " << before;
      EXPECT_EQ(CPU_COUNT(&mine), CPU_COUNT(&allowed) - 1) << "a worker may not run on every other core";
    }
    return;
  }
  FAIL() << "in 50 batches the caller never stayed on one core with a worker joining";
}

TEST(WorkerPool, CarriesAnExceptionAndStaysUsable) {
  WorkerPool& pool = WorkerPool::shared();
  std::atomic<int> ran{0};
  // Every other job takes a millisecond: the 10,000 would take seconds on 4
  // threads, so the batch stopping after job 17 is seen even when the
  // throwing thread is preempted (with instant jobs, the other threads ran
  // all 10,000 before it set the flag on a loaded machine).
  EXPECT_THROW(pool.run(10000, 4,
                        [&](std::size_t i) {
                          ++ran;
                          if (i == 17) throw std::runtime_error("job 17 failed");
                          std::this_thread::sleep_for(std::chrono::milliseconds(1));
                        }),
               std::runtime_error);
  EXPECT_LT(ran.load(), 1000);
  std::atomic<int> after{0};
  pool.run(100, 4, [&](std::size_t) { ++after; });
  EXPECT_EQ(after.load(), 100);
}

TEST(WorkerPool, NestedAndConcurrentCallsNeverWait) {
  // A job that calls run() again, and two threads running batches at once:
  // the busy pool hands them to parallel_for instead of deadlocking.
  WorkerPool& pool = WorkerPool::shared();
  std::atomic<int> inner{0};
  pool.run(8, 4, [&](std::size_t) { pool.run(10, 2, [&](std::size_t) { ++inner; }); });
  EXPECT_EQ(inner.load(), 80);
  std::atomic<int> total{0};
  std::vector<std::thread> callers;
  for (int c = 0; c < 4; ++c)
    callers.emplace_back([&] {
      for (int k = 0; k < 50; ++k) pool.run(64, 3, [&](std::size_t) { ++total; });
    });
  for (std::thread& t : callers) t.join();
  EXPECT_EQ(total.load(), 4 * 50 * 64);
}

// CPU seconds of this process, every thread (a thread's time is added when
// it sleeps or at a tick).
double process_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// WorkerPool::wake: a batch announced ahead runs as any other; a wake()
// that no batch follows, or one made while another thread's batch runs,
// leaves the pool as it was.
TEST(WorkerPool, AWakeIsOnlyAHint) {
  WorkerPool& pool = WorkerPool::shared();
  pool.run(8, 2, [](std::size_t) {});  // the workers exist
  for (int k = 0; k < 50; ++k) {
    pool.wake();
    if (k % 3 == 0) std::this_thread::sleep_for(std::chrono::microseconds(500));  // its polling ran out
    std::vector<std::atomic<int>> seen(static_cast<std::size_t>(k % 5) * 40 + 1);
    pool.run(seen.size(), 0, [&](std::size_t i) { ++seen[i]; });
    for (std::size_t i = 0; i < seen.size(); ++i) ASSERT_EQ(seen[i].load(), 1) << "index " << i << ", batch " << k;
  }
  std::atomic<bool> stop{false};
  std::thread waker([&] {
    while (!stop) pool.wake();
  });
  std::atomic<int> total{0};
  for (int k = 0; k < 50; ++k) pool.run(64, 0, [&](std::size_t) { ++total; });
  stop = true;
  waker.join();
  EXPECT_EQ(total.load(), 50 * 64);
}

// A woken worker polls for the announced batch for a bounded time only, and
// one that joined the batch does not poll again for it afterwards (it did
// for 0.3 ms after every region render while the wake stayed unanswered).
TEST(WorkerPool, AWakeCostsABoundedPollAndNoneOnceTheBatchIsJoined) {
  const cpu_set_t allowed = allowed_cores();
  if (CPU_COUNT(&allowed) < 2) GTEST_SKIP() << "a single core: the pool has no worker to wake";
  WorkerPool& pool = WorkerPool::shared();
  const std::thread::id caller = std::this_thread::get_id();
  const double workers = CPU_COUNT(&allowed) - 1;
  pool.run(8, 0, [](std::size_t) {});
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  double c0 = process_cpu_seconds();
  pool.wake();
  std::this_thread::sleep_for(std::chrono::milliseconds(30));
  // Each worker polls at most 0.3 ms.
  EXPECT_LT(process_cpu_seconds() - c0, workers * 0.3e-3 + 2e-3) << "a wake() with no batch kept a worker busy";
  // Announced batches that a worker joined: afterwards nothing polls. Each
  // worker's own CPU clock is read (exact, where the process's clock counts
  // a thread's time only when it next sleeps). Tried a few times, since on a
  // loaded machine a worker may not join in time.
  std::vector<double> after;
  for (int attempt = 0; attempt < 20 && after.size() < 5; ++attempt) {
    std::mutex m;
    std::vector<clockid_t> clocks;  // of the workers that ran a job
    pool.wake();
    busy_for(30);
    pool.run(64, 0, [&](std::size_t) {
      if (std::this_thread::get_id() != caller) {
        clockid_t c;
        ASSERT_EQ(pthread_getcpuclockid(pthread_self(), &c), 0);
        const std::lock_guard<std::mutex> lock(m);
        if (std::find(clocks.begin(), clocks.end(), c) == clocks.end()) clocks.push_back(c);
      }
      busy_for(10);
    });
    const auto workers_cpu = [&] {
      double sum = 0;
      for (const clockid_t c : clocks) {
        timespec t{};
        clock_gettime(c, &t);
        sum += static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
      }
      return sum;
    };
    const double w0 = workers_cpu();
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    if (!clocks.empty()) after.push_back((workers_cpu() - w0) / static_cast<double>(clocks.size()));
  }
  if (after.empty()) GTEST_SKIP() << "no worker joined an announced batch (a loaded machine)";
  std::sort(after.begin(), after.end());
  // Per worker, the median attempt: its way back to sleep (microseconds); a
  // poll would add 0.3 ms.
  EXPECT_LT(after[after.size() / 2], 0.1e-3)
      << "workers polled after joining the batch they were woken for";
}

TEST(ParallelOrdered, ConsumesEveryResultInOrderWithABoundedWindow) {
  for (int threads : {1, 2, 3, 8})
    for (std::size_t window : {1u, 2u, 5u}) {
      std::atomic<int> live{0}, peak{0};  // results produced and not yet consumed
      std::vector<std::size_t> order;
      parallel_ordered(
          500, threads, window,
          [&](std::size_t i) {
            const int now = ++live;
            for (int p = peak.load(); now > p && !peak.compare_exchange_weak(p, now);) {
            }
            if (i % 7 == 0) std::this_thread::yield();  // out-of-order completion
            return std::vector<std::size_t>(3, i);
          },
          [&](std::vector<std::size_t> r) {
            --live;
            ASSERT_EQ(r.size(), 3u);
            order.push_back(r[0]);
          });
      ASSERT_EQ(order.size(), 500u) << "threads " << threads << ", window " << window;
      for (std::size_t i = 0; i < order.size(); ++i)
        ASSERT_EQ(order[i], i) << "threads " << threads << ", window " << window;
      // Job i starts once result i - window was consumed (the window is at
      // least the worker count); +1: `live` drops only after the slot is free.
      const int allowed = static_cast<int>(std::max<std::size_t>(window, static_cast<std::size_t>(threads))) + 1;
      EXPECT_LE(peak.load(), allowed) << "threads " << threads << ", window " << window;
    }
}

TEST(ParallelOrdered, CarriesAnExceptionAndStopsConsuming) {
  for (int threads : {1, 2, 4}) {
    std::size_t consumed = 0;
    EXPECT_THROW(parallel_ordered(
                     10000, threads, 4,
                     [&](std::size_t i) {
                       if (i == 17) throw std::runtime_error("job 17 failed");
                       return i;
                     },
                     [&](std::size_t i) {
                       EXPECT_LT(i, 17u) << "consumed past the failed job, threads " << threads;
                       ++consumed;
                     }),
                 std::runtime_error)
        << "threads " << threads;
    EXPECT_LE(consumed, 17u);
    // A consumer that throws stops the producers too.
    std::atomic<int> produced{0};
    EXPECT_THROW(parallel_ordered(
                     10000, threads, 4, [&](std::size_t i) {
                       ++produced;
                       return i;
                     },
                     [&](std::size_t i) {
                       if (i == 3) throw std::runtime_error("write failed");
                     }),
                 std::runtime_error);
    EXPECT_LT(produced.load(), 100) << "threads " << threads;
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
