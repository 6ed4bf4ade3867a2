// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: the form factors from elements to a patch, with visibility in doubles through shaft
// culling (the default) or the exact machinery point by point (for checking).
#pragma once

#include "radiosity/elements.hpp"
#include "radiosity/shaft.hpp"
#include "radiosity/shooter_view.hpp"
#include "radiosity/visible_part.hpp"

#include <shadow/scene.hpp>

#include <memory>
#include <vector>

namespace shadow::radiosity {

/// Where the form factors come from. receive() from one thread at a time (it runs its own
/// workers); receive_pair() from up to `threads` threads at once (distinct worker indices).
class Receivers {
 public:
  Receivers(const Scene& scene, unsigned threads, bool exact);

  std::size_t exact_evaluations() const { return view_ ? view_->exact_evaluations() : 0; }
  /// Unit front normals per face (zero for a degenerate face).
  const std::vector<glm::dvec3>& normals() const { return culler_.normals(); }
  const ShaftCuller& culler() const { return culler_; }

  /// The form factor from each element to patch `s` and the quadrature change that estimates
  /// its error. Elements on the patch's face get 0 (a plane does not see itself).
  void receive(const std::vector<Patch>& patches, const std::vector<Element>& elements, const Patch& s,
               unsigned threads, std::vector<double>& factor, std::vector<double>& quad);

  /// The same for the elements of one receiving patch `r` only (visibility in doubles whatever
  /// the constructor's `exact`): factor[i] and quad[i] for element r.first + i. An element
  /// takes the 16-point rule within `close` times the sum of its and s's radii (receive(): 2).
  /// Returns false (and zeros) when nothing of `s` is seen from `r`.
  bool receive_pair(unsigned worker, const std::vector<Element>& elements, const Patch& r, const Patch& s,
                    double close, std::vector<double>& factor, std::vector<double>& quad);

  /// Some of triangle r in front of triangle s's face and some of s in front of r's face.
  bool faces_each_other(const Triangle& r, std::size_t r_face, const Triangle& s, std::size_t s_face) const;

 private:
  struct Worker {
    VisibleScratch visible;
    ShaftCuller::Scratch shaft;
    std::vector<std::size_t> faces;
    std::vector<const std::vector<glm::dvec3>*> occluders;
  };
  /// Patch r's elements' factors to the source in `chart` (patch s, whose corners are `source`),
  /// in worker w's storage; the caller has checked that r and s face each other.
  bool receive_patch(Worker& w, const SourceChart& chart, const std::vector<glm::dvec3>& source,
                     const std::vector<Element>& elements, const Patch& r, const Patch& s, double* factor,
                     double* quad, double close);

  bool exact_;
  ShaftCuller culler_;
  std::unique_ptr<ShooterView> view_;
  std::vector<Worker> workers_;
};

}  // namespace shadow::radiosity
