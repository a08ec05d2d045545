#include "service/worker_pool.h"

#include <algorithm>
#include <exception>

#include <spdlog/spdlog.h>

#include "service/cpu_quota.h"

namespace rollgap::service {

WorkerPool::WorkerPool(std::size_t workers, std::size_t interactive_capacity,
                       std::size_t batch_capacity, std::size_t batch_concurrency)
    : workers_(std::max<std::size_t>(1, workers)), interactive_capacity_(interactive_capacity),
      batch_capacity_(batch_capacity),
      batch_concurrency_(std::max<std::size_t>(1, batch_concurrency)) {
    threads_.reserve(workers_);
    for (std::size_t i = 0; i < workers_; ++i) threads_.emplace_back([this] { work(); });
}

WorkerPool::~WorkerPool() { shutdown(); }

bool WorkerPool::try_submit(Lane lane, Task task, const void* key) {
    {
        std::lock_guard lock(mutex_);
        if (stopping_) return false;
        auto& queue = lane == Lane::interactive ? interactive_ : batch_;
        const std::size_t capacity =
            lane == Lane::interactive ? interactive_capacity_ : batch_capacity_;
        // A task is refused only when it would have to wait: an idle worker takes it at once
        // even with a zero-length queue.
        const std::size_t free_workers = threads_.size() - busy_;
        // (Interactive tasks only queue behind interactive tasks: workers take them first. The
        // inner lane is left out: its helpers belong to work already admitted, and one whose
        // loop has no index left returns at once.)
        const bool starts_now = lane == Lane::interactive
                                    ? interactive_.size() < free_workers
                                    : interactive_.size() + batch_.size() < free_workers &&
                                          batch_running_ + batch_.size() < batch_concurrency_;
        if (!starts_now && queue.size() >= capacity) return false;
        queue.push_back({std::move(task), key});
    }
    wake_.notify_one();
    return true;
}

void WorkerPool::post(std::function<void()> task) {
    {
        std::lock_guard lock(mutex_);
        // Stopped with no task running: no worker may be left to take it.
        if (stopping_ && busy_ == 0) return;
        inner_.push_back(std::move(task));
    }
    wake_.notify_one();
}

bool WorkerPool::withdraw(const void* key) {
    if (key == nullptr) return false;
    Task removed;  // destroyed outside the lock: it may hold the last reference to what it captured
    std::lock_guard lock(mutex_);
    for (auto* queue : {&interactive_, &batch_}) {
        const auto found = std::find_if(queue->begin(), queue->end(),
                                        [key](const Queued& queued) { return queued.key == key; });
        if (found != queue->end()) {
            removed = std::move(found->task);
            queue->erase(found);
            return true;
        }
    }
    return false;
}

bool WorkerPool::can_take() const {
    return !inner_.empty() || !interactive_.empty() ||
           (!batch_.empty() && batch_running_ < batch_concurrency_);
}

void WorkerPool::work() {
    std::unique_lock lock(mutex_);
    for (;;) {
        wake_.wait(lock, [this] {
            return can_take() ||
                   (stopping_ && inner_.empty() && interactive_.empty() && batch_.empty());
        });
        if (!can_take()) return;  // stopping and nothing left
        Task task;
        bool batch = false;
        if (!inner_.empty()) {
            task = std::move(inner_.front());
            inner_.pop_front();
        } else if (!interactive_.empty()) {
            task = std::move(interactive_.front().task);
            interactive_.pop_front();
        } else {
            task = std::move(batch_.front().task);
            batch_.pop_front();
            batch = true;
            ++batch_running_;
        }
        ++busy_;
        lock.unlock();
        try {
            task();
        } catch (const std::exception& error) {
            spdlog::error("a worker task threw: {}", error.what());
        } catch (...) {
            spdlog::error("a worker task threw a non-standard exception");
        }
        task = nullptr;  // release what the task captured before counting it done
        lock.lock();
        --busy_;
        if (batch) {
            --batch_running_;
            wake_.notify_all();  // a batch slot is free; also wakes shutdown waiters
        }
    }
}

void WorkerPool::shutdown() {
    {
        std::lock_guard lock(mutex_);
        if (stopping_ && threads_.empty()) return;
        stopping_ = true;
    }
    wake_.notify_all();
    for (std::thread& thread : threads_) {
        if (thread.joinable()) thread.join();
    }
    std::lock_guard lock(mutex_);
    threads_.clear();
}

WorkerPoolStats WorkerPool::stats() const {
    std::lock_guard lock(mutex_);
    WorkerPoolStats stats;
    stats.workers = threads_.size();
    stats.busy = busy_;
    stats.inner_queued = inner_.size();
    stats.interactive_queued = interactive_.size();
    stats.interactive_capacity = interactive_capacity_;
    stats.batch_queued = batch_.size();
    stats.batch_capacity = batch_capacity_;
    stats.batch_running = batch_running_;
    stats.batch_concurrency = batch_concurrency_;
    return stats;
}

bool WorkerPool::idle() const {
    std::lock_guard lock(mutex_);
    return busy_ == 0 && inner_.empty() && interactive_.empty() && batch_.empty();
}

std::unique_ptr<WorkerPool> local_pool(std::size_t workers) {
    if (workers == 0) workers = static_cast<std::size_t>(cpu_budget().effective);
    return std::make_unique<WorkerPool>(workers, 0, 0, 1);
}

}  // namespace rollgap::service
