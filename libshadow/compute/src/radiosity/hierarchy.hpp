// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: hierarchical radiosity with clusters (docs/radiosity.md, "Hierarchical radiosity"):
// links between groups of patches far apart relative to their size, so that the links grow about
// linearly with the scene instead of as the square of its patches.
#pragma once

#include "radiosity/elements.hpp"
#include "radiosity/receivers.hpp"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace shadow::radiosity {

/// Options of the hierarchy's links.
struct HierarchyOptions {
  /// Two groups are linked as a whole when the sum of their radii is at most `separation`
  /// times the distance between their centroids (both then look like points to each other:
  /// the kernel's relative error is of the order of separation squared).
  double separation = 0.4;
  int rays = 8;  ///< visibility rays per link between groups
  /// Near links: a receiving element takes the 16-point rule within this times the sum of its
  /// and the source's radii, the 3-point rule beyond (Receivers::receive_pair). Shooting's 2
  /// doubled the time of a city for no measured gain (docs/radiosity.md).
  double close_rule = 1.0;
  unsigned threads = 1;
  /// Called now and then while the links are computed, with the share done (0 to 1).
  std::function<void(double)> progress;
};

/// The patches in a bounding volume hierarchy, the links between its nodes, and the transport
/// along them. Near pairs of patches (not separated enough) are linked patch to element with the
/// form factors of Receivers (visibility in doubles); separated groups with one factor per link,
/// the kernel at their centroids per pair of faces, and the visibility from rays between them.
class Hierarchy {
 public:
  /// `can_emit[p]`: whether patch p can ever leave light (some emittance or reflectance); links
  /// from groups that cannot are not made (a black ground sends nothing).
  Hierarchy(const std::vector<Patch>& patches, const std::vector<Element>& elements, Receivers& receivers,
            const std::vector<char>& can_emit, const HierarchyOptions& options);

  /// h[i] = direct[i] + the irradiance element i receives from every element's radiosity `b`
  /// (one Jacobi step of the radiosity equation). Deterministic at any thread count.
  void gather(const std::vector<double>& b, const std::vector<double>& direct, std::vector<double>& h) const;

  /// An estimate of the relative error of the transport from radiosities `b`: per receiving face,
  /// the far links' kernel errors (of the order of their separation squared) added and their
  /// rays' sampling errors added in quadrature (independent), weighted by what each carries;
  /// summed over faces, over all that the links carry.
  double link_error(const std::vector<double>& b) const;

  std::size_t near_links() const { return near_.size(); }
  std::size_t far_links() const { return far_.size(); }
  std::size_t nodes() const { return nodes_.size(); }

 private:
  struct Node {
    glm::dvec3 lo{0.0}, hi{0.0};  // box of its triangles
    glm::dvec3 centroid{0.0};     // area-weighted
    double radius = 0.0;          // from the centroid to the farthest vertex
    double area = 0.0;
    std::uint32_t first = 0, count = 0;            // its patches: order_[first, first + count)
    std::int32_t left = -1, right = -1;            // children (a leaf: one patch)
    std::uint32_t parts_first = 0, parts_count = 0;  // its faces: parts_[...], by face id
    bool emits = false;                              // some patch of it can leave light
  };
  struct Part {
    std::size_t face = 0;
    double area = 0.0;
  };
  struct NearLink {
    std::uint32_t receiver = 0, source = 0;  // patches
    std::size_t factors = 0;                 // into near_factors_: one per receiver element
    double quadrature = 0.0;                 // sum of the elements' quadrature change x area (m^2)
  };
  struct FarLink {
    std::uint32_t receiver = 0, source = 0;  // nodes
    glm::dvec3 direction{0.0};               // unit, from the source's centroid to the receiver's
    double inverse_square = 0.0;             // 1 / distance^2
    double visible = 1.0;                    // the rays' visibility estimate
    double kernel_error = 0.0;               // relative error of the centroid kernel (estimate)
    double sampling_error = 0.0;             // standard error of `visible` (relative to the transfer)
  };

  std::int32_t build(std::uint32_t first, std::uint32_t count, const std::vector<char>& can_emit);
  void link(std::vector<std::pair<std::uint32_t, std::uint32_t>>& near,
            std::vector<std::pair<std::uint32_t, std::uint32_t>>& far) const;
  bool hidden_by_plane(const Node& a, const Node& b) const;
  void make_far_link(FarLink& link, std::uint64_t seed, ShaftCuller::Scratch& scratch) const;
  /// pair(i, j) for every part j of each child of `node` (an inner node) and its own part i of
  /// the same face: the walk that sums powers up the tree and pushes irradiance down it.
  template <class Pair>
  void for_each_child_part(const Node& node, const Pair& pair) const;
  /// Power leaving each node's faces (W), per part, from the patches' mean radiosity.
  void part_powers(const std::vector<double>& patch_b, std::vector<double>& power) const;
  /// A far link's irradiance on a receiving face per unit of its cosine (W/m^2).
  double far_transfer(const FarLink& link, const std::vector<double>& power) const;
  /// Each patch's area-weighted mean of its elements' radiosities.
  std::vector<double> patch_radiosity(const std::vector<double>& b) const;

  const std::vector<Patch>& patches_;
  const std::vector<Element>& elements_;
  Receivers& receivers_;
  HierarchyOptions options_;
  std::vector<std::uint32_t> order_;  // patch ids in the hierarchy's order
  std::vector<Node> nodes_;           // parents before children; nodes_[0] the root
  std::vector<Part> parts_;
  std::vector<std::int32_t> leaf_of_patch_;
  /// Per patch: it faces the inside of a closed solid (a ground patch under a box standing on
  /// it: the first face along its normal is seen from behind). Far links neither reach nor
  /// sample it: what a group receives belongs to its open patches.
  std::vector<char> enclosed_;
  std::vector<NearLink> near_;  // by receiver
  std::vector<double> near_factors_;
  std::vector<FarLink> far_;  // by receiver
  std::vector<std::size_t> near_begin_, far_begin_;  // per patch / per node: first link
};

}  // namespace shadow::radiosity
