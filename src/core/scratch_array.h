// ScratchArray: a buffer of n elements that the caller writes before it reads them, without
// the value-initialising pass of std::vector::resize.
#pragma once

#include <algorithm>
#include <cstddef>
#include <memory>
#include <type_traits>
#include <utility>

namespace quarry {

// Why: a fresh std::vector<Vec3> of n elements is zeroed by the thread that sizes it, before a
// parallel loop overwrites every element. For the contacts that a neighbour-list build keeps
// (13 MB at 200k particles) that pass, with its page faults, was serial. Here the storage comes
// from std::allocator uninitialised (T is an implicit-lifetime type: objects exist in it once
// written) and is first touched by the loop that fills it.
template <class T>
class ScratchArray {
  static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T>);

 public:
  ScratchArray() = default;
  // A copy holds the same elements (a World is copied whole in tests and by callers).
  ScratchArray(const ScratchArray& other) { *this = other; }
  ScratchArray& operator=(const ScratchArray& other) {
    if (this != &other) {
      size_for_overwrite(other.size_);
      std::copy(other.data_, other.data_ + other.size_, data_);
    }
    return *this;
  }
  ScratchArray(ScratchArray&& other) noexcept
      : data_(std::exchange(other.data_, nullptr)), size_(std::exchange(other.size_, 0)),
        capacity_(std::exchange(other.capacity_, 0)) {}
  ScratchArray& operator=(ScratchArray&& other) noexcept {
    if (this != &other) {
      release();
      data_ = std::exchange(other.data_, nullptr);
      size_ = std::exchange(other.size_, 0);
      capacity_ = std::exchange(other.capacity_, 0);
    }
    return *this;
  }
  ~ScratchArray() { release(); }

  // n elements of unspecified value (the previous contents, where they fit).
  void size_for_overwrite(std::size_t n) {
    if (n > capacity_) {
      release();
      data_ = std::allocator<T>().allocate(n);
      capacity_ = n;
    }
    size_ = n;
  }
  // Gives the memory back.
  void release() noexcept {
    if (data_) std::allocator<T>().deallocate(data_, capacity_);
    data_ = nullptr;
    size_ = capacity_ = 0;
  }

  T* data() { return data_; }
  const T* data() const { return data_; }
  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  T& operator[](std::size_t k) { return data_[k]; }
  const T& operator[](std::size_t k) const { return data_[k]; }

 private:
  T* data_ = nullptr;
  std::size_t size_ = 0, capacity_ = 0;
};

}  // namespace quarry
