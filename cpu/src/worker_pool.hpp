// Internal to logrid::cpu: a pool of worker threads that knows nothing of the work it
// runs (the CPU occlusion buffer hands it set-up and raster jobs; the buffer's data stay
// in the buffer, as the masked occlusion culler keeps its thread pool apart from its
// buffer). Tasks are plain function pointers with a context and an index: no allocation
// per task.
//
// The caller works too: while it waits (wait(), forEach) it runs queued tasks itself, as
// worker size(), so a pool of N threads puts N + 1 threads on the work, and a pool of no
// thread is a queue the caller runs in wait(). Waking a sleeping worker costs tens of
// microseconds on a loaded machine; the caller never waits for a wake-up to get work done.
//
// Ordering: tasks start in the order posted, and a worker (the caller included) takes the
// next task only after finishing its last, so the tasks one worker runs are in the order
// they were posted. wait() returns once every task posted so far is done, and everything
// they wrote is then visible to the caller (the queue's mutex orders it). One caller at a
// time: post, forEach and wait must not be called from several threads at once, nor from
// a task.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <mutex>
#include <thread>
#include <vector>

namespace logrid::cpu::detail {

class WorkerPool {
 public:
  // `worker` is the index of the thread running the task, in [0, size()]; size() is the
  // caller.
  using TaskFunction = void (*)(void* context, std::uint32_t worker, std::size_t index);

  explicit WorkerPool(std::uint32_t threads);
  ~WorkerPool();  // finishes every task posted, then joins the threads
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  std::uint32_t size() const { return std::uint32_t(threads_.size()); }  // threads started

  // Queues run(context, worker, index) for a worker; returns at once.
  void post(TaskFunction run, void* context, std::size_t index);
  // Runs run(context, worker, i) for every i in [0, count), each once, on the workers and
  // the caller (each takes the next i left, in increasing order), and returns when they
  // and every task posted before are done. Tasks posted before may still be running when
  // the first i starts: wait() first where the jobs need them done.
  void forEach(std::size_t count, TaskFunction run, void* context);
  // Runs queued tasks until none is left, then returns when every task posted so far is
  // done.
  void wait();
  // Seconds the threads started spent running tasks, summed (the caller's not counted);
  // read after wait().
  double busySeconds() const;

 private:
  struct Task {
    TaskFunction run;
    void* context;
    std::size_t index;
  };
  void work(std::uint32_t worker);
  static void claim(void* pool, std::uint32_t worker, std::size_t unused);

  std::vector<std::thread> threads_;
  std::vector<double> busy_;  // per worker, written by that worker only
  std::mutex mutex_;
  std::condition_variable work_cv_, done_cv_;
  std::deque<Task> queue_;
  std::uint64_t posted_ = 0, finished_ = 0;
  bool stop_ = false;
  // forEach's range, fixed while it runs.
  TaskFunction range_run_ = nullptr;
  void* range_context_ = nullptr;
  std::size_t range_count_ = 0;
  std::atomic<std::size_t> range_next_{0};
};

}  // namespace logrid::cpu::detail
