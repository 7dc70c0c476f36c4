#include "worker_pool.hpp"

#include <chrono>
#include <numeric>

#include "logrid/elapsed.hpp"

namespace logrid::cpu::detail {

WorkerPool::WorkerPool(std::uint32_t threads) : busy_(threads, 0.0) {
  threads_.reserve(threads);
  for (std::uint32_t w = 0; w < threads; ++w) threads_.emplace_back([this, w] { work(w); });
}

WorkerPool::~WorkerPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  work_cv_.notify_all();
  for (std::thread& t : threads_) t.join();
}

void WorkerPool::post(TaskFunction run, void* context, std::size_t index) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    queue_.push_back({run, context, index});
    ++posted_;
  }
  work_cv_.notify_one();
}

void WorkerPool::claim(void* pool, std::uint32_t worker, std::size_t) {
  WorkerPool& p = *static_cast<WorkerPool*>(pool);
  for (std::size_t i = p.range_next_.fetch_add(1, std::memory_order_relaxed); i < p.range_count_;
       i = p.range_next_.fetch_add(1, std::memory_order_relaxed)) {
    p.range_run_(p.range_context_, worker, i);
  }
}

void WorkerPool::forEach(std::size_t count, TaskFunction run, void* context) {
  if (count == 0) {
    wait();
    return;
  }
  {
    // Written before the tasks are queued (under the mutex the workers take them with).
    std::lock_guard<std::mutex> lock(mutex_);
    range_run_ = run;
    range_context_ = context;
    range_count_ = count;
    range_next_.store(0, std::memory_order_relaxed);
    const std::size_t tasks = std::min<std::size_t>(count - 1, threads_.size());
    for (std::size_t t = 0; t < tasks; ++t) queue_.push_back({&WorkerPool::claim, this, 0});
    posted_ += tasks;
    if (tasks > 0) work_cv_.notify_all();
  }
  claim(this, size(), 0);
  wait();
}

void WorkerPool::wait() {
  std::unique_lock<std::mutex> lock(mutex_);
  while (!queue_.empty()) {
    const Task task = queue_.front();
    queue_.pop_front();
    lock.unlock();
    task.run(task.context, size(), task.index);
    lock.lock();
    ++finished_;
  }
  done_cv_.wait(lock, [&] { return finished_ == posted_; });
}

double WorkerPool::busySeconds() const { return std::accumulate(busy_.begin(), busy_.end(), 0.0); }

void WorkerPool::work(std::uint32_t worker) {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    work_cv_.wait(lock, [&] { return stop_ || !queue_.empty(); });
    if (queue_.empty()) return;  // stopping, nothing left
    const Task task = queue_.front();
    queue_.pop_front();
    lock.unlock();
    const auto start = std::chrono::steady_clock::now();
    task.run(task.context, worker, task.index);
    busy_[worker] += secondsSince(start);
    lock.lock();
    if (++finished_ == posted_) done_cv_.notify_all();
  }
}

}  // namespace logrid::cpu::detail
