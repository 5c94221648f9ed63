"""docs/BENCHMARKS.md from the suite's results (results.json)."""
import collections
import math
import os

from . import issue10
from .stats import fmt_bytes, fmt_num, fmt_summary, summary
from .tool import finite

THESIS_ASRS = 43
THESIS_SECONDS = 38.0
THESIS_CPU_MHZ = 400.0

REPRODUCE = """\
## How to reproduce

```sh
bash scripts/install-deps.sh --peers   # Debian packages, including MRPT, OpenCV, python3-matplotlib
bench/run_all                          # configures and builds build/ (Release), runs everything, writes docs/
```

`bench/run_all` builds the `cogmap` command, the micro-benchmarks and the peer
programs in `build/` (`--build-dir DIR` to change, `--no-build` to use a build as
it is), then runs every job on a pool of `--jobs N` processes (default: the
number of cores), each step with a time limit (`--step-timeout`, default 600 s).
It writes this page, `docs/benchmarks/results.json` (every raw number, including
each command's wall time and peak memory) and the figures `docs/bench_*.png`,
`docs/peer_mrpt_*.png`. Intermediate logs and maps go to `build/bench-work/`.
Smaller runs: `--seeds 1`, `--worlds nine_rooms`, `--robots pioneer16`,
`--drifts 0,1`, `--skip real,micro,peers`; the pose graph's section (issue 10)
adds about 120 map runs: `--skip issue10` leaves it out, `--skip issue10-carmen` or
`issue10-cost` its two biggest pieces (`--cost-rooms N` sizes the generated
building of the cost run, 1000 rooms by default); `bench/run_all --smoke` (also
`bench/smoke`, and the ctest `bench_smoke`, label `slow`) runs one world, one
robot, one seed and one drift into a scratch folder and fails unless every metric
is present and finite.
"""

DEFINITIONS = """\
## Definitions

- **wall precision** (`wall_precision_mean_m`, `_p95_m`): distance from points every
  5 cm along the map's walls to the nearest true wall, mean and 95th percentile, in
  the world frame of the log's ground truth (so drift shows). **wall recall**: the
  share of the length of the true walls the robot could see that lies within 0.2 m of
  a map wall (`cogmap eval`, issue 4).
- **room precision / recall**: an ASR matches a true `Room` when most of its area
  lies in it; precision = share of ASRs that match a room not matched before, recall
  = share of rooms matched (issue 5). Worlds without `Room` cairns (ARIA `office`)
  have none.
- **heading error**: per ASR, |mapped heading - true heading| after removing one
  global rotation, median and max over the ASRs; *raw* = odometry, *corrected* = after
  EM (issue 6). A run mapped as a single ASR has 0 by this definition (its one error
  is the global rotation).
- **bytes per stage** (thesis table 4.2): the ASRs' grids, extracted vertices and
  final polylines, summed over ASRs.
- **map s**: wall-clock seconds of `cogmap map` on the log (reading, gridding,
  vectorizing, storing, correcting, writing every output), measured by the suite;
  **x real time** = the log's duration / map s; **s/ASR** = map s / ASR count.
- **mapped floor**: the area of the known cells (explored empty, occupied or robot
  path) of one modified-HIMM grid of the whole log at 0.1 m cells. Every map size per
  square metre below divides by this same area.
- **grid as PNG / PGM**: that grid as a map_server trinary image (occupied 0, free
  254, unknown 205) cropped to the box of known cells; PNG through libpng at the
  default compression, PGM binary (P5) with its header. **MRPT gridmap.gz**: MRPT's
  own grid of the same readings (`COccupancyGridMap2D`, serialized with
  `mrpt::serialization` into `CFileGZOutputStream`).
- Spreads: `median [min–max]` over the seeds (and over drifts where a table pools
  them); `n` runs per cell as the table says.
"""


def _pct(x):
    return "n/a" if x is None else f"{100 * x:.1f}%"


class Report:
    def __init__(self, results):
        self.r = results
        self.reasons = collections.OrderedDict()

    def na(self, reason):
        """Registers a reason and returns its footnote marker."""
        if reason not in self.reasons:
            self.reasons[reason] = len(self.reasons) + 1
        return f"n/a<sup>{self.reasons[reason]}</sup>"

    # -- helpers ---------------------------------------------------------------
    def cell(self, runs, key, digits=3, scale=1.0, reason_of=None):
        s = summary([r["metrics"].get(key) for r in runs if r.get("metrics")])
        if s:
            return fmt_summary(s, digits, scale)
        reason = reason_of(key) if reason_of else None
        if not reason:
            reason = self.reason_for(runs, key)
        return self.na(reason)

    def reason_for(self, runs, key):
        groups = ("all", "map", "heading", "eval") if key.startswith("heading_error") else ("all", "map", "eval")
        for group in groups:
            for r in runs:
                if group in r.get("na", {}):
                    return r["na"][group]
        family = "heading_error_deg_*" if key.startswith("heading_error_deg") else key
        for r in runs:
            if r.get("eval") is not None and key not in r.get("metrics", {}):
                return f"neither `cogmap eval --json` nor the map's report.json gives `{family}`"
        return f"no run gave `{key}`"

    def pair(self, runs, raw_key, key, digits=2):
        a = self.cell(runs, raw_key, digits)
        b = self.cell(runs, key, digits)
        return f"{a} → {b}"

    # -- sections ----------------------------------------------------------------
    def header(self):
        m = self.r["machine"]
        cfg = self.r["config"]
        lines = [
            "# Benchmarks",
            "",
            "Generated by `bench/run_all` (do not edit its sections by hand: run it again). Every "
            "number of its sections comes from the run described here; missing ones are n/a with "
            "the reason. Sections it does not write (measured by hand or by other scripts, each "
            "saying how) are kept from the previous file, before the figures.",
            "",
            f"- **commit** `{(m.get('commit') or 'unknown')[:12]}` ({m.get('commit_subject') or ''})"
            + (" with local changes" if m.get("dirty") else ""),
            f"- **machine**: {m.get('nproc')} cores, {m.get('cpu_model')}"
            + (f" at {m['cpu_mhz']:.0f} MHz" if m.get("cpu_mhz") else "")
            + f", {m.get('mem_total_gib')} GiB RAM, {m.get('os')}",
            f"- **run**: {self.r['started_utc']} UTC, {self.r['suite_wall_s'] / 60:.1f} min wall clock "
            f"on {cfg['jobs']} parallel jobs, build type {cfg.get('build_type', '?')}"
            + (f"; 1-minute load average {m['load_average_at_start']} at the start and "
               f"{m.get('load_average_at_end', '?')} at the end (times are wall clock: on a busy "
               "machine they grow, and their spreads with them)" if "load_average_at_start" in m else ""),
            f"- **grid of runs**: worlds {', '.join(cfg['worlds'])} x robots {', '.join(cfg['robots'])} "
            f"x drift {', '.join(f'{d:g}' for d in cfg['drifts'])} deg/m x seeds "
            f"{', '.join(str(s) for s in cfg['seeds'])} = {len(self.r.get('sim', []))} simulated runs, "
            "each `cogmap simulate` -> `cogmap map` -> `cogmap eval --json`",
            "",
        ]
        failed = cfg.get("failed_targets") or []
        if failed:
            lines.append("These targets did not build, so their figures are n/a: " +
                         ", ".join(f"`{t}`" for t in failed) + ".")
            lines.append("")
        missing = {k: v for k, v in self.r.get("commands", {}).items() if v is not True}
        if missing:
            lines.append("Not available in this build: " + "; ".join(
                f"`{k}` ({v})" for k, v in missing.items()) + ".")
            lines.append("")
        return lines

    def accuracy(self):
        sims = self.r.get("sim", [])
        out = ["## Accuracy per world, robot and drift", "",
               f"Median [min–max] over {len(self.r['config']['seeds'])} seeds. Heading errors in degrees, "
               "raw (odometry) → corrected (EM).", ""]
        helper = [r for r in sims if r.get("heading_source") == "cogmap_suite_heading_eval"]
        if helper:
            out += [f"Heading errors of {len(helper)} of the {len(sims)} runs come from the suite's helper "
                    "`bench/suite/heading_eval.cc` (the library's `cogmap::localize::ComputeHeadingErrors` "
                    "on the run's `map.sqlite`), because `cogmap eval --json` does not report the "
                    "`heading_error_deg_*` keys in this build.", ""]
        by_world = collections.OrderedDict()
        for s in sims:
            by_world.setdefault(s["params"]["world_name"], []).append(s)
        for world, runs in by_world.items():
            has_rooms = runs[0]["params"].get("has_rooms", True)
            out += [f"### {world}", "",
                    "| robot | drift °/m | wall prec. mean m | wall prec. p95 m | wall recall | "
                    "room prec. | room recall | heading median ° | heading max ° | ASRs |",
                    "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
            groups = collections.OrderedDict()
            for s in runs:
                groups.setdefault((s["params"]["robot"], s["params"]["drift_deg_per_m"]), []).append(s)
            room_reason = (lambda k: None) if has_rooms else (
                lambda k: "the world has no `Room` cairns (no ground-truth rooms)")
            for (robot, drift), g in groups.items():
                out.append("| " + " | ".join([
                    robot, f"{drift:g}",
                    self.cell(g, "wall_precision_mean_m"), self.cell(g, "wall_precision_p95_m"),
                    self.cell(g, "wall_recall"),
                    self.cell(g, "room_precision", reason_of=None if has_rooms else room_reason),
                    self.cell(g, "room_recall", reason_of=None if has_rooms else room_reason),
                    self.pair(g, "heading_error_deg_median_raw", "heading_error_deg_median"),
                    self.pair(g, "heading_error_deg_max_raw", "heading_error_deg_max"),
                    self.cell(g, "asr_count", 0)]) + " |")
            out.append("")
        return out

    def floor_plan(self):
        """Issue 11: the floor plan's figures beside the ASR walls it was made from."""
        sims = [r for r in self.r.get("sim", []) if not r["params"].get("variant")]
        out = ["## Floor plan (issue 11)", "",
               "Median [min–max] over seeds. `plan_duplication`: plan wall length lying on true walls / "
               "true wall length it covers (target <= 1.15); room IoU: each true room against its best plan "
               "room, median (target >= 0.80); overlap: area where plan rooms overlap (target 0); wall p95: "
               "plan walls against the ASR walls they were made from (target: no worse). "
               "docs/floor-plan.md describes the plan.", ""]
        helper = [r for r in sims if r.get("plan_source") == "cogmap_suite_plan_from_store"]
        if helper:
            out += [f"The plan of {len(helper)} of the {len(sims)} runs was built by the suite's helper "
                    "`bench/suite/plan_from_store.cc` (`cogmap::plan::BuildPlan` on the run's `map.sqlite`): "
                    "`cogmap map` did not write plan.json in this build.", ""]
        out += ["| world | robot | drift °/m | duplication | room IoU median | overlap m² | "
                "wall p95 m plan / ASR | wall p50 m plan | recall plan / ASR | vertices / m | walls | rooms |",
                "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
        groups = collections.OrderedDict()
        for s in sims:
            groups.setdefault((s["params"]["world_name"], s["params"]["robot"], s["params"]["drift_deg_per_m"]),
                              []).append(s)
        for (world, robot, drift), g in groups.items():
            out.append("| " + " | ".join([
                world, robot, f"{drift:g}",
                self.cell(g, "plan_duplication"), self.cell(g, "room_iou_median"),
                self.cell(g, "room_overlap_m2", 2),
                f"{self.cell(g, 'plan_wall_precision_p95_m')} / {self.cell(g, 'wall_precision_p95_m')}",
                self.cell(g, "plan_wall_precision_p50_m"),
                f"{self.cell(g, 'plan_wall_recall')} / {self.cell(g, 'wall_recall')}",
                self.cell(g, "plan_vertices_per_m", 2), self.cell(g, "plan_walls", 0),
                self.cell(g, "plan_rooms", 0)]) + " |")
        out.append("")
        return out

    def size_speed(self):
        sims = self.r.get("sim", [])
        out = ["## Size and speed per world and robot", "",
               "All drifts and seeds pooled (median [min–max]). Bytes per stage as the thesis's "
               "table 4.2, summed over ASRs.", "",
               "| world | robot | runs | grid B | vertices B | polylines B | polylines / grid | "
               "map s | x real time | s / ASR | peak MiB |",
               "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
        groups = collections.OrderedDict()
        for s in sims:
            groups.setdefault((s["params"]["world_name"], s["params"]["robot"]), []).append(s)
        for (world, robot), g in groups.items():
            ratios = [r["metrics"]["bytes_polylines"] / r["metrics"]["bytes_grid"] for r in g
                      if finite(r["metrics"].get("bytes_polylines")) and r["metrics"].get("bytes_grid")]
            rs = summary(ratios)
            out.append("| " + " | ".join([
                world, robot, str(len(g)),
                self.cell(g, "bytes_grid", 0), self.cell(g, "bytes_vertices", 0),
                self.cell(g, "bytes_polylines", 0),
                fmt_summary(rs, 3, 100.0) + " %" if rs else self.na(self.reason_for(g, "bytes_polylines")),
                self.cell(g, "map_s"), self.cell(g, "times_real_time"), self.cell(g, "seconds_per_asr"),
                self.cell(g, "map_peak_rss_mib")]) + " |")
        out.append("")
        return out

    def thesis_speed(self):
        sims = self.r.get("sim", [])
        thesis = THESIS_SECONDS / THESIS_ASRS
        out = ["## Speed against the thesis", "",
               f"The thesis mapped 43 ASRs of 4 m in 38 s in batch on a 400 MHz Pentium "
               f"(figure 4.13): {thesis:.3f} s per ASR, which includes its grid building and "
               "vectorization. cogmap's s/ASR below is the whole `cogmap map` command (reading "
               "the log, every stage, the SQLite store and every output file) divided by the "
               "number of ASRs.", ""]
        mhz = self.r["machine"].get("cpu_mhz")
        th = self.r.get("thesis", [])
        ts = summary([r["metrics"].get("seconds_per_asr") for r in th if r.get("metrics")])
        if th:
            out.append(f"- **the thesis's own setting**, `hallway_loop` mapped with `cogmap map --boundary fixed "
                       f"--asr-length 4` (16 sonars, no drift, {len(th)} seeds): "
                       f"{self.cell(th, 'asr_count', 0)} ASRs in {self.cell(th, 'map_s')} s, "
                       f"{self.cell(th, 'seconds_per_asr')} s per ASR"
                       + (f": {thesis / ts['median']:.0f} times the thesis's speed." if ts else "."))
        s = summary([r["metrics"].get("seconds_per_asr") for r in sims if r.get("metrics")])
        if s:
            out.append(f"- all simulated runs (doorway boundaries, every world and robot): {fmt_summary(s)} s "
                       f"per ASR, {thesis / s['median']:.0f} times the thesis's speed (median).")
        else:
            out.append("- all simulated runs: " + self.na(self.reason_for(sims, "seconds_per_asr")))
        ref = ts or s
        if mhz and ref:
            clock = mhz / THESIS_CPU_MHZ
            out.append(f"- this CPU's clock is {clock:.1f} times the thesis's ({mhz:.0f} MHz against 400 MHz), "
                       f"so per clock cycle cogmap runs at {thesis / ref['median'] / clock:.1f} times the "
                       f"thesis's speed ({'fixed-length setting' if ts else 'all runs'}).")
        out.append("")
        return out

    def scale(self):
        sc = self.r.get("scale")
        out = ["## Scale: a generated building", ""]
        if not sc:
            return out + ["Not run (`--skip scale` or `--scale-rooms 0`).", ""]
        p = sc["params"]
        out.append(f"`cogmap gen-building` with {p['rooms']} rooms along a corridor, simulated with "
                   "the 16-sonar ring without drift, then `cogmap map` (issue 5's scale test).")
        out.append("")
        if sc.get("na", {}).get("all"):
            return out + [self.na(sc["na"]["all"]), ""]
        m = sc["metrics"]
        g = [sc]
        out += ["| ASRs | map s | log s | x real time | s / ASR | peak MiB | polylines B | grid B | "
                "room prec. | room recall |", "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
                "| " + " | ".join([self.cell(g, "asr_count", 0), self.cell(g, "map_s"),
                                   self.cell(g, "log_duration_s"), self.cell(g, "times_real_time"),
                                   self.cell(g, "seconds_per_asr"), self.cell(g, "map_peak_rss_mib"),
                                   self.cell(g, "bytes_polylines", 0), self.cell(g, "bytes_grid", 0),
                                   self.cell(g, "room_precision"), self.cell(g, "room_recall")]) + " |", ""]
        mb = sc.get("map_bench")
        if mb and isinstance(mb.get("checkpoints"), list):
            out += ["`cogmap_map_bench` (issue 5's scale benchmark) on the same log, streaming into a store:", "",
                    "| at | records | ASRs | µs per reading | VmHWM KiB | cells of the current grid |",
                    "|---|---:|---:|---:|---:|---:|"]
            for c in mb["checkpoints"]:
                out.append(f"| {c.get('at')} | {c.get('records')} | {c.get('asr_count')} | "
                           f"{fmt_num(c.get('us_per_reading'))} | {c.get('vm_hwm_kb')} | {c.get('current_grid_cells')} |")
            out += ["", f"Peak memory at 100% over 10%: {fmt_num(mb.get('hwm_ratio_100_over_10'))}; time per "
                    f"reading at 100% over 10%: {fmt_num(mb.get('time_ratio_100_over_10'))}.", ""]
        elif sc.get("na", {}).get("map_bench"):
            out += ["`cogmap_map_bench`: " + self.na(sc["na"]["map_bench"]), ""]
        secs = sc.get("asr_seconds") or []
        if len(secs) >= 10:
            k = max(1, len(secs) // 10)
            first, last = sorted(secs[:k]), sorted(secs[-k:])
            out.append(f"Per-ASR processing time, first 10% of the ASRs: median "
                       f"{1000 * first[len(first) // 2]:.2f} ms; last 10%: median "
                       f"{1000 * last[len(last) // 2]:.2f} ms (the thesis claims a cost per step that "
                       "does not grow with the map; see `bench_time_per_asr.png`).")
            out.append("")
        return out

    def real(self):
        reals = self.r.get("real", [])
        out = ["## Real logs", "",
               "`cogmap map` on the logs of `../shared/data` (no ground-truth walls; the CARMEN "
               "logs' corrected poses are the heading reference, so drift added to their odometry "
               "is measured when `cogmap eval` gives heading errors for them).", "",
               "| log | added drift °/m | ASRs | grid B | polylines B | map s | log s | x real time | "
               "s / ASR | heading median ° raw → corr. | heading max ° raw → corr. |",
               "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
        helper = [r["params"]["log_name"] for r in reals if r.get("heading_source") == "cogmap_suite_heading_eval"]
        if helper:
            out[-2:-2] = ["Heading errors of " + ", ".join(f"`{h}`" for h in helper) + " come from the "
                          "suite's helper `bench/suite/heading_eval.cc` (`cogmap::localize::ComputeHeadingErrors` "
                          "on the run's `map.sqlite`, against the poses the log gives as true), because "
                          "`cogmap eval` wants a world for a real log.", ""]
        for r in reals:
            p = r["params"]
            g = [r]
            out.append("| " + " | ".join([
                p["log_name"], f"{p['drift_deg_per_m']:g}", self.cell(g, "asr_count", 0),
                self.cell(g, "bytes_grid", 0), self.cell(g, "bytes_polylines", 0),
                self.cell(g, "map_s"), self.cell(g, "log_duration_s"), self.cell(g, "times_real_time"),
                self.cell(g, "seconds_per_asr"),
                self.pair(g, "heading_error_deg_median_raw", "heading_error_deg_median"),
                self.pair(g, "heading_error_deg_max_raw", "heading_error_deg_max")]) + " |")
        out.append("")
        return out

    def peers(self):
        out = ["## Peers", "", "### Occupancy grid: MRPT `COccupancyGridMap2D` against cogmap's modified HIMM", "",
               "Same readings, same poses (the true poses for the simulated logs, odometry for the real "
               "ones), 0.1 m cells, readings used up to the MHIMM "
               "window w = 3 m (MRPT's `maxDistanceInsertion`). MRPT fuses each sonar reading over "
               "its whole cone (log-odds, free triangle and occupied arc), cogmap's MHIMM only "
               "along the beam's centre line, as the thesis does; for the laser both trace rays. "
               "Time is insertion only (the log is read first); memory is the peak resident "
               "memory of a process building only that grid minus a process that only reads the "
               "log (the grids are small next to the libraries, so these differences are within "
               "about 1 MiB of noise; the grids' own sizes are the columns after).", "",
               "| log | sensor | readings | cogmap s | MRPT s | cogmap readings/s | MRPT readings/s | "
               "peak MiB log only / cogmap / MRPT | cogmap grid B in memory | MRPT grid B in memory | "
               "cogmap known m² | MRPT known m² | picture |",
               "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
        acc_rows = []
        wins = []
        size_rows = []
        for p in self.r.get("peers", {}).get("mrpt", []):
            name = p["params"]["name"]
            if "all" in p.get("na", {}):
                out.append(f"| {name} | " + " | ".join([self.na(p["na"]["all"])] * 11) + " | |")
                continue
            runs = p["runs"]
            base = runs["none"]["process_peak_rss_kib"]
            c, m = runs["cogmap"]["cogmap"], runs["mrpt"]["mrpt"]
            dc = (runs["cogmap"]["process_peak_rss_kib"] - base) / 1024.0
            dm = (runs["mrpt"]["process_peak_rss_kib"] - base) / 1024.0
            both = runs["both"]
            out.append("| " + " | ".join([
                name, both.get("sensor", "?"), str(both.get("readings")),
                fmt_num(c["insert_s"]), fmt_num(m["insert_s"]),
                f"{c['readings_per_s']:.3g}", f"{m['readings_per_s']:.3g}",
                f"{base / 1024:.1f} / {base / 1024 + dc:.1f} / {base / 1024 + dm:.1f}",
                fmt_bytes(c["grid_bytes_in_memory"]),
                fmt_bytes(m["grid_bytes_in_memory"]), fmt_num(c["known_area_m2"]),
                fmt_num(m["known_area_m2"]), f"[png]({p.get('png', '')})"]) + " |")
            if m["insert_s"] < c["insert_s"]:
                wins.append(f"MRPT builds its grid faster on `{name}` ({fmt_num(m['insert_s'])} s "
                            f"against {fmt_num(c['insert_s'])} s).")
            if m["grid_bytes_in_memory"] < c["grid_bytes_in_memory"]:
                wins.append(f"MRPT's grid takes less memory on `{name}` "
                            f"({fmt_bytes(m['grid_bytes_in_memory'])}: 1 byte per cell, against "
                            f"{fmt_bytes(c['grid_bytes_in_memory'])} for cogmap's float cells).")
            if m["known_area_m2"] > c["known_area_m2"] * 1.05:
                wins.append(f"MRPT's cone model covers more floor from the same readings on `{name}` "
                            f"({fmt_num(m['known_area_m2'])} m² known against {fmt_num(c['known_area_m2'])} m²).")
            size_rows.append((name, p))
            ca, ma = both.get("cogmap", {}).get("occupied_vs_walls"), both.get("mrpt", {}).get("occupied_vs_walls")
            if ca and ma and "mean_m" in ca and "mean_m" in ma:
                acc_rows.append("| " + " | ".join([
                    name, str(ca["occupied_cells"]), str(ma["occupied_cells"]),
                    _pct(ca["share_within_0_2m"]), _pct(ma["share_within_0_2m"]),
                    fmt_num(ca["mean_m"]), fmt_num(ma["mean_m"]), fmt_num(ca["p95_m"]),
                    fmt_num(ma["p95_m"])]) + " |")
                better_share = ma["share_within_0_2m"] > ca["share_within_0_2m"] + 0.005
                same_share = abs(ma["share_within_0_2m"] - ca["share_within_0_2m"]) <= 0.005
                if better_share or (same_share and ma["mean_m"] < ca["mean_m"]):
                    why = ("MRPT fuses each reading over its cone, so a wall appears where several cones "
                           "agree; the MHIMM's centre-line hits with +1.5 on 8 neighbours thicken walls"
                           if both.get("sensor") == "sonar" else
                           "MRPT marks only the end cell of each beam; the MHIMM adds +1.5 to the 8 "
                           "neighbours of every hit, so its walls are about three cells thick")
                    wins.append(f"MRPT's grid is closer to the true walls on `{name}`: "
                                f"{_pct(ma['share_within_0_2m'])} of its occupied cells within 0.2 m, mean "
                                f"{fmt_num(ma['mean_m'])} m, against {_pct(ca['share_within_0_2m'])} and "
                                f"{fmt_num(ca['mean_m'])} m for the MHIMM ({why}; cogmap's clean stage "
                                "thins them to one cell before vectorizing).")
        out.append("")
        if acc_rows:
            out += ["Occupied cells (MHIMM: value > 7; MRPT: occupancy probability > 0.65) against the "
                    "true walls of the simulated world, with the true poses (so only the fusion rule "
                    "differs):", "",
                    "| log | cogmap occupied cells | MRPT occupied cells | cogmap within 0.2 m | "
                    "MRPT within 0.2 m | cogmap mean m | MRPT mean m | cogmap p95 m | MRPT p95 m |",
                    "|---|---:|---:|---:|---:|---:|---:|---:|---:|"] + acc_rows + [""]
        out += self.sizes(size_rows, wins)
        out += self.opencv(wins)
        out += ["### Where a peer does better", ""]
        if wins:
            out += [f"- {w}" for w in wins]
        else:
            out.append("- In this run, no peer figure beat cogmap's on the measures above.")
        out.append("")
        return out

    def _polyline_bytes_for(self, name):
        """cogmap's polyline bytes for the log a peer comparison used."""
        src = self.r.get("peers", {}).get("sources", {}).get(name)
        if not src:
            return None, None
        kind, key = src
        pool = self.r.get(kind, [])
        for r in pool:
            if r.get("name") == key or r.get("job") == key:
                v = r.get("metrics", {}).get("bytes_polylines")
                return (float(v) if finite(v) else None), r
        return None, None

    def sizes(self, size_rows, wins):
        out = ["### Map size per square metre of mapped floor", "",
               "One log, one mapped floor (see Definitions), four ways to store the map (cogmap's polylines, and three grid formats). cogmap's "
               "polylines are the `bytes_polylines` of `cogmap map` on the same log.", "",
               "| log | mapped floor m² | cogmap polylines B/m² | grid PNG B/m² | map_server PGM B/m² | "
               "MRPT gridmap.gz B/m² | polylines / PNG |",
               "|---|---:|---:|---:|---:|---:|---:|"]
        for name, p in size_rows:
            both = p["runs"]["both"]
            floor = both.get("mapped_floor_m2") or 0
            sz = both.get("sizes", {})
            poly, _ = self._polyline_bytes_for(name)
            per = lambda b: fmt_num(b / floor) if b and floor else "n/a"
            poly_cell = per(poly) if poly else self.na(
                f"no `bytes_polylines` from `cogmap map` for the log of {name}")
            ratio = f"{100 * poly / sz['grid_png_bytes']:.1f}%" if poly and sz.get("grid_png_bytes") else "n/a"
            out.append("| " + " | ".join([
                name, fmt_num(floor), poly_cell, per(sz.get("grid_png_bytes")),
                per(sz.get("grid_pgm_bytes")), per(sz.get("mrpt_gridmap_gz_bytes")), ratio]) + " |")
            if poly and sz.get("grid_png_bytes") and sz["grid_png_bytes"] < poly:
                wins.append(f"The grid as PNG is smaller than cogmap's polylines on `{name}`.")
            if poly and sz.get("mrpt_gridmap_gz_bytes") and sz["mrpt_gridmap_gz_bytes"] < poly:
                wins.append(f"MRPT's compressed gridmap is smaller than cogmap's polylines on `{name}`.")
        out.append("")
        return out

    def opencv(self, wins=None):
        wins = wins if wins is not None else []
        cv = self.r.get("peers", {}).get("opencv", [])
        ov = self.r.get("peers", {}).get("opencv_vectorize", [])
        out = ["### Vectorization: OpenCV `findContours` + `approxPolyDP` against cogmap's pipeline", ""]
        if ov:
            out += ["`bench/peer_opencv_vectorize.cc`: one modified-HIMM grid of the whole simulated run "
                    "(true poses, no drift), cleaned by cogmap's clean stage (SPEC 3.1); then cogmap's "
                    "extract, vertex simplify, Douglas-Peucker and line fit against OpenCV's "
                    "`findContours` (RETR_LIST) and `approxPolyDP` with the same tolerance (1.5 cells). "
                    "Times exclude the shared clean stage and are the median of 7 runs; bytes are both "
                    "sides' polylines in cogmap's polyline encoding. OpenCV traces the outline of each "
                    "one-cell-thick wall, so each wall appears twice (along and back).", "",
                    "| log | cogmap mode | vertices cogmap / OpenCV | bytes cogmap / OpenCV | "
                    "wall prec. mean m cogmap / OpenCV | wall prec. p95 m | wall recall | ms cogmap / OpenCV | "
                    "clean ms |", "|---|---|---:|---:|---:|---:|---:|---:|---:|"]
            for p in ov:
                name, mode = p["params"]["name"], p["params"]["mode"]
                if p.get("na", {}).get("all"):
                    out.append(f"| {name} | {mode} | " + " | ".join([self.na(p["na"]["all"])] * 7) + " |")
                    continue
                d = p["result"]
                c, o = d["cogmap"], d["opencv"]
                pair = lambda k, f=fmt_num: f"{f(c[k])} / {f(o[k])}"
                out.append("| " + " | ".join([
                    name, mode, pair("vertex_count", lambda x: str(int(x))),
                    pair("bytes_polylines", lambda x: str(int(x))),
                    pair("wall_precision_mean_m"), pair("wall_precision_p95_m"), pair("wall_recall"),
                    f"{1000 * c['seconds']:.3f} / {1000 * o['seconds']:.3f}",
                    f"{1000 * d['clean_seconds']:.2f}"]) + " |")
                if o["seconds"] < c["seconds"]:
                    wins.append(f"OpenCV vectorizes `{name}` ({mode}) faster: {1000 * o['seconds']:.3f} ms "
                                f"against {1000 * c['seconds']:.3f} ms (after the shared clean stage).")
                if o["wall_recall"] > c["wall_recall"] + 0.01:
                    wins.append(f"OpenCV's outlines find more of the true walls on `{name}` ({mode}): recall "
                                f"{fmt_num(o['wall_recall'])} against {fmt_num(c['wall_recall'])}.")
                if o["wall_precision_mean_m"] < c["wall_precision_mean_m"] - 0.005:
                    wins.append(f"OpenCV's outlines lie closer to the true walls on `{name}` ({mode}): mean "
                                f"{fmt_num(o['wall_precision_mean_m'])} m against "
                                f"{fmt_num(c['wall_precision_mean_m'])} m.")
                if o["vertex_count"] < c["vertex_count"]:
                    wins.append(f"OpenCV needs fewer vertices on `{name}` ({mode}).")
            out.append("")
        if not cv:
            if not ov:
                out += [self.na("no OpenCV comparison program in build/bench/"), ""]
            return out
        for c in cv:
            out.append(f"`{c['params']['binary']}` (the vectorization issue's comparison on synthetic room "
                       "layouts), as it prints it:")
            out.append("")
            if "na" in c and c["na"].get("all"):
                out.append(self.na(c["na"]["all"]))
            elif c.get("benchmarks"):
                out += self._bench_table(c["benchmarks"])
            else:
                out += ["```", (c.get("stdout") or "").strip()[:4000], "```"]
            out.append("")
        return out

    def _bench_table(self, rows):
        extra = sorted({k for r in rows for k in r if k and finite(r.get(k)) and k not in (
            "name", "real_time", "cpu_time", "time_unit", "iterations")})
        out = ["| " + " | ".join(["benchmark", "time per iteration"] + extra) + " |",
               "|---|---:|" + "---:|" * len(extra)]
        for r in rows:
            t = f"{fmt_num(r.get('real_time'))} {r.get('time_unit', '')}"
            out.append("| " + " | ".join([f"`{r['name']}`", t] + [
                (f"{r[k]:.4g}" if finite(r.get(k)) else "") for k in extra]) + " |")
        return out

    def micro(self):
        out = ["## Micro-benchmarks", "",
               "Every `build/bench/*_bench` (Google Benchmark, `--benchmark_format=json`), real time "
               "per iteration and the counters each benchmark reports.", ""]
        micro = self.r.get("micro", [])
        if not micro:
            out += [self.na("no *_bench executable in build/bench/"), ""]
        for m in micro:
            out += [f"### {m['params']['binary']}", ""]
            if m.get("na", {}).get("all"):
                out += [self.na(m["na"]["all"]), ""]
                continue
            out += self._bench_table(m.get("benchmarks", [])) + [""]
        return out

    def figures(self):
        out = ["## Figures", ""]
        for f, caption in self.r.get("figures", []):
            out += [f"![{caption}]({f})", "", f"*{caption}*", ""]
        for p in self.r.get("peers", {}).get("mrpt", []):
            if p.get("png") and not p.get("na", {}).get("all"):
                out += [f"![MRPT and cogmap grids, {p['params']['name']}]({p['png']})", "",
                        f"*Left cogmap's modified HIMM (grey unknown, white empty, black occupied, red "
                        f"robot path), right MRPT's COccupancyGridMap2D (darker = more likely occupied), "
                        f"same readings and poses: {p['params']['name']}.*", ""]
        for msg in self.r.get("figure_notes", []):
            out += [f"- {msg}"]
        out.append("")
        return out

    def footnotes(self):
        if not self.reasons:
            return []
        out = ["## Why some figures are n/a", ""]
        for reason, n in self.reasons.items():
            out.append(f"{n}. {reason}")
        out.append("")
        return out

    def markdown(self):
        body = []
        body += self.accuracy()
        body += self.floor_plan()
        body += self.size_speed()
        body += self.thesis_speed()
        body += self.scale()
        body += self.real()
        body += issue10.section(self)
        body += self.peers()
        body += self.micro()
        body += self.figures()
        lines = self.header() + [REPRODUCE] + body + self.footnotes() + [DEFINITIONS]
        return "\n".join(lines).rstrip() + "\n"
