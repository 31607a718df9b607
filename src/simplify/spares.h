// Arrays an island gives back when it closes, for the next island to fill: freed, arrays of
// 1 MB and more go back to the system at once (return_freed_arrays_to_the_system()), and the
// next island's would fault its pages in again, one 4 KiB page at a time (most island arrays
// are not whole huge pages). Islands open and close on any thread, once each: one lock is
// cheap. What is given back is held until clear().
#pragma once

#include <mutex>
#include <utility>
#include <vector>

namespace dynpm::simplification {

template <class T>
class Spares {
 public:
  // One given back earlier, or a new one.
  T take() {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (items_.empty()) return T{};
    T item = std::move(items_.back());
    items_.pop_back();
    return item;
  }
  void give(T&& item) {
    const std::lock_guard<std::mutex> lock(mutex_);
    items_.push_back(std::move(item));
  }
  void clear() {
    const std::lock_guard<std::mutex> lock(mutex_);
    std::vector<T>().swap(items_);
  }

 private:
  std::mutex mutex_;
  std::vector<T> items_;
};

}  // namespace dynpm::simplification
