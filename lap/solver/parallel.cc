#include "lap/solver/parallel.h"

#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>

namespace ttz::lap {
namespace {

// Worker p (p >= 1) runs part p of every job that has more than p parts; jobs are numbered, and a
// worker waits for a number it has not seen.
class WorkerPool {
 public:
  ~WorkerPool() {
    {
      std::lock_guard<std::mutex> lock(m_);
      stop_ = true;
    }
    start_.notify_all();
    for (std::thread& t : workers_) t.join();
  }

  void Run(int parts, const std::function<void(int)>& work) {
    std::lock_guard<std::mutex> turn(turn_);  // one job at a time
    {
      std::lock_guard<std::mutex> lock(m_);
      while (static_cast<int>(workers_.size()) < parts - 1) {
        const int p = static_cast<int>(workers_.size()) + 1;
        workers_.emplace_back([this, p] { Loop(p); });
      }
      work_ = &work;
      parts_ = parts;
      pending_ = parts - 1;
      ++job_;
    }
    start_.notify_all();
    std::exception_ptr failure;  // part 0's, rethrown once the workers are done with `work`
    try {
      work(0);
    } catch (...) {
      failure = std::current_exception();
    }
    std::unique_lock<std::mutex> lock(m_);
    done_.wait(lock, [&] { return pending_ == 0; });
    if (failure) std::rethrow_exception(failure);
  }

 private:
  void Loop(int p) {
    long seen = 0;
    std::unique_lock<std::mutex> lock(m_);
    while (true) {
      start_.wait(lock, [&] { return stop_ || job_ != seen; });
      if (stop_) return;
      seen = job_;
      if (p >= parts_) continue;
      const std::function<void(int)>* work = work_;
      lock.unlock();
      (*work)(p);
      lock.lock();
      if (--pending_ == 0) done_.notify_one();
    }
  }

  std::mutex turn_, m_;
  std::condition_variable start_, done_;
  std::vector<std::thread> workers_;
  const std::function<void(int)>* work_ = nullptr;
  int parts_ = 0, pending_ = 0;
  long job_ = 0;
  bool stop_ = false;
};

}  // namespace

void RunParts(int parts, const std::function<void(int)>& work) {
  static WorkerPool pool;
  pool.Run(parts, work);
}

}  // namespace ttz::lap
