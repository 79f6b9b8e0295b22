#pragma once
// Error metrics of a rendered image against a reference: the numbers every result table reports.
//
// x is the test image, r the reference, both linear RGB of the same size; only their first 3
// channels are compared. Each error metric is a mean over the N pixels p and the 3 channels c:
//   MSE    = mean (x − r)²                                  RMSE = √MSE
//   relMSE = mean (x − r)² / (r² + kRelMseEpsilon)
//   SMAPE  = mean |x − r| / (|x| + |r| + kSmapeEpsilon)      (no factor 2: values in [0, 1))
//   MAPE   = mean |x − r| / (|r| + kMapeEpsilon)
// The perceptual metrics see display values t(v) = srgbEncode(v' / (1 + v')), v' = max(v, 0)
// (Reinhard, then the sRGB curve; negative radiance shows as black), with peak kDisplayPeak:
//   PSNR   = 10 · log10(kDisplayPeak² / mean (t(x) − t(r))²) in dB, at most kMaxPsnrDb: identical
//            images give exactly kMaxPsnrDb, a number JSON can hold, where the formula gives +inf.
//   SSIM   = Wang et al. 2004 on t(Y), Y = Rec. 709 luminance (core/util/math.h), with a Gaussian
//            window of radius kSsimRadius and deviation kSsimSigma. Near the borders only the
//            part of the window inside the image is used, renormalised. Per pixel, with window
//            means μ, variances σ² and covariance σxy, C1 = (kSsimK1·L)², C2 = (kSsimK2·L)²,
//            L = kDisplayPeak: (2μxμr + C1)(2σxr + C2) / ((μx² + μr² + C1)(σx² + σr² + C2));
//            the mean over pixels is reported. Identical images give exactly 1.
// Robust variants drop the N / kRobustDropDivisor pixels (rounded down) with the largest
// per-pixel error e_p = mean over c of the metric's term, then average the rest, so that a few
// fireflies cannot decide a ranking alone.
// Non-finite values: a pixel with NaN or ±Inf in its first 3 channels, in the test or in the
// reference, counts in nonfinitePixels. When there is any, every non-robust metric is NaN, never
// a mean over the finite pixels only; for the robust variants such a pixel's error is +inf, so it
// is dropped when there are few enough of them and makes the metric +inf otherwise.
// Determinism: sums run per row, then over rows in order, in double, so the numbers do not depend
// on the number of threads.

#include "core/config/params.h"
#include "core/image/image.h"

#include <cstddef>

namespace gibench {

// The PSNR of identical images, and of any closer than mean (t(x) − t(r))² = 10^-20 · kDisplayPeak²:
// far above what renders that differ at all reach (a difference of 1/255 in one pixel of an 8K
// image is about 128 dB).
inline constexpr double kMaxPsnrDb = 200.0;
// Keeps relMSE finite where the reference is black; 0.01 is the usual choice in the denoising
// literature, so that our numbers compare with published ones.
inline constexpr double kRelMseEpsilon = 0.01;
// Keeps SMAPE defined where both images are black.
inline constexpr double kSmapeEpsilon = 0.01;
// Keeps MAPE finite where the reference is black.
inline constexpr double kMapeEpsilon = 0.01;
// Largest display value after tone mapping: the L of PSNR and SSIM.
inline constexpr double kDisplayPeak = 1.0;
// SSIM constants of Wang et al. 2004: 11×11 window, σ = 1.5 pixels, K1, K2.
inline constexpr int kSsimRadius = 5;
inline constexpr double kSsimSigma = 1.5;
inline constexpr double kSsimK1 = 0.01;
inline constexpr double kSsimK2 = 0.03;
// Robust metrics drop N / kRobustDropDivisor pixels (integer division): the top 0.01 %.
inline constexpr std::size_t kRobustDropDivisor = 10000;

// Per-pixel errors that errorMap() can draw; each value is the mean over the 3 channels of the
// metric's term above.
enum class ErrorMapKind { SquaredError, RelMse, Smape, Mape };

struct ImageMetrics {
    double mse = 0.0, rmse = 0.0, relMse = 0.0, smape = 0.0, mape = 0.0;
    double psnr = 0.0;  // dB
    double ssim = 0.0;  // in [-1, 1]
    // Mean over pixels of the mean of the 3 channels, of the test and of the reference: their
    // ratio is the test's bias, which relMSE (regularised by kRelMseEpsilon) hides on dim images.
    double mean = 0.0, referenceMean = 0.0;
    double mseRobust = 0.0, relMseRobust = 0.0, smapeRobust = 0.0, mapeRobust = 0.0;
    std::size_t pixels = 0;
    std::size_t nonfinitePixels = 0;
};

// Every metric above of `test` against `reference`. Both need the same width and height and at
// least 3 channels, else std::invalid_argument ("image sizes differ: test WxH, reference WxH" or
// "metrics need at least 3 channels, got test C, reference C").
// Runs in parallel with oneTBB; the result does not depend on the thread count.
ImageMetrics computeMetrics(const Image& test, const Image& reference);

// {"mse", "rmse", "relmse", "smape", "mape", "psnr", "ssim", "mse_robust", "relmse_robust",
// "smape_robust", "mape_robust", "mean", "reference_mean", "pixels", "nonfinite_pixels"}, every
// value a finite number.
// Metrics that are not finite (images with non-finite pixels; JSON has no number for them, and a
// null or "inf" would pass for a measurement in a results table) throw std::domain_error naming
// the metric: callers refuse such images first (compare, references) or treat a rendered one as
// the defect it is.
Json toJson(const ImageMetrics& metrics);

// A one-channel image of the per-pixel error of `kind`. A pixel with a non-finite value in its
// first 3 channels, in either image, is NaN; an error beyond the largest float (squared
// differences of values above ~1.8e19) is that largest float. Same preconditions and errors as
// computeMetrics().
Image errorMap(const Image& test, const Image& reference, ErrorMapKind kind);

}  // namespace gibench
