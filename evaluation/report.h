// What `evaluate` tells a person: the error table (the layout of evo's evo_ape / evo_rpe
// statistics: rmse, mean, median, std, min, max, with units) and the check that the two
// trajectories are the same run (enough of each one's poses associated).
#pragma once

#include <string>

#include "evaluation/metrics.h"

namespace slt {

// Below this fraction of either trajectory's poses associated, the numbers describe a part of
// the run only (or another run: a ground truth of 100 poses against an estimate of 600).
constexpr double kMinAssociatedFraction = 0.95;

// "" when at least min_fraction of the estimate's poses and of the ground truth's poses are
// associated; otherwise one sentence naming the counts of both, e.g. "only 100 of 600
// estimate poses (16.7 %) are associated with a ground-truth pose within 0.01 s".
std::string AssociationWarning(const TrajectoryErrors& errors, double min_fraction = kMinAssociatedFraction);

// The table (common/table.h, as text), one line per metric (ATE and RPE, translation in m and
// rotation in deg; six decimals, a column widened for a number of more than 10 characters),
// preceded by a line on the association and the alignment and followed by the
// final-frame error:
//
//   associated 100 of 100 estimate and 100 of 100 ground-truth poses (max time difference 0.01 s); alignment none
//   metric                       rmse       mean     median        std        min        max
//   ATE translation (m)      0.001234   ...
//   ... (ATE rotation, RPE translation, RPE rotation)
//   RPE: 99 pairs (i, i + 1), i = 0, 1, 2, ...
//   final error (frame 99, time 3.3 s): translation 0.001450 m, rotation 0.153000 deg
std::string ErrorTable(const TrajectoryErrors& errors);

}  // namespace slt
