// SPDX-License-Identifier: GPL-3.0-or-later
// shadow-bench soft: the soft-shadow baselines (PCF, PCSS, k rays per point) against the
// exact visible fraction of extended lights (light_visibility), speed against error (docs/soft-shadows.md).
#pragma once

#include <string>
#include <vector>

namespace bench {

struct SoftOptions {
  unsigned threads = 2;
  bool quick = false;                  ///< one small scene, two settings a method (seconds)
  std::string csv_path;                ///< write the rows as CSV
  std::vector<std::string> only_scenes;  ///< empty: all
  unsigned reference_rays = 4096;      ///< rays a point of the ray cross-check (at most 1024 with quick)
  /// Negative: report only. Otherwise fail (exit 1) when the ray cross-check's mean error against
  /// the exact fractions exceeds it, when rays do not improve with k, or a visibility leaves [0, 1].
  double max_error = -1;
};

/// Runs every scene, method and setting; prints a Markdown table. Non-zero on a failed check.
int run_soft(const SoftOptions& options);

}  // namespace bench
