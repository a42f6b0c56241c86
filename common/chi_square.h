// The chi-square distribution's quantile, used by the trackers' validation gate (eq. 20) and by
// the consistency (NEES) bands of evaluation/.
#pragma once

namespace slt {

// Quantile of the chi-square distribution with `dof` degrees of freedom (Wilson-Hilferty with
// a Newton polish on the CDF; accurate to 1e-6 relative for dof >= 1 and p in [0.01, 1 - 1e-9]).
double ChiSquareQuantile(double probability, int dof);

}  // namespace slt
