#include "worker_pool.h"

#include <algorithm>
#include <chrono>

namespace hope {
namespace parallel {
namespace {

// How long a thread that has just finished looks for what comes next before it sleeps.
constexpr std::chrono::microseconds kLookAhead{200};

// Yields the core until done() or kLookAhead has passed; returns done().
template <class Done>
bool yieldUntil(Done done) {
  const auto until = std::chrono::steady_clock::now() + kLookAhead;
  for (int polls = 0; !done(); ++polls) {
    if ((polls & 15) == 15 && std::chrono::steady_clock::now() >= until) return done();
    std::this_thread::yield();
  }
  return true;
}

}  // namespace

WorkerPool& WorkerPool::shared() {
  static WorkerPool pool;
  return pool;
}

WorkerPool::~WorkerPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  job_posted_.notify_all();
  for (std::thread& thread : threads_) thread.join();
}

std::size_t WorkerPool::startedThreads() {
  std::lock_guard<std::mutex> lock(mutex_);
  return threads_.size();
}

void WorkerPool::runTasks(const std::function<void(std::size_t)>& task, std::size_t count) {
  for (std::size_t i = next_task_.fetch_add(1, std::memory_order_relaxed); i < count;
       i = next_task_.fetch_add(1, std::memory_order_relaxed)) {
    task(i);
  }
}

void WorkerPool::run(std::size_t count, int helpers, const std::function<void(std::size_t)>& task) {
  helpers = static_cast<int>(std::min<std::size_t>(std::max(0, helpers), count ? count - 1 : 0));
  std::unique_lock<std::mutex> caller(caller_mutex_, std::try_to_lock);
  if (helpers == 0 || !caller.owns_lock()) {
    for (std::size_t i = 0; i < count; ++i) task(i);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    while (threads_.size() < static_cast<std::size_t>(helpers)) {
      threads_.emplace_back([this] { help(); });
    }
    task_ = &task;
    count_ = count;
    next_task_.store(0, std::memory_order_relaxed);
    open_seats_ = helpers;
    job_.fetch_add(1, std::memory_order_release);
  }
  job_posted_.notify_all();
  runTasks(task, count);
  // Every task is claimed. Close the job, so that a helper woken only now stays asleep, and
  // wait for the helpers still running a task they claimed.
  std::unique_lock<std::mutex> lock(mutex_);
  open_seats_ = 0;
  lock.unlock();
  const auto helpers_done = [this] { return helpers_working_.load() == 0; };
  if (yieldUntil(helpers_done)) return;
  lock.lock();
  helpers_left_.wait(lock, helpers_done);
}

void WorkerPool::help() {
  std::uint64_t last_job = 0;
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    lock.unlock();
    yieldUntil([&] { return stopping_ || job_.load(std::memory_order_acquire) != last_job; });
    lock.lock();
    job_posted_.wait(lock, [&] { return stopping_ || (open_seats_ > 0 && job_ != last_job); });
    if (stopping_) return;
    last_job = job_;
    --open_seats_;
    helpers_working_.fetch_add(1);
    const std::function<void(std::size_t)>& task = *task_;
    const std::size_t count = count_;
    lock.unlock();
    runTasks(task, count);
    lock.lock();
    if (helpers_working_.fetch_sub(1) == 1) helpers_left_.notify_one();
  }
}

}  // namespace parallel
}  // namespace hope
