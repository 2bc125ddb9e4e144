#pragma once
/// One thread pool primitive for the whole project: run independent jobs on
/// several threads and carry the first exception back to the caller (a worker
/// that throws must not end in std::terminate).
#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

namespace cmr {

/// The cores this thread may run on: its CPU affinity (taskset, a container's
/// cpuset, a CI runner's limit), which std::thread::hardware_concurrency
/// ignores; every online core where the affinity cannot be read.
inline int available_cores() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) == 0 && CPU_COUNT(&set) > 0) return CPU_COUNT(&set);
  return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

/// The number of worker threads to use for `threads` (0: every available core).
inline int thread_count(int threads) { return threads > 0 ? threads : available_cores(); }

/// Calls job(i) for every i in [0, count), on up to thread_count(threads)
/// threads including the caller's; jobs are handed out in increasing order.
/// When a job throws, no further jobs start, the running ones finish, and the
/// first exception is rethrown here once every worker has stopped.
template <class Job>
void parallel_for(std::size_t count, int threads, Job&& job) {
  const std::size_t workers = std::min<std::size_t>(static_cast<std::size_t>(thread_count(threads)), count);
  std::atomic<std::size_t> next{0};
  std::atomic<bool> failed{false};
  std::exception_ptr first_error;
  std::mutex error_mutex;
  auto work = [&] {
    for (std::size_t i = next++; i < count && !failed; i = next++) {
      try {
        job(i);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(error_mutex);
        if (!first_error) first_error = std::current_exception();
        failed = true;
      }
    }
  };
  std::vector<std::thread> pool;
  for (std::size_t t = 1; t < workers; ++t) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
  if (first_error) std::rethrow_exception(first_error);
}

/// Worker threads started once and kept for the process: run() has
/// parallel_for's contract (job(i) for every i in [0, count) on up to
/// thread_count(threads) threads including the caller's, in increasing
/// order, the first exception rethrown once all stopped) without starting a
/// thread per call. A frame of a few milliseconds (a 512x512 region) paid
/// about 0.1 ms per started thread. One batch runs at a time; a call made
/// while the pool is busy (another thread's batch, or a job that calls run()
/// again) is handed to parallel_for, so it never waits for the pool.
class WorkerPool {
 public:
  /// The process's pool: never destroyed (its threads sleep until exit).
  static WorkerPool& shared() {
    static WorkerPool* pool = new WorkerPool;
    return *pool;
  }

  template <class Job>
  void run(std::size_t count, int threads, Job&& job) {
    const std::size_t workers = std::min<std::size_t>(static_cast<std::size_t>(thread_count(threads)), count);
    std::unique_lock<std::mutex> busy(busy_, std::try_to_lock);
    if (workers <= 1 || !busy.owns_lock()) {
      parallel_for(count, threads, std::forward<Job>(job));
      return;
    }
    std::atomic<std::size_t> next{0};
    std::atomic<bool> failed{false};
    std::exception_ptr first_error;
    std::mutex error_mutex;
    std::function<void()> work = [&] {
      for (std::size_t i = next++; i < count && !failed; i = next++) {
        try {
          job(i);
        } catch (...) {
          const std::lock_guard<std::mutex> lock(error_mutex);
          if (!first_error) first_error = std::current_exception();
          failed = true;
        }
      }
    };
    {
      std::lock_guard<std::mutex> lock(mutex_);
      for (; threads_.size() + 1 < workers; steered_from_ = -1) threads_.emplace_back([this] { serve(); });
      steer_off(sched_getcpu());
      work_ = &work;
      wanted_ = workers - 1;
      running_ = 0;
      ++batch_;
    }
    wake_.notify_all();
    work();
    // The batch's last jobs are running on workers: poll for them a while
    // before sleeping, since a caller put to sleep is woken late (as a worker
    // is: up to 70 us after the last job on this project's VM).
    poll_until([&] { return running_.load(std::memory_order_acquire) == 0; }, kTailPoll);
    {
      std::unique_lock<std::mutex> lock(mutex_);
      // Every worker that took the batch has finished it; none takes it later.
      done_.wait(lock, [&] { return running_ == 0; });
      wanted_ = 0;
      work_ = nullptr;
    }
    if (first_error) std::rethrow_exception(first_error);
  }

  /// A batch is coming soon: the sleeping workers wake now and poll for it
  /// for up to kWakePoll, so that the time they take to wake (20-130 us on
  /// this project's VM, longer the longer they slept) passes while the
  /// caller prepares the batch. Without a batch in that time they sleep
  /// again, having spent at most kWakePoll of a core each.
  void wake() {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      if (threads_.empty()) return;
      ++wakes_;
    }
    wake_.notify_all();
  }

 private:
  WorkerPool() = default;
  void serve() {
    std::uint64_t seen = 0, woken = 0;
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      const auto joinable = [&] { return batch_.load(std::memory_order_relaxed) != seen && wanted_ > 0; };
      wake_.wait(lock, [&] { return joinable() || wakes_ != woken; });
      if (!joinable()) {  // wake(): poll for the batch, then sleep again
        woken = wakes_;
        const std::uint64_t before = batch_;
        lock.unlock();
        poll_until([&] { return batch_.load(std::memory_order_acquire) != before; }, kWakePoll);
        lock.lock();
        continue;
      }
      seen = batch_;
      woken = wakes_;  // a wake() for this batch is answered by joining it
      --wanted_;
      ++running_;
      std::function<void()>* work = work_;
      lock.unlock();
      (*work)();
      lock.lock();
      if (--running_ == 0) done_.notify_all();
    }
  }
  // Polls `ready` until it holds or `limit` has passed.
  template <class Ready>
  static void poll_until(Ready&& ready, std::chrono::microseconds limit) {
    const auto end = std::chrono::steady_clock::now() + limit;
    while (!ready() && std::chrono::steady_clock::now() < end) {
#if defined(__x86_64__) || defined(__i386__)
      __builtin_ia32_pause();
#endif
    }
  }
  static constexpr std::chrono::microseconds kTailPoll{1000}, kWakePoll{300};
  // Keeps the sleeping workers off the caller's core. Woken, a worker is
  // queued where the kernel places it, and on this project's VM, after an
  // idle millisecond, that was the caller's own core, busy with the batch
  // (likely because a halted virtual core counts as preempted, not idle):
  // in 4 of 10 batches the worker did not start within 0.6 ms, and a frame
  // of a drag ran on one core (tools/bench/bench_wake; docs/performance.md,
  // "An idle core joins late"). Each worker may run on any core the caller may
  // but the caller's own; redone only when the caller has moved. A caller
  // bound to one core leaves the workers as they are.
  void steer_off(int cpu) {
    if (cpu < 0 || cpu == steered_from_) return;
    cpu_set_t allowed;
    CPU_ZERO(&allowed);
    if (sched_getaffinity(0, sizeof allowed, &allowed) != 0 || !CPU_ISSET(cpu, &allowed)) return;
    CPU_CLR(cpu, &allowed);
    if (CPU_COUNT(&allowed) == 0) return;
    for (std::thread& t : threads_) (void)pthread_setaffinity_np(t.native_handle(), sizeof allowed, &allowed);
    steered_from_ = cpu;
  }
  int steered_from_ = -1;  // the caller's core the workers were last kept off
  std::mutex busy_;   // held by the batch's caller
  std::mutex mutex_;  // guards what follows
  std::condition_variable wake_, done_;
  std::vector<std::thread> threads_;
  std::function<void()>* work_ = nullptr;
  // Workers still to join the batch, and in it (changed under mutex_;
  // running_ is also polled without it).
  std::size_t wanted_ = 0;
  std::atomic<std::size_t> running_{0};
  std::atomic<std::uint64_t> batch_{0};  // batches begun (changed under mutex_, polled without it)
  std::uint64_t wakes_ = 0;              // wake() calls
};

/// A pipeline whose output stays in order: produce(i) for every i in
/// [0, count) on up to thread_count(threads) worker threads, and consume(r)
/// of each result on the calling thread in increasing i (a streamed output:
/// cmr analyze's JSON, report/analyze_json.hpp). Jobs are handed out in
/// increasing order, and job i starts only once result i - window has been
/// consumed, so at most `window` results exist at a time (memory stays that
/// of `window` results, whatever count is). With one thread (or one job) it
/// is the plain loop consume(produce(i)) on the calling thread. When produce
/// or consume throws, no further job starts and no further result is
/// consumed; the first exception is rethrown here once every worker stopped.
template <class Produce, class Consume>
void parallel_ordered(std::size_t count, int threads, std::size_t window, Produce&& produce, Consume&& consume) {
  using Result = std::invoke_result_t<Produce&, std::size_t>;
  const std::size_t workers = std::min<std::size_t>(static_cast<std::size_t>(thread_count(threads)), count);
  if (workers <= 1) {
    for (std::size_t i = 0; i < count; ++i) consume(produce(i));
    return;
  }
  window = std::max(window, workers);
  std::vector<std::optional<Result>> slots(window);  // result i in slot i % window
  std::mutex mutex;
  std::condition_variable changed;
  std::size_t next = 0, consumed = 0;  // guarded by mutex
  bool failed = false;
  std::exception_ptr first_error;
  const auto fail = [&](std::exception_ptr e) {
    const std::lock_guard<std::mutex> lock(mutex);
    if (!first_error) first_error = std::move(e);
    failed = true;
  };
  auto work = [&] {
    for (;;) {
      std::size_t i = 0;
      {
        std::unique_lock<std::mutex> lock(mutex);
        changed.wait(lock, [&] { return failed || next >= count || next < consumed + window; });
        if (failed || next >= count) return;
        i = next++;
      }
      try {
        Result r = produce(i);
        const std::lock_guard<std::mutex> lock(mutex);
        slots[i % window].emplace(std::move(r));
      } catch (...) {
        fail(std::current_exception());
      }
      changed.notify_all();
    }
  };
  std::vector<std::thread> pool;
  for (std::size_t t = 0; t < workers; ++t) pool.emplace_back(work);
  try {
    for (std::size_t i = 0; i < count; ++i) {
      std::optional<Result> r;
      {
        std::unique_lock<std::mutex> lock(mutex);
        changed.wait(lock, [&] { return failed || slots[i % window].has_value(); });
        if (failed) break;
        r.swap(slots[i % window]);
        ++consumed;
      }
      changed.notify_all();
      consume(std::move(*r));
    }
  } catch (...) {
    fail(std::current_exception());
  }
  changed.notify_all();
  for (std::thread& t : pool) t.join();
  if (first_error) std::rethrow_exception(first_error);
}

}  // namespace cmr
