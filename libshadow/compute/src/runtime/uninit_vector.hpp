// SPDX-License-Identifier: GPL-3.0-or-later
// Vectors whose elements are left uninitialised when sized, for large scratch arrays that a
// parallel loop then writes in full. std::vector<T>(n) zeroes its n elements on the calling
// thread before any worker starts; for arrays of hundreds of megabytes that zeroing is the first
// touch of every page (the kernel clearing it), and it ran serially while the other threads
// waited (a million faces: about a second of one thread in the preparation). Left uninitialised,
// each page is first touched by the worker that writes it.
#pragma once

#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace shadow::runtime {

/// An allocator that default-initialises (for trivial types: leaves alone) what std::vector
/// would value-initialise (zero); construction with arguments is unchanged.
template <class T, class Base = std::allocator<T>>
class DefaultInitAllocator : public Base {
  using Traits = std::allocator_traits<Base>;

 public:
  template <class U>
  struct rebind {
    using other = DefaultInitAllocator<U, typename Traits::template rebind_alloc<U>>;
  };

  using Base::Base;
  DefaultInitAllocator() = default;
  template <class U, class B>
  DefaultInitAllocator(const DefaultInitAllocator<U, B>& other) noexcept : Base(other) {}  // NOLINT: rebinding

  template <class U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    Traits::construct(static_cast<Base&>(*this), p, std::forward<Args>(args)...);
  }
};

/// A std::vector whose `UninitVector<T> v(n)` and `v.resize(n)` leave trivial elements
/// uninitialised: every element must be written before it is read. Only for trivially
/// default-constructible T (integers, glm vectors, plain structs of them).
template <class T>
using UninitVector = std::vector<T, DefaultInitAllocator<T>>;

}  // namespace shadow::runtime
