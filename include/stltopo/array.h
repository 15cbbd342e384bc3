// stltopo/array.h: Array, the malloc-backed owning array the core stores its data in.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

namespace stltopo {

namespace detail {
// Asks the OS to back a large array with huge pages (Linux, native builds; a no-op
// elsewhere): fewer page faults and TLB misses on the big, randomly accessed arrays.
void adviseHugePages(void* p, size_t bytes);
}  // namespace detail

// ---------------------------------------------------------------------------
// A minimal owning array of trivially copyable T (malloc-backed so that an
// allocation failure is a return value, not an exception or a wasm abort).
template <class T>
class Array {
 public:
  Array() = default;
  Array(const Array&) = delete;
  Array& operator=(const Array&) = delete;
  Array(Array&& o) noexcept : p_(o.p_), n_(o.n_), cap_(o.cap_) {
    o.p_ = nullptr;
    o.n_ = o.cap_ = 0;
  }
  Array& operator=(Array&& o) noexcept {
    if (this != &o) {
      std::free(p_);
      p_ = o.p_;
      n_ = o.n_;
      cap_ = o.cap_;
      o.p_ = nullptr;
      o.n_ = o.cap_ = 0;
    }
    return *this;
  }
  ~Array() { std::free(p_); }

  T* data() { return p_; }
  const T* data() const { return p_; }
  size_t size() const { return n_; }
  bool empty() const { return n_ == 0; }
  size_t capacity() const { return cap_; }
  T& operator[](size_t i) { return p_[i]; }
  const T& operator[](size_t i) const { return p_[i]; }
  T* begin() { return p_; }
  T* end() { return p_ + n_; }
  const T* begin() const { return p_; }
  const T* end() const { return p_ + n_; }

  // All fallible operations return false on allocation failure and leave the
  // array unchanged.
  [[nodiscard]] bool reserve(size_t n) {
    if (n <= cap_) return true;
    if (n > SIZE_MAX / sizeof(T)) return false;
    void* q = std::realloc(p_, n * sizeof(T));
    if (!q) return false;
    p_ = static_cast<T*>(q);
    cap_ = n;
    if (n * sizeof(T) >= (size_t(4) << 20)) detail::adviseHugePages(p_, n * sizeof(T));
    return true;
  }
  [[nodiscard]] bool resize(size_t n) {
    if (!reserve(n)) return false;
    n_ = n;
    return true;
  }
  [[nodiscard]] bool assign(size_t n, T value) {
    if (!resize(n)) return false;
    for (size_t i = 0; i < n; ++i) p_[i] = value;
    return true;
  }
  [[nodiscard]] bool push_back(const T& v) {
    if (n_ == cap_ && !reserve(cap_ < 8 ? 16 : cap_ * 2)) return false;
    p_[n_++] = v;
    return true;
  }
  void clear() { n_ = 0; }
  void release() {
    std::free(p_);
    p_ = nullptr;
    n_ = cap_ = 0;
  }
  void shrink(size_t n) {
    if (n < n_) n_ = n;
  }

 private:
  T* p_ = nullptr;
  size_t n_ = 0;
  size_t cap_ = 0;
};

}  // namespace stltopo
