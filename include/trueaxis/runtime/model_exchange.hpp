#pragma once
// ModelExchange: hands a new model to the real-time thread without stopping
// the loop, without a lock the real-time thread could wait on, and without
// ever freeing memory on the real-time thread.
//
// Two single-pointer atomic slots:
//   mailbox_  publisher → RT: the newest published, not yet picked up model.
//   retired_  RT → collector: the model the RT thread stopped using.
// The RT thread (Acquire) picks up the mailbox only when retired_ is empty,
// moving its current model to retired_; a non-RT thread (Publish or
// CollectRetired) deletes what is in retired_. Both RT operations are a
// load and an exchange: wait-free. A model published while another one is
// still waiting in the mailbox replaces it (the older one is deleted by the
// publisher, the RT thread never saw it).
#include <atomic>
#include <memory>
#include <mutex>

namespace trueaxis::runtime {

template <typename T>
class ModelExchange {
 public:
  ModelExchange() = default;
  ModelExchange(const ModelExchange&) = delete;
  ModelExchange& operator=(const ModelExchange&) = delete;
  // The RT thread must have stopped calling Acquire().
  ~ModelExchange() {
    delete mailbox_.exchange(nullptr);
    delete retired_.exchange(nullptr);
    delete current_;
  }

  // Any non-RT thread. Takes ownership.
  void Publish(std::unique_ptr<T> model) {
    std::lock_guard<std::mutex> lock(publish_mutex_);
    delete retired_.exchange(nullptr, std::memory_order_acq_rel);
    delete mailbox_.exchange(model.release(), std::memory_order_acq_rel);
  }

  // Any non-RT thread: frees the model the RT thread has let go of, if any.
  // Returns true if one was freed.
  bool CollectRetired() {
    std::lock_guard<std::mutex> lock(publish_mutex_);
    T* r = retired_.exchange(nullptr, std::memory_order_acq_rel);
    delete r;
    return r != nullptr;
  }

  // RT thread only: the model to use this cycle (nullptr before the first
  // publish). Switches to a newly published model when the retired slot is free.
  const T* Acquire() {
    if (retired_.load(std::memory_order_acquire) == nullptr) {
      if (T* fresh = mailbox_.exchange(nullptr, std::memory_order_acq_rel)) {
        if (current_) retired_.store(current_, std::memory_order_release);
        current_ = fresh;
      }
    }
    return current_;
  }

  // True while a published model has not been picked up yet.
  bool Pending() const { return mailbox_.load(std::memory_order_acquire) != nullptr; }

 private:
  std::mutex publish_mutex_;  // serialises publishers/collectors; never taken by the RT thread
  std::atomic<T*> mailbox_{nullptr};
  std::atomic<T*> retired_{nullptr};
  T* current_ = nullptr;  // RT-thread owned
};

}  // namespace trueaxis::runtime
