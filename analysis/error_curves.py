"""Error against render time of a run, between its measured frames.

A run's error is measured at the frames' finishing times (cumulative render time). Between two
measured frames the curve is a straight line on log-log axes (error and time both positive), the
shape of a converging estimator's error (a power of time); outside the measured frames it is not
defined. Frames without an error (null: not measured) are skipped.
"""

import math

import numpy as np


def measured(times, errors):
    """The (time, error) pairs with a positive time and error, in time order, as arrays."""
    times, errors = np.asarray(times, dtype=float), np.asarray(errors, dtype=float)
    keep = (times > 0) & (errors > 0) & np.isfinite(times) & np.isfinite(errors)
    order = np.argsort(times[keep], kind="stable")
    return times[keep][order], errors[keep][order]


def error_at(times, errors, at):
    """The error at each of the times `at`, interpolated on the log-log curve; NaN before the first
    measured frame and after the last."""
    t, e = measured(times, errors)
    at = np.asarray(at, dtype=float)
    if len(t) == 0:
        return np.full(at.shape, math.nan)
    with np.errstate(divide="ignore", invalid="ignore"):
        log_at = np.log(at)
        out = np.exp(np.interp(log_at, np.log(t), np.log(e)))
    out[(at < t[0]) | (at > t[-1]) | ~np.isfinite(log_at)] = math.nan
    return out


def time_to_reach(times, errors, target):
    """The first time the error reaches `target` (is at most it), interpolated on the log-log curve
    between the last frame above it and the first at or below it; the first frame's time when that
    one already is; NaN when the run never reaches it."""
    t, e = measured(times, errors)
    reached = np.flatnonzero(e <= target)
    if len(reached) == 0 or not target > 0:
        return math.nan
    k = reached[0]
    if k == 0:
        return float(t[0])
    fraction = (math.log(target) - math.log(e[k - 1])) / (math.log(e[k]) - math.log(e[k - 1]))
    return float(math.exp(math.log(t[k - 1]) + fraction * (math.log(t[k]) - math.log(t[k - 1]))))


def common_times(curves, points=48):
    """Log-spaced times on which every one of the curves ((times, errors) pairs) is defined: from
    the latest first measured frame to the earliest last one. Empty when they share no time."""
    spans = [measured(t, e) for t, e in curves]
    if not spans or any(len(t) == 0 for t, _ in spans):
        return np.array([])
    start, end = max(t[0] for t, _ in spans), min(t[-1] for t, _ in spans)
    if start > end:
        return np.array([])
    if start == end:
        return np.array([start])
    return np.geomspace(start, end, points)


def error_targets(first_errors, final_errors, most=6):
    """Errors to time the runs at for an equal-error comparison: values 1, 2, 5 × 10^k from the
    lowest final error up to (not including) the highest first-frame error, at most `most` of them,
    evenly spread over that list when it is longer (its ends kept)."""
    finals, firsts = np.asarray(final_errors, dtype=float), np.asarray(first_errors, dtype=float)
    finals, firsts = finals[np.isfinite(finals) & (finals > 0)], firsts[np.isfinite(firsts)]
    if not len(finals) or not len(firsts):
        return []
    low, high = finals.min(), firsts.max()
    candidates = [m * 10.0 ** k for k in range(-15, 10) for m in (1, 2, 5)]
    inside = [c for c in candidates if low * (1 - 1e-12) <= c < high]
    if len(inside) > most:
        inside = [inside[i] for i in np.unique(np.round(np.linspace(0, len(inside) - 1, most)).astype(int))]
    return inside
