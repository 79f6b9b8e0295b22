#pragma once
// FLIP: the perceptual difference of a test image from a reference, per pixel, as a viewer flipping
// between the two would see it.
//
// LDR-FLIP: Andersson, Nilsson, Akenine-Möller, Oskarsson, Åström, Fairchild 2020, "FLIP: A
// Difference Evaluator for Alternating Images" (HPG). HDR-FLIP: Andersson, Nilsson, Shirley,
// Akenine-Möller 2021, "Visualizing Errors in Rendered High Dynamic Range Images" (Eurographics),
// and Andersson, Nilsson, Akenine-Möller 2021, "Visualizing and Communicating Errors in Rendered
// Images" (Ray Tracing Gems II, ch. 19). The constants below are the papers'; where the
// reference implementation (NVlabs/flip) fixes a detail the papers leave open, gibench follows it.
//
// LDR-FLIP of linear RGB images x (test) and r (reference), values clamped to [0, 1]:
//   Colour. Each image goes linear RGB → XYZ (sRGB primaries, D65; white = XYZ of RGB (1,1,1)) →
//   YCxCz (Y = 116·Y/Yw − 16, Cx = 500·(X/Xw − Y/Yw), Cz = 200·(Y/Yw − Z/Zw)). Each opponent
//   channel is filtered with its contrast sensitivity function, a sum of Gaussians in visual
//   angle x (degrees): S(x) = a1·√(π/b1)·exp(−π²x²/b1) + a2·√(π/b2)·exp(−π²x²/b2), over a square
//   of radius ⌈3·√(max b / (2π²))·ppd⌉ pixels, normalised to sum 1 (kFlipCsf). The filtered image
//   goes back to linear RGB, clamped to [0, 1], then to CIELAB; the Hunt adjustment scales a*, b*
//   by 0.01·L*. The HyAB distance |ΔL*| + √(Δa*² + Δb*²) raised to kFlipQc is mapped to [0, 1]
//   against cmax = HyAB(green, blue)^kFlipQc, the largest distance between two colours: values
//   below kFlipPc·cmax go linearly to [0, kFlipPt], the rest linearly to (kFlipPt, 1]. That is
//   ΔEc.
//   Features. On the luminance Y/Yw, edges are the first and points the second derivative of a
//   Gaussian of σ = 0.5·kFlipFeatureWidthDeg·ppd pixels, radius ⌈3σ⌉, positive weights
//   normalised to sum 1 and negative ones to −1, applied along x and along y. With e and p the
//   lengths of the (x, y) responses, ΔEf = (max(|e_x − e_r|, |p_x − p_r|) / √2)^kFlipQf.
//   FLIP = ΔEc^(1 − ΔEf): features in the images make a colour difference more visible.
// Borders repeat the edge pixel (as the reference implementation does).
//
// HDR-FLIP of linear RGB radiance (negative values count as 0): for each of n exposures c from
// c_start to c_stop in equal steps, both images are scaled by 2^c and tone mapped with the ACES
// fit of Narkowicz (with the reference's pre-exposure 0.6 folded in, kFlipAces):
//   T(v) = clamp((k0·v² + k1·v + k2) / (k3·v² + k4·v + k5), 0, 1),
// and LDR-FLIP is computed on the tone-mapped images (linear values: the reference
// implementation encodes them to sRGB and its LDR-FLIP decodes them again). HDR-FLIP is the
// per-pixel maximum over the exposures. Automatic range, from the reference's luminance
// Y = 0.2126·R + 0.7152·G + 0.0722·B: with t = kFlipExposureTarget and v_t the value with T(v_t) =
// t, c_start = log2(v_t / max Y) (the brightest pixel lands on t), c_stop = log2(v_t / median Y)
// (so does the median), n = max(2, ⌈c_stop − c_start⌉). An all-black reference gives
// c_start = c_stop = 0. Where more than half the reference is black the paper's median is 0 and
// c_stop infinite; gibench then takes the median of the non-black pixels.
//
// Every FLIP value is in [0, 1]; identical images give 0 at every pixel. LDR-FLIP is symmetric in
// test and reference; HDR-FLIP is not (the exposures come from the reference). Every pixel is
// computed on its own, in parallel with oneTBB: the results do not depend on the thread count.

#include "core/image/image.h"

#include <array>
#include <numbers>

namespace gibench {

// Pixels per degree of visual angle of an observer `distance` from a monitor `monitorWidth` wide
// (same unit) showing `monitorPixels` pixels across: the paper's ppd = d · (p / w) · π / 180.
constexpr double flipPixelsPerDegree(double distance, double monitorPixels, double monitorWidth) {
    return distance * (monitorPixels / monitorWidth) * std::numbers::pi / 180.0;
}
// The papers' default observer: 0.7 m from a 0.7 m wide 4K (3840 pixels) monitor, ≈ 67.02.
inline constexpr double kFlipDefaultPixelsPerDegree = flipPixelsPerDegree(0.7, 3840.0, 0.7);

// Exponents and redistribution of the colour and feature terms (HPG 2020, section 4).
inline constexpr double kFlipQc = 0.7;
inline constexpr double kFlipQf = 0.5;
inline constexpr double kFlipPc = 0.4;
inline constexpr double kFlipPt = 0.95;
// Peak-to-trough width of the human edge detector, in degrees: σ = half of it.
inline constexpr double kFlipFeatureWidthDeg = 0.082;

// The opponent channels of YCxCz and their contrast sensitivity functions (a1, b1, a2, b2) of
// S(x) above (HPG 2020, Table 1). a2 = 0: a single Gaussian.
enum class FlipOpponent { Achromatic, RedGreen, BlueYellow };
struct FlipCsf {
    double a1, b1, a2, b2;
};
inline constexpr std::array<FlipCsf, 3> kFlipCsf = {{
    {1.0, 0.0047, 0.0, 0.0},     // achromatic (Y)
    {1.0, 0.0053, 0.0, 0.0},     // red-green (Cx)
    {34.1, 0.04, 13.5, 0.025},  // blue-yellow (Cz)
}};

// The ACES fit's rational polynomial (k0 .. k5) and the tone-mapped value the automatic exposure
// range puts the brightest and the median pixel on (RTG II ch. 19 / EG 2021).
inline constexpr std::array<double, 6> kFlipAces = {0.6 * 0.6 * 2.51, 0.6 * 0.03, 0.0, 0.6 * 0.6 * 2.43, 0.6 * 0.59, 0.14};
inline constexpr double kFlipExposureTarget = 0.85;

// T(v) above (v < 0 counts as 0).
double flipToneMap(double v);

// The two terms of LDR-FLIP and their combination, each a one-channel image of the inputs' size.
struct FlipTerms {
    Image color;    // ΔEc
    Image feature;  // ΔEf
    Image flip;     // ΔEc^(1 − ΔEf)
};

// LDR-FLIP of `test` against `reference`: linear RGB of the same size (first 3 channels),
// clamped to [0, 1]. Throws std::invalid_argument when the sizes differ, an image has fewer than
// 3 channels or `pixelsPerDegree` is not a positive finite number. Values must be finite
// (callers refuse images with NaN or infinities first).
FlipTerms ldrFlipTerms(const Image& test, const Image& reference, double pixelsPerDegree = kFlipDefaultPixelsPerDegree);
Image ldrFlip(const Image& test, const Image& reference, double pixelsPerDegree = kFlipDefaultPixelsPerDegree);

struct FlipExposures {
    double start = 0.0, stop = 0.0;  // log2 of the scale factor
    int count = 2;                   // >= 1; 1 uses `start` only
};
// The automatic exposure range above, of linear RGB `reference` (finite values).
FlipExposures flipExposures(const Image& reference);

// HDR-FLIP over `exposures`, or over flipExposures(reference). Same preconditions and errors as
// ldrFlipTerms(), and `exposures.count` must be at least 1 with finite start and stop.
Image hdrFlip(const Image& test, const Image& reference, const FlipExposures& exposures,
              double pixelsPerDegree = kFlipDefaultPixelsPerDegree);
Image hdrFlip(const Image& test, const Image& reference, double pixelsPerDegree = kFlipDefaultPixelsPerDegree);

// What the FLIP tool reports of a map: mean, median (the mean of the two middle values for an
// even count) and maximum over the pixels. The map must not be empty.
struct FlipStatistics {
    double mean = 0.0, median = 0.0, max = 0.0;
};
FlipStatistics flipStatistics(const Image& flipMap);

// The filters as (2r+1)² one-channel images, centre at (r, r): the contrast sensitivity filter of
// an opponent channel (weights sum to 1), and the x-direction feature detector (positive weights
// sum to 1, negative ones to −1; the y-direction one is its transpose). What the implementation
// convolves with, separably.
enum class FlipFeature { Edge, Point };
Image flipContrastSensitivityKernel(FlipOpponent channel, double pixelsPerDegree = kFlipDefaultPixelsPerDegree);
Image flipFeatureKernel(FlipFeature feature, double pixelsPerDegree = kFlipDefaultPixelsPerDegree);

}  // namespace gibench
