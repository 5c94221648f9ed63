"""The drift rate a map reports against the truth, as bench/never_worse and
the issue-10 section count it."""
import math


def _finite(v):
    return isinstance(v, (int, float)) and math.isfinite(v)


def count_within_3sigma(runs):
    """runs: (rate, own sigma, spread sigma, truth) in deg/m, one per run.
    Runs without a rate, an own sigma or a truth are left out. Returns
    (counted, within 3 own sigmas, within 3 sigmas over every fit)."""
    counted = own = spread = 0
    for rate, so, ss, truth in runs:
        if not (_finite(rate) and _finite(so) and _finite(truth)):
            continue
        counted += 1
        off = abs(truth - rate)
        own += off <= 3.0 * so
        spread += _finite(ss) and off <= 3.0 * ss
    return counted, own, spread
