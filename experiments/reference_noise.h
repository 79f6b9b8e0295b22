#pragma once
// The noise floor of error plots: how far the reference itself is from the converged image.
// A run's relMSE against the reference is, in expectation, its relMSE against the converged image
// plus this, since the reference's noise is independent of the run's; curves flatten at it.
//
// For the reference's total layer with its "variance" layer v (the variance of each pixel's mean,
// path_traced.cpp), the expected relMSE of the reference r is mean over pixels and the 3 channels
// of v / (r² + kRelMseEpsilon): relMSE's formula (core/image/metrics.h) with (r − truth)²
// replaced by its expectation. For a low-discrepancy reference v is what independent samples
// would give, so the floor is an upper bound. Only "total" has a variance layer.

#include "core/image/image.h"
#include "core/config/params.h"

namespace gibench {

// {"total": expected relMSE} when the reference has a "variance" layer matching its total, else null.
Json referenceNoise(const LayeredImage& reference);

}  // namespace gibench
