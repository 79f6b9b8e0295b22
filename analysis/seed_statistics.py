"""Statistics over seeds: the mean of a configuration's runs and the standard error of that mean,
and which entries of a comparison lie within the spread of the best.

The standard error of the mean of n values is s / sqrt(n), s their sample standard deviation
(n - 1 in its denominator); with one value there is no spread (NaN). "Within the spread" of the
best (lowest) entry: the intervals mean ± SE of the two overlap, |m - m_best| <= SE + SE_best,
i.e. the difference is not significant at the ±1 SE level. Entries without a spread are never
within it.
"""

import math

import numpy as np


def mean_and_se(values, require_all=True):
    """(mean, standard error of the mean, n) of the values. NaN values are missing: with
    require_all any missing value makes the mean missing too (a run that stopped before a
    checkpoint leaves the others' mean biased), else they are left out. (NaN, NaN, n) without a
    value; SE NaN with one."""
    values = np.asarray(values, dtype=float)
    present = values[~np.isnan(values)]
    if len(present) == 0 or (require_all and len(present) < len(values)):
        return math.nan, math.nan, len(present)
    if len(present) == 1:
        return float(present[0]), math.nan, 1
    return float(present.mean()), float(present.std(ddof=1) / math.sqrt(len(present))), len(present)


def best_index(means):
    """Index of the lowest finite mean, None when there is none."""
    means = np.asarray(means, dtype=float)
    if np.all(np.isnan(means)):
        return None
    return int(np.nanargmin(means))


def within_spread_of_best(means, ses):
    """Per entry: True when its interval mean ± SE overlaps the best (lowest) entry's; False for
    the best itself, for missing entries, and wherever either has no spread."""
    means, ses = np.asarray(means, dtype=float), np.asarray(ses, dtype=float)
    best = best_index(means)
    marks = np.zeros(len(means), dtype=bool)
    if best is None or math.isnan(ses[best]):
        return marks
    with np.errstate(invalid="ignore"):
        marks = np.abs(means - means[best]) <= ses + ses[best]
    marks &= ~np.isnan(ses) & ~np.isnan(means)
    marks[best] = False
    return marks
