"""Medians and spreads, and the number formats of the report."""
import math
import statistics


def finite_values(values):
    return [float(v) for v in values if isinstance(v, (int, float)) and not isinstance(v, bool)
            and math.isfinite(v)]


def summary(values):
    """{'n', 'median', 'min', 'max', 'q1', 'q3'} of the finite values, or None."""
    v = sorted(finite_values(values))
    if not v:
        return None
    out = {"n": len(v), "median": statistics.median(v), "min": v[0], "max": v[-1]}
    if len(v) >= 4:
        q = statistics.quantiles(v, n=4, method="inclusive")
        out["q1"], out["q3"] = q[0], q[2]
    return out


def fmt_num(x, digits=3):
    if x is None:
        return "n/a"
    if digits == 0 and abs(x - round(x)) < 1e-9:
        return f"{x:.0f}"
    ax = abs(x)
    if ax == 0:
        return "0"
    if ax >= 1e6:
        return f"{x:.3g}"
    if ax >= 100:
        return f"{x:.0f}"
    if ax >= 10:
        return f"{x:.1f}"
    if ax >= 1:
        return f"{x:.2f}"
    if ax >= 0.01:
        return f"{x:.{digits}f}"
    return f"{x:.2g}"


def fmt_summary(s, digits=3, scale=1.0):
    """'median [min-max]' (the spread of the seeds), or 'n/a'."""
    if not s:
        return "n/a"
    med = fmt_num(s["median"] * scale, digits)
    if s["n"] == 1 or s["min"] == s["max"]:
        return med
    return f"{med} [{fmt_num(s['min'] * scale, digits)}–{fmt_num(s['max'] * scale, digits)}]"


def fmt_bytes(b):
    if b is None:
        return "n/a"
    if b >= 1024 * 1024:
        return f"{b / 1024 / 1024:.2f} MiB"
    if b >= 1024:
        return f"{b / 1024:.1f} KiB"
    return f"{b:.0f} B"
