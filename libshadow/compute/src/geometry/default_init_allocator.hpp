// SPDX-License-Identifier: GPL-3.0-or-later
// An allocator whose vectors grow without writing their new elements: resize() of a vector of
// plain points default-initialises them (leaves doubles as they are) instead of zero-filling.
// The fast path's clips and hulls size a scratch vector to its largest possible output, write
// the points, then shrink it to what they wrote; scratch vectors are swapped in and out, so each
// clip and hull grew one again, and std::allocator's zero fill of every new element was some 3%
// of the fast path's instructions (docs/benchmarks.md, "Twentieth look").
#pragma once

#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace shadow::geometry {

/// std::allocator, but construct(p) with no arguments default-initialises: for trivially
/// default-constructible types (glm's vectors) resize() leaves new elements unwritten.
template <class T>
struct DefaultInitAllocator : std::allocator<T> {
  using std::allocator<T>::allocator;
  template <class U>
  struct rebind {
    using other = DefaultInitAllocator<U>;
  };
  template <class U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    std::allocator_traits<std::allocator<T>>::construct(static_cast<std::allocator<T>&>(*this), p,
                                                        std::forward<Args>(args)...);
  }
};

/// A vector whose resize() leaves new elements of a plain type unwritten: scratch sized to its
/// largest output and shrunk to what was written. Write every element before reading it.
template <class T>
using UnfilledVector = std::vector<T, DefaultInitAllocator<T>>;

}  // namespace shadow::geometry
