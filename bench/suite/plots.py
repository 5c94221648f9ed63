"""The figures of docs/BENCHMARKS.md (matplotlib, Agg backend, PNG)."""
import collections
import os

from .stats import summary
from .tool import finite


def _plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


COLORS = {"pioneer16": "tab:blue", "pioneer8": "tab:orange", "laser": "tab:green"}


def _median(runs, key):
    s = summary([r["metrics"].get(key) for r in runs if r.get("metrics")])
    return s["median"] if s else None


def error_vs_drift(results, path):
    """Heading error (raw dashed, corrected solid) and wall precision p95 against drift."""
    sims = results.get("sim", [])
    worlds = list(collections.OrderedDict.fromkeys(s["params"]["world_name"] for s in sims))
    if not worlds:
        return "no simulated runs"
    have = any(finite(s.get("metrics", {}).get("heading_error_deg_median_raw")) or
               finite(s.get("metrics", {}).get("wall_precision_p95_m")) for s in sims)
    if not have:
        return "no run gave heading errors or wall precision"
    plt = _plt()
    fig, axes = plt.subplots(2, len(worlds), figsize=(4 * len(worlds), 6.5), squeeze=False)
    for i, world in enumerate(worlds):
        runs = [s for s in sims if s["params"]["world_name"] == world]
        robots = list(collections.OrderedDict.fromkeys(s["params"]["robot"] for s in runs))
        drifts = sorted({s["params"]["drift_deg_per_m"] for s in runs})
        for robot in robots:
            c = COLORS.get(robot)
            for key, style, label in (("heading_error_deg_median_raw", "--", "raw"),
                                      ("heading_error_deg_median", "-", "corrected")):
                xs, ys = [], []
                for d in drifts:
                    g = [s for s in runs if s["params"]["robot"] == robot and s["params"]["drift_deg_per_m"] == d]
                    y = _median(g, key)
                    if y is not None:
                        xs.append(d), ys.append(y)
                if xs:
                    axes[0][i].plot(xs, ys, style, marker="o", color=c, label=f"{robot} {label}")
            xs, ys = [], []
            for d in drifts:
                g = [s for s in runs if s["params"]["robot"] == robot and s["params"]["drift_deg_per_m"] == d]
                y = _median(g, "wall_precision_p95_m")
                if y is not None:
                    xs.append(d), ys.append(y)
            if xs:
                axes[1][i].plot(xs, ys, "-", marker="s", color=c, label=robot)
        if not axes[0][i].lines:
            axes[0][i].text(0.5, 0.5, "heading errors n/a\n(no heading_error_deg_* keys;\nsee BENCHMARKS.md)",
                            ha="center", va="center", transform=axes[0][i].transAxes, color="0.4")
        axes[0][i].set_title(world)
        axes[0][i].set_xlabel("heading drift (deg/m)")
        axes[1][i].set_xlabel("heading drift (deg/m)")
        axes[0][i].grid(alpha=0.3)
        axes[1][i].grid(alpha=0.3)
    axes[0][0].set_ylabel("ASR heading error, median (deg)")
    axes[1][0].set_ylabel("wall precision p95 (m)")
    for ax in (axes[0][0], axes[1][0]):
        if ax.lines:
            ax.legend(fontsize=7)
    fig.suptitle("Error against odometry heading drift (median over seeds; dashed = raw odometry, solid = corrected by cogmap map)")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return None


def size_per_stage(results, path):
    """Bytes per stage per world and robot, and bytes per m^2 per storage format."""
    sims = results.get("sim", [])
    groups = collections.OrderedDict()
    for s in sims:
        groups.setdefault((s["params"]["world_name"], s["params"]["robot"]), []).append(s)
    stages = [("bytes_grid", "grid"), ("bytes_vertices", "vertices"), ("bytes_polylines", "polylines")]
    rows = [(k, [_median(g, key) for key, _ in stages]) for k, g in groups.items()]
    rows = [(k, v) for k, v in rows if any(x for x in v)]
    peers = [p for p in results.get("peers", {}).get("mrpt", []) if not p.get("na", {}).get("all")]
    if not rows and not peers:
        return "no sizes measured"
    plt = _plt()
    ncols = 2 if peers else 1
    fig, axes = plt.subplots(1, ncols, figsize=(7 * ncols, 4.8), squeeze=False)
    ax = axes[0][0]
    if rows:
        import numpy as np
        x = np.arange(len(rows))
        w = 0.27
        for j, (_, label) in enumerate(stages):
            vals = [v[j] if v[j] else 0 for _, v in rows]
            ax.bar(x + (j - 1) * w, vals, w, label=label)
        ax.set_yscale("log")
        ax.set_xticks(x)
        ax.set_xticklabels([f"{w_}\n{r}" for (w_, r), _ in rows], fontsize=7, rotation=45, ha="right")
        ax.set_ylabel("bytes (log scale)")
        ax.set_title("map size per stage (thesis table 4.2), median")
        ax.legend()
        ax.grid(axis="y", alpha=0.3)
    if peers:
        ax = axes[0][1]
        import numpy as np
        names = [p["params"]["name"] for p in peers]
        fmts = [("cogmap polylines", None), ("grid PNG", "grid_png_bytes"),
                ("map_server PGM", "grid_pgm_bytes"), ("MRPT gridmap.gz", "mrpt_gridmap_gz_bytes")]
        x = np.arange(len(names))
        w = 0.2
        for j, (label, key) in enumerate(fmts):
            vals = []
            for p in peers:
                both = p["runs"]["both"]
                floor = both.get("mapped_floor_m2") or 0
                b = p.get("polyline_bytes") if key is None else both.get("sizes", {}).get(key)
                vals.append(b / floor if b and floor else 0)
            ax.bar(x + (j - 1.5) * w, vals, w, label=label)
        ax.set_yscale("log")
        ax.set_xticks(x)
        ax.set_xticklabels(names, fontsize=7, rotation=20)
        ax.set_ylabel("bytes per m² of mapped floor (log scale)")
        ax.set_title("one map, four ways to store it")
        ax.legend(fontsize=7)
        ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return None


def time_per_asr(results, path):
    """Seconds per ASR against the ASR's index (thesis figure 4.13), longest runs."""
    series = []
    runs = {"sim": results.get("sim", []), "real": results.get("real", []),
            "thesis": results.get("thesis", []),
            "scale": [results["scale"]] if results.get("scale") else []}
    for kind in ("scale", "thesis", "sim", "real"):
        for r in runs[kind]:
            secs = r.get("asr_seconds") or []
            if len(secs) >= 3:
                p = r["params"]
                if kind == "thesis":
                    label = f"hallway-fixed-4m pioneer16 s{p['seed']}"
                elif kind == "sim":
                    label = f"{p['world_name']} {p['robot']} d{p['drift_deg_per_m']:g} s{p['seed']}"
                else:
                    label = f"{p['log_name']} d{p['drift_deg_per_m']:g}"
                series.append((kind, len(secs), label, secs))
    if not series:
        return "no map report gave per-ASR seconds"
    # The scale run, the thesis's setting, and the longest simulated and real
    # runs: four lines a reader can tell apart.
    best = collections.OrderedDict()
    for kind, n, label, secs in sorted(series, key=lambda t: -t[1]):
        if kind not in best:
            best[kind] = (label, secs)
    plt = _plt()
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.5))
    for label, secs in best.values():
        axes[0].plot(range(1, len(secs) + 1), [1000 * s for s in secs], marker=".", label=label)
        cum = []
        t = 0.0
        for s in secs:
            t += s
            cum.append(t)
        axes[1].plot(range(1, len(secs) + 1), cum, marker=".", label=label)
    thesis = 38.0 / 43.0
    axes[1].plot([1, 43], [thesis, 38.0], "k--", label="thesis: 43 ASRs in 38 s (400 MHz)")
    axes[0].set_xlabel("ASR number (order mapped)")
    axes[0].set_ylabel("processing time of the ASR (ms)")
    axes[0].set_title("time per ASR as the map grows")
    axes[1].set_xlabel("ASR number")
    axes[1].set_ylabel("cumulative processing time (s)")
    axes[1].set_yscale("log")
    axes[1].set_title("cumulative, against the thesis")
    for a in axes:
        a.grid(alpha=0.3)
        a.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return None


def make_all(results, docs_dir):
    figs, notes = [], []
    for fn, name, caption in (
            (error_vs_drift, "bench_error_vs_drift.png",
             "Heading error (top) and wall precision (bottom) against heading drift"),
            (size_per_stage, "bench_size_per_stage.png",
             "Map size per stage, and per square metre of mapped floor against grid formats"),
            (time_per_asr, "bench_time_per_asr.png",
             "Processing time per ASR as the map grows (thesis figure 4.13)")):
        try:
            why = fn(results, os.path.join(docs_dir, name))
        except ImportError as e:
            why = f"matplotlib missing ({e}): scripts/install-deps.sh --peers"
        if why:
            notes.append(f"`{name}`: n/a, {why}.")
        else:
            figs.append((name, caption))
    return figs, notes
