// SPDX-License-Identifier: GPL-3.0-or-later
// One face's exact boundary curves, packed (packed_boundaries.hpp).
#include "sunmap/packed_boundaries.hpp"

#include "runtime/parallel.hpp"

#include <gmpxx.h>

#include <algorithm>
#include <cstdlib>
#include <map>
#include <stdexcept>
#include <unordered_map>
#include <utility>
#include <vector>

namespace shadow::sunmap {

using exact::Kernel;
using exact::Point2;

static_assert(GMP_NUMB_BITS == 64 && sizeof(mp_limb_t) == 8, "two 32-bit sizes are packed into one limb");

namespace {

/// Two signed 32-bit sizes in one limb.
mp_limb_t two_sizes(long a, long b) {
  if (std::labs(a) > INT32_MAX || std::labs(b) > INT32_MAX)
    throw std::length_error("sun-hours map: a boundary point's coordinate has more than 2^31 limbs");
  return (static_cast<mp_limb_t>(static_cast<std::uint32_t>(static_cast<std::int32_t>(a))) << 32) |
         static_cast<std::uint32_t>(static_cast<std::int32_t>(b));
}
long high_size(mp_limb_t l) { return static_cast<std::int32_t>(static_cast<std::uint32_t>(l >> 32)); }
long low_size(mp_limb_t l) { return static_cast<std::int32_t>(static_cast<std::uint32_t>(l)); }

void append_limbs(mpz_srcptr z, std::vector<mp_limb_t>& out) {
  const std::size_t n = mpz_size(z);
  const mp_limb_t* l = mpz_limbs_read(z);
  out.insert(out.end(), l, l + n);
}

/// The integer whose |size| limbs start at `l`, its sign that of `size`, into z.
template <class Iterator>
void read_integer(Iterator l, long size, mpz_ptr z) {
  const std::size_t n = static_cast<std::size_t>(std::labs(size));
  if (n == 0) {
    mpz_set_ui(z, 0);
    return;
  }
  mp_limb_t* w = mpz_limbs_write(z, static_cast<mp_size_t>(n));
  std::copy(l, l + static_cast<std::ptrdiff_t>(n), w);
  mpz_limbs_finish(z, static_cast<mp_size_t>(size));
}

}  // namespace

Point2 PackedBoundaries::unpack_point(std::uint64_t p) const {
  auto l = store_->limbs.begin() + static_cast<std::ptrdiff_t>(store_->at[p]);
  const long sizes[4] = {high_size(l[0]), low_size(l[0]), high_size(l[1]), low_size(l[1])};
  l += 2;
  mpq_class x, y;
  mpz_ptr parts[4] = {mpq_numref(x.get_mpq_t()), mpq_denref(x.get_mpq_t()), mpq_numref(y.get_mpq_t()),
                      mpq_denref(y.get_mpq_t())};
  for (int k = 0; k < 4; ++k) {
    read_integer(l, sizes[k], parts[k]);
    l += static_cast<std::ptrdiff_t>(std::labs(sizes[k]));
  }
  // A leaf holding its exact point, as the canonical boundaries make theirs: the same interval
  // and the same doubles as the point packed.
  return Point2(Kernel::Exact_kernel::Point_2(x, y));
}

PackedBoundaries::Chunk PackedBoundaries::pack(const std::vector<Curve>& curves) {
  Chunk out;
  // Equal points by value (the segments of a boundary meet end to end; whether they share the
  // point's object depends on how they were made), so each point is packed once.
  const auto less = [](const Point2& a, const Point2& b) { return CGAL::compare_xy(a, b) == CGAL::SMALLER; };
  std::map<Point2, std::uint64_t, decltype(less)> packed(less);
  const auto index = [&](const Point2& p) {
    const auto [it, fresh] = packed.try_emplace(p, 0);
    if (fresh) {
      const auto& e = CGAL::exact(p);  // held by p's own representation (p.x() would be a new one)
      mpz_srcptr xn = mpq_numref(e.x().get_mpq_t()), xd = mpq_denref(e.x().get_mpq_t());
      mpz_srcptr yn = mpq_numref(e.y().get_mpq_t()), yd = mpq_denref(e.y().get_mpq_t());
      out.at_.push_back(out.limbs_.size());
      out.limbs_.push_back(two_sizes(xn->_mp_size, xd->_mp_size));
      out.limbs_.push_back(two_sizes(yn->_mp_size, yd->_mp_size));
      for (mpz_srcptr z : {xn, xd, yn, yd}) append_limbs(z, out.limbs_);
      it->second = out.at_.size() - 1;
    }
    return it->second;
  };
  out.segments_.reserve(curves.size());
  for (const Curve& c : curves) {
    const std::uint64_t from = index(c.source());
    const std::uint64_t to = index(c.target());
    out.segments_.push_back(Segment{from, to, c.data(), CGAL::compare_xy(c.source(), c.target()) != CGAL::LARGER});
  }
  out.at_.shrink_to_fit();
  out.limbs_.shrink_to_fit();
  return out;
}

void PackedBoundaries::add(Chunk&& chunk) {
  if (chunk.segments_.empty()) return;
  if (!store_) store_ = std::make_unique<Store>();
  Store& s = *store_;
  const std::uint64_t points = s.at.size(), limbs = s.limbs.size();
  for (std::uint64_t a : chunk.at_) s.at.push_back(a + limbs);
  s.limbs.insert(s.limbs.end(), chunk.limbs_.begin(), chunk.limbs_.end());
  for (Segment g : chunk.segments_) {
    g.from += points;
    g.to += points;
    s.segments.push_back(g);
  }
  chunk = Chunk{};
}

void PackedBoundaries::unpack(const std::vector<std::size_t>& which, std::vector<Curve>& out) const {
  out.clear();
  out.reserve(which.size());
  std::unordered_map<std::uint64_t, Point2> points;
  points.reserve(which.size() * 2);
  const auto point = [&](std::uint64_t p) -> const Point2& {
    const auto [it, fresh] = points.try_emplace(p);
    if (fresh) it->second = unpack_point(p);
    return it->second;
  };
  for (std::size_t k : which) {
    const Segment& s = store_->segments[k];
    out.emplace_back(SegmentTraits::Curve_2(point(s.from), point(s.to)), s.tag);
  }
}

std::vector<RoughSegment> PackedBoundaries::rough(unsigned threads) const {
  // Each point's doubles once (they are what rough_segment reads of a curve's ends).
  struct Doubles {
    double x, y, xlo, xhi;
  };
  if (!store_) return {};
  std::vector<Doubles> at(store_->at.size());
  runtime::parallel_for_blocks(at.size(), 4096, threads, [&](unsigned, std::size_t, std::size_t b, std::size_t e) {
    for (std::size_t p = b; p < e; ++p) {
      const Point2 q = unpack_point(p);
      const auto xi = CGAL::to_interval(q.x());
      at[p] = Doubles{CGAL::to_double(q.x()), CGAL::to_double(q.y()), xi.first, xi.second};
    }
  });
  std::vector<RoughSegment> out(size());
  for (std::size_t k = 0; k < out.size(); ++k) {
    const Segment& s = store_->segments[k];
    const Doubles &a = at[s.from], &b = at[s.to];
    const Doubles &f = s.forward ? a : b, &t = s.forward ? b : a;  // rough_segment's ends
    out[k] = RoughSegment{f.x, f.y, t.x, t.y, std::min(a.xlo, b.xlo), std::max(a.xhi, b.xhi),
                          static_cast<std::uint32_t>(instant(k)), tag_left(s.tag)};
  }
  return out;
}

std::size_t PackedBoundaries::bytes() const {
  if (!store_) return 0;
  return store_->at.size() * sizeof(std::uint64_t) + store_->limbs.size() * sizeof(mp_limb_t) +
         store_->segments.size() * sizeof(Segment);
}

}  // namespace shadow::sunmap
