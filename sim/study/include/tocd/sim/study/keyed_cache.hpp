#pragma once

#include <cstddef>
#include <functional>
#include <future>
#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <string>

namespace tocd::sim::study {

/// A thread-safe memo of expensive results (FE solutions, meshes) keyed by a canonical text
/// of their inputs. Concurrent callers asking for the same key share one computation: the
/// first computes (outside the lock), the others wait on its future. Holds at most
/// `capacity` entries and forgets the least recently used beyond that. A computation that
/// throws is not kept; every caller waiting on it sees the exception.
template <class V>
class KeyedCache {
 public:
  explicit KeyedCache(std::size_t capacity = 8) : capacity_(capacity == 0 ? 1 : capacity) {}

  struct Lookup {
    std::shared_ptr<const V> value;
    bool hit = false;  ///< the value was computed before this call (or by a concurrent one)
  };

  Lookup get_or_compute(const std::string& key, const std::function<V()>& make) {
    std::promise<std::shared_ptr<const V>> promise;
    std::shared_future<std::shared_ptr<const V>> future;
    bool owner = false;
    {
      std::lock_guard lock(mutex_);
      if (auto it = entries_.find(key); it != entries_.end()) {
        order_.splice(order_.begin(), order_, it->second.position);
        future = it->second.future;
        ++hits_;
      } else {
        owner = true;
        future = promise.get_future().share();
        order_.push_front(key);
        entries_.emplace(key, Entry{future, order_.begin()});
        ++misses_;
        while (entries_.size() > capacity_) {
          entries_.erase(order_.back());
          order_.pop_back();
        }
      }
    }
    if (!owner) return {future.get(), true};
    try {
      promise.set_value(std::make_shared<const V>(make()));
    } catch (...) {
      promise.set_exception(std::current_exception());
      std::lock_guard lock(mutex_);
      if (auto it = entries_.find(key); it != entries_.end() && it->second.future.valid()) {
        order_.erase(it->second.position);
        entries_.erase(it);
      }
      throw;
    }
    return {future.get(), false};
  }

  std::size_t size() const {
    std::lock_guard lock(mutex_);
    return entries_.size();
  }
  std::size_t hits() const {
    std::lock_guard lock(mutex_);
    return hits_;
  }
  std::size_t misses() const {
    std::lock_guard lock(mutex_);
    return misses_;
  }

 private:
  struct Entry {
    std::shared_future<std::shared_ptr<const V>> future;
    std::list<std::string>::iterator position;
  };
  std::size_t capacity_;
  mutable std::mutex mutex_;
  std::map<std::string, Entry> entries_;
  std::list<std::string> order_;  ///< most recently used first
  std::size_t hits_ = 0, misses_ = 0;
};

}  // namespace tocd::sim::study
