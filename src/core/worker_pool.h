// The threads behind parallel.h: a few long-lived helper threads that sleep while there is
// nothing to do. Private to the core library.
//
// Why not OpenMP: libgomp's idle threads spin (OMP_WAIT_POLICY=active unless the environment
// says otherwise, read once when the library loads), and a thread that spins at a barrier
// holds a core that the thread with the remaining work needs. On a robot where other nodes
// keep a core busy, a 3.6 ms frame took 61 ms on two threads. Here a helper that has nothing
// to do sleeps on a condition variable, and the calling thread never waits for a helper to
// start: it takes every task no helper has claimed yet, so a helper that the scheduler wakes
// late costs nothing but its wake-up. A thread that has just finished (a helper its task, the
// caller its share) looks for what comes next for a few tens of microseconds, yielding the
// core to anyone else who wants it, before it sleeps: the passes of one frame follow each
// other closely, and a wake-up from sleep costs as much.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace hope {
namespace parallel {

class WorkerPool {
 public:
  // The process's pool, its threads started when first asked for.
  static WorkerPool& shared();

  // Runs task(i) for every i in [0, count): on the calling thread and on up to `helpers` pool
  // threads, each task on exactly one thread, tasks claimed in increasing order. Returns when
  // every task has run. When another thread is running tasks on the pool (two extractors in
  // two threads, or a task that asks for threads itself) every task runs on the calling
  // thread, so callers never wait for each other. Tasks must not throw.
  void run(std::size_t count, int helpers, const std::function<void(std::size_t)>& task);

  // The number of helper threads started so far (for tests).
  std::size_t startedThreads();

  ~WorkerPool();

 private:
  WorkerPool() = default;
  void help();
  // Claims and runs tasks of the current job until none is left.
  void runTasks(const std::function<void(std::size_t)>& task, std::size_t count);

  std::mutex caller_mutex_;  // one caller's job at a time

  std::mutex mutex_;  // guards everything below but the atomics
  std::condition_variable job_posted_;
  std::condition_variable helpers_left_;
  std::vector<std::thread> threads_;
  const std::function<void(std::size_t)>* task_ = nullptr;
  std::size_t count_ = 0;
  std::atomic<std::uint64_t> job_{0};  // incremented for every job posted
  int open_seats_ = 0;                 // helpers that may still join the current job
  std::atomic<bool> stopping_{false};
  std::atomic<std::size_t> next_task_{0};
  std::atomic<int> helpers_working_{0};
};

}  // namespace parallel
}  // namespace hope
