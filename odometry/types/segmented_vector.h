// A sequence that grows one element at a time without ever moving what it holds: fixed-size segments, each
// allocated once. For the records a run keeps for as long as it lasts (a pose and its statistics per scan).
//
// std::vector doubles its buffer and copies into the new one: at its last doubling it holds up to twice what
// is in use, old and new buffers are resident together during the copy, and the old one is left as a hole in
// the heap (the executables keep freed memory for reuse: odometry/types/process_memory.h). Over an hour at
// 10 Hz that made the resident memory rise in steps (bench/bench_long_run.sh, README's hour-long run);
// segments make it grow by what is stored, one segment ahead at most.
#pragma once

#include <algorithm>
#include <cstddef>
#include <iterator>
#include <type_traits>
#include <utility>
#include <vector>

namespace uf {

template <typename T>
class SegmentedVector {
 public:
  // Elements per segment: 256 KiB of them (at least one).
  static constexpr std::size_t kPerSegment = std::max<std::size_t>(1, (std::size_t{256} << 10) / sizeof(T));

  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }

  void push_back(T value) {
    if (size_ == segments_.size() * kPerSegment) segments_.emplace_back().reserve(kPerSegment);
    segments_.back().push_back(std::move(value));
    ++size_;
  }

  T& operator[](std::size_t i) { return segments_[i / kPerSegment][i % kPerSegment]; }
  const T& operator[](std::size_t i) const { return segments_[i / kPerSegment][i % kPerSegment]; }
  T& back() { return segments_.back().back(); }
  const T& back() const { return segments_.back().back(); }

  // Moves the elements into one vector, releasing each segment once it is emptied: the records and one
  // copy are resident together only at this one point, at the end of the run.
  std::vector<T> TakeVector() && {
    std::vector<T> all;
    all.reserve(size_);
    for (std::vector<T>& segment : segments_) {
      std::move(segment.begin(), segment.end(), std::back_inserter(all));
      std::vector<T>().swap(segment);
    }
    segments_.clear();
    size_ = 0;
    return all;
  }

  template <bool kConst>
  class Iterator {
   public:
    using Owner = std::conditional_t<kConst, const SegmentedVector, SegmentedVector>;
    using iterator_category = std::forward_iterator_tag;
    using value_type = T;
    using difference_type = std::ptrdiff_t;
    using pointer = std::conditional_t<kConst, const T*, T*>;
    using reference = std::conditional_t<kConst, const T&, T&>;

    Iterator() = default;
    Iterator(Owner* owner, std::size_t i) : owner_(owner), i_(i) {}
    reference operator*() const { return (*owner_)[i_]; }
    pointer operator->() const { return &(*owner_)[i_]; }
    Iterator& operator++() {
      ++i_;
      return *this;
    }
    Iterator operator++(int) {
      Iterator before = *this;
      ++i_;
      return before;
    }
    bool operator==(const Iterator& other) const { return i_ == other.i_; }

   private:
    Owner* owner_ = nullptr;
    std::size_t i_ = 0;
  };

  Iterator<false> begin() { return {this, 0}; }
  Iterator<false> end() { return {this, size_}; }
  Iterator<true> begin() const { return {this, 0}; }
  Iterator<true> end() const { return {this, size_}; }

 private:
  std::vector<std::vector<T>> segments_;  // all full but the last
  std::size_t size_ = 0;
};

}  // namespace uf
