#include "optim/ransac.h"

namespace slt {

const OptionSchema<RansacOptions>& RansacOptionsSchema() {
  using O = RansacOptions;
  static const OptionSchema<O> schema =
      OptionSchema<O>()
          .Field("ransac_max_iterations", &O::max_iterations, AtLeast(1), "RANSAC samples at most")
          .Field("ransac_confidence", &O::confidence, InRange(0.0, 1.0, "()"),
                 "RANSAC adaptive stopping: probability of an all-inlier sample")
          .Field("seed", &O::seed, AnyNumber(), "seed of the RANSAC sampler (reset with the tracker)");
  return schema;
}

}  // namespace slt
