"""Issue 10's figures (the pose graph over ASRs), each beside `--no-graph` (the
default before issue 10) and the raw odometry, in one run of the suite:

  sim      simulated, 16 sonars, 1 and 2 deg/m, every seed, on nine_rooms,
           hallway_loop, aria/office and cluttered_lab: the suite's default-mode
           runs (the pose graph) of phase 1, mapped again with `--no-graph` and
           with `--no-correct` (the odometry's own map);
  carmen   the five CARMEN logs, laser and `convert --as-sonar pioneer16`, with
           0 and 1 deg/m added (`map --add-drift-deg-per-m`), both ways;
  cost     a generated 1000-room building, simulated and mapped, whole-command
           time per ASR and peak memory at the first 10 % of the run against
           100 %.

`bench/run_all --skip issue10` leaves all of it out; `issue10-carmen` and
`issue10-cost` leave out the two big pieces (`--cost-rooms N` sizes the last).
"""
import os
import re
import shutil

from . import cases, drift_check, runner
from .stats import fmt_num, fmt_summary, summary
from .tool import finite, lookup, parse_json_output, read_json

WORLDS = ["nine_rooms", "hallway_loop", "aria/office", "cluttered_lab"]
ROBOT = "pioneer16"
DRIFTS = [1.0, 2.0]  # (a) at 1 deg/m, (b) at 2 deg/m
CARMEN = ["intel", "aces", "belgioioso", "fhw", "freiburg-101"]
SONAR = "pioneer16"
COST_ROOMS = 1000

# Variants of `cogmap map` beside the default (the pose graph).
VARIANTS = {"graph": (), "nograph": ("--no-graph",), "raw": ("--no-correct",)}

# Keys of `cogmap eval --json` the section uses.
EVAL_KEYS = ["wall_precision_p95_m", "wall_recall", "asr_count", "room_precision", "room_recall",
             "heading_error_deg_median", "heading_error_deg_median_raw",
             "ate_rmse_m", "ate_rmse_m_raw", "rpe_5m_trans_m", "rpe_5m_trans_m_raw",
             "rpe_5m_rot_deg", "rpe_5m_rot_deg_raw",
             "pose_calibration_3sigma", "pose_calibration_position_3sigma",
             "pose_calibration_heading_3sigma", "pose_calibration_asrs", "odometry_drift_deg_per_m"]


def graph_summary(report):
    """The scalars of report.json's `pose_graph` object (None without one)."""
    pg = report.get("pose_graph") if isinstance(report, dict) else None
    if not isinstance(pg, dict):
        return None
    out = {}
    for k in ("solution", "closures_accepted", "revisits", "rooms", "drift_rate_deg_per_m",
              "drift_rate_sigma_deg_per_m", "drift_rate_spread_sigma_deg_per_m", "chi2",
              "chi2_dof", "registrations", "solve_seconds", "covariance_seconds"):
        if k in pg and (finite(pg[k]) or isinstance(pg[k], str)):
            out[k] = pg[k]
    cands = pg.get("closure_candidates")
    if isinstance(cands, list):
        out["closure_candidates"] = len(cands)
        out["closures_rejected"] = sum(1 for c in cands if isinstance(c, dict) and not c.get("accepted"))
    unc = pg.get("uncertain_asrs")
    if isinstance(unc, list):
        out["uncertain_asrs"] = len(unc)
    warn = pg.get("warnings")
    if isinstance(warn, list):
        out["warnings"] = len(warn)
        out["warning_texts"] = [str(w)[:200] for w in warn[:5]]
    pl = pg.get("placements")
    if isinstance(pl, list):
        out["placements"] = len(pl)
        pos = sorted((p["sigma_x_m"] ** 2 + p["sigma_y_m"] ** 2) ** 0.5 for p in pl if isinstance(p, dict)
                     and finite(p.get("sigma_x_m")) and finite(p.get("sigma_y_m")))
        rot = sorted(p["sigma_theta_deg"] for p in pl if isinstance(p, dict) and finite(p.get("sigma_theta_deg")))
        if pos:
            out["sigma_position_median_m"] = pos[len(pos) // 2]
        if rot:
            out["sigma_theta_median_deg"] = rot[len(rot) // 2]
    return out


def _eval_metrics(ev):
    m = {}
    for k in EVAL_KEYS:
        v = lookup(ev, k) if isinstance(ev, dict) else None
        if finite(v):
            m[k] = float(v)
    return m


def _map_and_eval(ctx, log, out, extra, world=None, do_eval=True, timeout_s=None):
    """`cogmap map LOG -o OUT EXTRA...` then `cogmap eval OUT --json` (with the
    world when given). Returns a variant's result dict."""
    c = ctx.cogmap
    res = {"steps": {}, "metrics": {}, "na": {}}
    for opt in extra:
        if str(opt).startswith("--") and not c.has_option("map", opt):
            res["na"]["all"] = f"`cogmap map` has no option {opt}"
            return res
    shutil.rmtree(out, ignore_errors=True)
    argv = [c.binary, "map", log, "-o", out] + list(extra)
    if world and c.has_option("map", "--world"):
        argv += ["--world", world]
    s = (runner.run_command([str(a) for a in argv], timeout_s=timeout_s) if timeout_s else ctx.run(argv))
    res["steps"]["map"] = cases._step_summary(s)
    if not s.ok:
        res["na"]["all"] = s.reason()
        return res
    report = read_json(os.path.join(out, "report.json")) or {}
    g = graph_summary(report)
    if g is not None:
        res["graph"] = g
    for k in ("log_duration_s", "total_seconds", "mapping_seconds", "max_rss_kb_mapping", "asr_count"):
        v = lookup(report, k)
        if finite(v):
            res["metrics"]["report_" + k] = float(v)
    if "report_asr_count" not in res["metrics"] and isinstance(report.get("asrs"), list):
        res["metrics"]["report_asr_count"] = float(len(report["asrs"]))
    res["metrics"]["map_s"] = s.wall_s
    res["metrics"]["map_peak_rss_mib"] = s.maxrss_kib / 1024.0
    dur = res["metrics"].get("report_log_duration_s")
    if dur:
        res["metrics"]["times_real_time"] = dur / max(s.wall_s, 1e-9)
    n = res["metrics"].get("report_asr_count")
    if n and finite(res["metrics"].get("report_mapping_seconds")):
        res["metrics"]["mapping_seconds_per_asr"] = res["metrics"]["report_mapping_seconds"] / n
    if not do_eval:
        if n:
            res["metrics"]["seconds_per_asr"] = s.wall_s / n
        return res
    argv = [c.binary, "eval", out, "--json"] + (["--world", world] if world else [])
    s = ctx.run(argv)
    res["steps"]["eval"] = cases._step_summary(s)
    ev = parse_json_output(s.stdout) if s.ok else None
    if ev is None:
        res["na"]["eval"] = s.reason() if not s.ok else "`cogmap eval --json` printed no JSON object"
    else:
        res["metrics"].update(_eval_metrics(ev))
    n = res["metrics"].get("asr_count", res["metrics"].get("report_asr_count"))
    if n:
        res["metrics"]["seconds_per_asr"] = res["metrics"]["map_s"] / n
    return res


def sim_log_path(ctx, world_path, drift, seed):
    """The log cases.sim_job writes for this world, robot, drift and seed."""
    name = os.path.splitext(os.path.basename(world_path))[0]
    return os.path.join(ctx.work_dir, "sim", f"{name}_{ROBOT}_d{drift:g}_s{seed}.log")


def variant_job(ctx, world_path, drift, seed, variant):
    """Maps the log of a phase-1 run again with a variant's options."""
    name = os.path.splitext(os.path.basename(world_path))[0]

    def run(job):
        log = sim_log_path(ctx, world_path, drift, seed)
        if not os.path.exists(log):
            return {"params": job.params, "na": {"all": "the simulated log of phase 1 is missing"}}
        out = os.path.join(ctx.work_dir, "issue10", "map", f"{name}_d{drift:g}_s{seed}_{variant}")
        res = _map_and_eval(ctx, log, out, VARIANTS[variant], world_path)
        res["params"] = job.params
        return res

    return runner.Job(name=f"issue10/sim/{name}/{drift:g}/{seed}/{variant}", kind="issue10_sim",
                      params={"world_name": name, "world": world_path, "drift_deg_per_m": drift, "seed": seed,
                              "variant": variant},
                      run=run, cost=3.0 if name in ("hallway_loop", "office") else 1.0)


def carmen_path(shared, name):
    return os.path.join(shared, "data", "carmen", f"{name}-corrected.log.gz")


def carmen_job(ctx, name, sensor, drifts=(0.0, 1.0)):
    """One CARMEN log with one sensor: laser as logged, or sonar from
    `cogmap convert --as-sonar`; each added drift mapped with the pose graph
    and with `--no-graph`, each map scored against the log's reference poses."""

    def run(job):
        res = {"params": job.params, "steps": {}, "na": {}, "runs": {}}
        c = ctx.cogmap
        path = carmen_path(ctx.shared_dir, name)
        if not os.path.exists(path):
            res["na"]["all"] = f"{os.path.basename(path)} is not in ../shared/data/carmen"
            return res
        base = os.path.join(ctx.work_dir, "issue10", "carmen")
        os.makedirs(base, exist_ok=True)
        log = path
        if sensor == "sonar":
            if not c.has_option("convert", "--as-sonar"):
                res["na"]["all"] = "`cogmap convert` has no option --as-sonar"
                return res
            log = os.path.join(base, f"{name}_{SONAR}.log")
            s = ctx.run([c.binary, "convert", path, "--as-sonar", SONAR, "-o", log])
            res["steps"]["convert"] = cases._step_summary(s)
            if not s.ok:
                res["na"]["all"] = s.reason()
                return res
        for d in drifts:
            for variant in ("graph", "nograph"):
                extra = list(VARIANTS[variant])
                if d:
                    extra += ["--add-drift-deg-per-m", d]
                out = os.path.join(base, f"{name}_{sensor}_d{d:g}_{variant}")
                res["runs"][f"{d:g}/{variant}"] = _map_and_eval(ctx, log, out, extra)
        if sensor == "sonar":
            try:
                os.remove(log)  # tens of MB each; the maps keep what the report needs
            except OSError:
                pass
        return res

    return runner.Job(name=f"issue10/carmen/{name}/{sensor}", kind="issue10_carmen",
                      params={"log_name": name, "sensor": sensor, "drifts": list(drifts)}, run=run,
                      cost=12.0 if name == "intel" else 8.0)


def cost_job(ctx, rooms, seed=1, share=0.1):
    """A generated building of 'rooms' rooms, simulated to the end and to the
    first 'share' of its duration, each mapped (pose graph; the whole run also
    with `--no-graph`): whole-command seconds per ASR and peak memory."""

    def run(job):
        res = {"params": job.params, "steps": {}, "na": {}, "runs": {}}
        c = ctx.cogmap
        for cmd in ("gen-building", "simulate", "map"):
            if not c.has(cmd):
                res["na"]["all"] = c.missing_reason(cmd)
                return res
        base = os.path.join(ctx.work_dir, "issue10", "cost")
        os.makedirs(base, exist_ok=True)
        world = os.path.join(base, f"building_{rooms}.map")
        # A room every 8 m of corridor on each side (gen-building's default
        # corridor is 1000 m, sized for 100 rooms).
        corridor = max(1000.0, 4.0 * rooms)
        argv = [c.binary, "gen-building", "--rooms", rooms, "--seed", seed, "-o", world]
        if c.has_option("gen-building", "--corridor-m"):
            argv[-2:-2] = ["--corridor-m", corridor]
        s = ctx.run(argv)
        res["steps"]["gen-building"] = cases._step_summary(s)
        if not s.ok:
            res["na"]["all"] = s.reason()
            return res
        res["corridor_m"] = corridor
        full = os.path.join(base, f"building_{rooms}_full.log")
        s = ctx.run([c.binary, "simulate", world, "--robot", ROBOT, "--seed", seed, "--drift-deg-per-m", 0,
                     "-o", full])
        res["steps"]["simulate_full"] = cases._step_summary(s)
        if not s.ok:
            res["na"]["all"] = s.reason()
            return res
        logs = {"100": full}
        if c.has_option("simulate", "--max-time"):
            m = re.search(r"simulated ([0-9.]+) s", s.stdout)
            dur = float(m.group(1)) if m else _native_log_duration(full)
            if dur:
                part = os.path.join(base, f"building_{rooms}_{int(share * 100)}pct.log")
                s = ctx.run([c.binary, "simulate", world, "--robot", ROBOT, "--seed", seed, "--drift-deg-per-m",
                             0, "--max-time", round(share * dur, 1), "-o", part])
                res["steps"]["simulate_part"] = cases._step_summary(s)
                if s.ok:
                    logs["10"] = part
                else:
                    res["na"]["part"] = s.reason()
            else:
                res["na"]["part"] = "no duration in the simulated log"
        else:
            res["na"]["part"] = "`cogmap simulate` has no option --max-time"
        # Maps and logs take hundreds of MB at 1000 rooms (map.pgm alone is
        # about 300 MB): each goes once its figures are read.
        todo = [(f"{at}/graph", log, ()) for at, log in sorted(logs.items(), key=lambda kv: int(kv[0]))]
        todo.append(("100/nograph", full, VARIANTS["nograph"]))
        for key, log, extra in todo:
            out = os.path.join(base, "map_" + key.replace("/", "_"))
            res["runs"][key] = _map_and_eval(ctx, log, out, extra, world, do_eval=False,
                                             timeout_s=max(ctx.step_timeout_s, 1800.0))
            shutil.rmtree(out, ignore_errors=True)
        for log in logs.values():
            try:
                os.remove(log)
            except OSError:
                pass
        return res

    return runner.Job(name=f"issue10/cost/building_{rooms}", kind="issue10_cost",
                      params={"rooms": rooms, "seed": seed, "share": share}, run=run, cost=100.0)


def _native_log_duration(path):
    """Seconds from the first to the last time stamp of a native log (its
    records start with the time, docs/log-format.md)."""
    first = last = None
    try:
        with open(path, errors="replace") as f:
            for line in f:
                parts = line.split()
                if len(parts) < 2 or line.startswith("#"):
                    continue
                try:
                    t = float(parts[1])
                except ValueError:
                    continue
                if first is None:
                    first = t
                last = t
    except OSError:
        return None
    return (last - first) if first is not None and last > first else None


def phase1_jobs(ctx, world_path_of, grid_names, seeds, selected, smoke):
    """The default-mode (pose graph) runs the section needs that the suite's
    grid does not already make: kind 'issue10_graph', kept out of the grid's
    tables. 'grid_names' are the names of the grid's sim jobs; 'selected' the
    worlds of the run (`--worlds`)."""
    jobs = []
    for w in worlds(selected, smoke):
        wp = world_path_of(w)
        if not os.path.exists(wp):
            continue
        for d in drifts(smoke):
            for s in seeds:
                j = cases.sim_job(ctx, wp, ROBOT, d, s)
                if j.name not in grid_names:
                    j.kind = "issue10_graph"
                    jobs.append(j)
    return jobs


def worlds(selected, smoke):
    """The section's worlds that the run selected (all four by default)."""
    return [w for w in WORLDS if w in selected or w.split("/")[-1] in selected][:1 if smoke else None]


def drifts(smoke):
    return DRIFTS[:1] if smoke else DRIFTS


def phase2_jobs(ctx, world_path_of, seeds, selected, smoke, skip, cost_rooms):
    jobs = []
    for w in worlds(selected, smoke):
        wp = world_path_of(w)
        if not os.path.exists(wp):
            continue
        for d in drifts(smoke):
            for s in seeds:
                for v in (("nograph", "raw") if d == 1.0 else ("nograph",)):
                    jobs.append(variant_job(ctx, wp, d, s, v))
    if not smoke and "issue10-carmen" not in skip:
        for name in CARMEN:
            for sensor in ("laser", "sonar"):
                jobs.append(carmen_job(ctx, name, sensor))
    if not smoke and "issue10-cost" not in skip and cost_rooms > 0:
        jobs.append(cost_job(ctx, cost_rooms))
    return jobs


def collect(sim_runs, phase2_results, phase2_jobs_):
    """results['issue10']: the graph runs' section metrics (from phase 1, taken
    before results.json trims the reports) and the phase-2 results."""
    out = {"sim": [], "carmen": [], "cost": None}
    for r in sim_runs:
        p = r.get("params", {})
        if p.get("robot") != ROBOT or p.get("variant") or p.get("drift_deg_per_m") not in DRIFTS:
            continue
        if p.get("world_name") not in [w.split("/")[-1] for w in WORLDS]:
            continue
        g = {"params": {"world_name": p["world_name"], "world": p.get("world"), "drift_deg_per_m":
                        p["drift_deg_per_m"], "seed": p["seed"], "variant": "graph"},
             "metrics": {}, "na": dict(r.get("na", {}))}
        g["metrics"].update(_eval_metrics(r.get("eval")))
        for k in ("map_s", "map_peak_rss_mib", "times_real_time", "seconds_per_asr"):
            if finite(r.get("metrics", {}).get(k)):
                g["metrics"][k] = r["metrics"][k]
        gs = graph_summary(r.get("map_report"))
        if gs is not None:
            g["graph"] = gs
        out["sim"].append(g)
    for j in phase2_jobs_:
        res = phase2_results.get(j.name, {})
        res.setdefault("params", j.params)
        res["job"] = j.name
        if j.kind == "issue10_sim":
            out["sim"].append(res)
        elif j.kind == "issue10_carmen":
            out["carmen"].append(res)
        elif j.kind == "issue10_cost":
            out["cost"] = res
    return out


def smoke_problems(issue10):
    """Suite errors in the section's smoke runs (the pose graph's own figures
    may be n/a while it does not build; a crash of the suite may not)."""
    problems = []
    for r in issue10.get("sim", []):
        if r.get("error"):
            problems.append(f"{r.get('job', 'issue10')}: {r['error']}")
        if r["params"].get("variant") in ("nograph", "raw"):
            for k in ("wall_precision_p95_m", "ate_rmse_m", "heading_error_deg_median"):
                if not finite(r.get("metrics", {}).get(k)):
                    why = "; ".join(f"{g}: {v}" for g, v in r.get("na", {}).items())
                    problems.append(f"{r.get('job')}: {k} missing or not finite" + (f" ({why})" if why else ""))
    return problems


# ---- the report section ------------------------------------------------------------

VARIANT_LABEL = {"graph": "pose graph", "nograph": "`--no-graph`", "raw": "odometry (`--no-correct`)"}
TARGET_P95_M = 0.20
TARGET_RECALL = 0.80
TARGET_HEADING_DEG = 0.5
TARGET_ATE_KEEP_M = 0.05
TARGET_COST_RATIO = 1.2
TARGET_CALIBRATION = 0.95


def _vals(runs, key):
    return [r["metrics"][key] for r in runs if finite(r.get("metrics", {}).get(key))]


def _med(runs, key):
    s = summary(_vals(runs, key))
    return s["median"] if s else None


def _calibration(runs):
    """(within, checked) pooled over the runs' placed ASRs."""
    within = checked = 0
    for r in runs:
        m = r.get("metrics", {})
        n, f = m.get("pose_calibration_asrs"), m.get("pose_calibration_3sigma")
        if finite(n) and n > 0 and finite(f):
            checked += int(n)
            within += int(round(f * n))
    return within, checked


def _graph_vals(runs, key):
    return [r["graph"][key] for r in runs if isinstance(r.get("graph"), dict) and finite(r["graph"].get(key))]


def _solutions(runs):
    counts = {}
    for r in runs:
        sol = (r.get("graph") or {}).get("solution")
        if isinstance(sol, str):
            counts[sol] = counts.get(sol, 0) + 1
    return ", ".join(f"{k} {v}" for k, v in sorted(counts.items(), key=lambda kv: -kv[1])) or "n/a"


def _sum_fmt(values, digits=0):
    s = summary(values)
    return fmt_summary(s, digits) if s else "n/a"


def section(rep):
    """'## Pose graph (issue 10)' for docs/BENCHMARKS.md; rep is the Report."""
    data = rep.r.get("issue10")
    out = ["## Pose graph (issue 10)", ""]
    if not data:
        return out + ["Not run (`--skip issue10`, or `--skip sim`).", ""]
    sims = data.get("sim", [])
    have_graph = any(isinstance(r.get("graph"), dict) for r in sims) or any(
        isinstance(v.get("graph"), dict) for c in data.get("carmen", []) for v in c.get("runs", {}).values())
    out += ["Issue 10's figures, each beside `cogmap map --no-graph` (the default before issue 10: the "
            "drift filter's heading correction, rotation only) and the raw odometry (`cogmap map "
            "--no-correct`, or eval's `_raw` keys). **pose graph** is the default `cogmap map`. Every "
            "map is scored by `cogmap eval --json`; the loop closures, rooms and solution come from "
            "report.json's `pose_graph` object. Calibration: the share of the placed ASRs (pooled over "
            "the runs) whose true frame pose, relative to the first ASR, lies within 3 sigma of the "
            "graph's covariance in position and in heading (`pose_calibration_3sigma`).", ""]
    if not have_graph:
        out += ["**This build's `cogmap map` writes no `pose_graph` object** (the pose graph is not in "
                "it), so the pose graph's rows below are the default mode as it is.", ""]
    shortfalls, met = [], []
    out += _sim_table(rep, sims, 1.0, shortfalls, met)
    out += _worse_table(rep, sims, shortfalls, met)
    out += _carmen_table(rep, data.get("carmen", []), shortfalls, met)
    out += _revisits(rep, data.get("carmen", []), shortfalls, met)
    out += _cost(rep, data.get("cost"), data.get("carmen", []), shortfalls, met)
    out += ["### Against issue 10's targets", ""]
    out += [f"- met: {m}" for m in met]
    out += [f"- **not met**: {s}" for s in shortfalls]
    if not met and not shortfalls:
        out.append("- no target could be checked in this run")
    out.append("")
    return out


def _sim_table(rep, sims, drift, shortfalls, met):
    runs = [r for r in sims if r["params"].get("drift_deg_per_m") == drift]
    if not runs:
        return []
    seeds = sorted({r["params"]["seed"] for r in runs})
    out = [f"### Simulated, 16 sonars, {drift:g} °/m, {len(seeds)} seed{'s' if len(seeds) != 1 else ''}", "",
           "Median [min–max] over the seeds. *rooms*: the physical rooms of report.json's `pose_graph` "
           "(ASRs of one room merged by revisits); *loop closures*: accepted closure edges per run; "
           "*solution*: which solution `cogmap map` kept, in how many runs; *calibration*: placed ASRs "
           "within 3σ, pooled, with the median over runs of each run's median placement σ (position "
           "sqrt(σx² + σy²), heading): wide σ make calibration easy, so read the two together.", "",
           "| world | map | wall prec. p95 m | wall recall | ATE m | RPE 5 m, m | RPE 5 m, ° | heading median ° | "
           "ASRs | rooms | loop closures | calibration 3σ | solution |",
           "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
    by_world = {}
    for r in runs:
        by_world.setdefault(r["params"]["world_name"], []).append(r)
    for world, wr in by_world.items():
        for variant in ("graph", "nograph", "raw"):
            g = [r for r in wr if r["params"].get("variant") == variant]
            if not g:
                continue
            is_graph = variant == "graph"
            cal = "—"
            if is_graph:
                w, n = _calibration(g)
                sp, st = _graph_vals(g, "sigma_position_median_m"), _graph_vals(g, "sigma_theta_median_deg")
                sig = (f"; σ {fmt_num(summary(sp)['median'])} m, {fmt_num(summary(st)['median'], 2)}°"
                       if sp and st else "")
                cal = f"{w}/{n} ({100 * w / n:.0f} %{sig})" if n else rep.na(
                    "no placed ASR with a covariance (`pose_calibration_asrs` is 0 or missing: the map has no "
                    "pose graph placements, or eval does not give the key)")
            out.append("| " + " | ".join([
                world, VARIANT_LABEL[variant],
                rep.cell(g, "wall_precision_p95_m"), rep.cell(g, "wall_recall"),
                rep.cell(g, "ate_rmse_m"), rep.cell(g, "rpe_5m_trans_m"), rep.cell(g, "rpe_5m_rot_deg", 2),
                rep.cell(g, "heading_error_deg_median", 2), rep.cell(g, "asr_count", 0),
                _sum_fmt(_graph_vals(g, "rooms")) if is_graph else "—",
                _sum_fmt(_graph_vals(g, "closures_accepted")) if is_graph else "—",
                cal, _solutions(g) if is_graph else "—"]) + " |")
            if is_graph:
                p95, rec = _med(g, "wall_precision_p95_m"), _med(g, "wall_recall")
                if p95 is not None and rec is not None:
                    ok = sum(1 for r in g if r["metrics"].get("wall_precision_p95_m", 9) <= TARGET_P95_M
                             and r["metrics"].get("wall_recall", 0) >= TARGET_RECALL)
                    text = (f"{world} at {drift:g} °/m: wall precision p95 <= {TARGET_P95_M} m and recall >= "
                            f"{TARGET_RECALL} (median {fmt_num(p95)} m / {fmt_num(rec)}; both in {ok} of {len(g)} "
                            "runs)")
                    (met if p95 <= TARGET_P95_M and rec >= TARGET_RECALL else shortfalls).append(text)
                if world == "hallway_loop":
                    closed = sum(1 for v in _graph_vals(g, "closures_accepted") if v > 0)
                    text = f"hallway_loop's loop closes (an accepted loop closure in {closed} of {len(g)} runs)"
                    (met if closed == len(g) else shortfalls).append(text)
    out.append("")
    g_all = [r for r in runs if r["params"].get("variant") == "graph"]
    w, n = _calibration(g_all)
    if n:
        text = (f"calibration: truth within 3 sigma for {w} of {n} placed ASRs ({100 * w / n:.1f} %; target "
                f">= {100 * TARGET_CALIBRATION:.0f} %) at {drift:g} °/m")
        (met if w / n >= TARGET_CALIBRATION else shortfalls).append(text)
    # The drift rate's own sigma, beside the poses': the rate reported
    # against the drift added, by the kept fit's sigma and by its sigma over
    # every fit of the rates (report.json; runs that give one).
    runs = []
    for r in g_all:
        gs = r.get("graph") or {}
        # The odometry's own drift against the truth (cogmap eval), else the one added.
        truth = r.get("metrics", {}).get("odometry_drift_deg_per_m")
        runs.append((gs.get("drift_rate_deg_per_m"), gs.get("drift_rate_sigma_deg_per_m"),
                     gs.get("drift_rate_spread_sigma_deg_per_m"), truth if finite(truth) else drift))
    with_sigma, own, spread = drift_check.count_within_3sigma(runs)
    if with_sigma:
        text = (f"the drift rate within 3 sigma of the odometry's own ({drift:g} °/m added) in {spread} of {with_sigma} runs by its "
                f"sigma over every fit of the rates ({own} by the kept fit's own sigma; target as the poses', "
                f">= {100 * TARGET_CALIBRATION:.0f} %)")
        (met if spread / with_sigma >= TARGET_CALIBRATION else shortfalls).append(text)
    return out


def _worse_table(rep, sims, shortfalls, met):
    out = ["### Never worse than odometry", "",
           "A run is *worse* when its ATE (RMSE after one SE(2) alignment) exceeds the ATE of its own "
           "raw odometry (`ate_rmse_m_raw` of the same map), strictly.", "",
           "| drift °/m | world | runs | ATE m pose graph | ATE m `--no-graph` | ATE m odometry | "
           "pose graph worse | `--no-graph` worse |", "|---:|---|---:|---:|---:|---:|---:|---:|"]
    any_row = False
    for drift in DRIFTS:
        tot = {"graph": [0, 0], "nograph": [0, 0]}
        by_world = {}
        for r in sims:
            if r["params"].get("drift_deg_per_m") == drift:
                by_world.setdefault(r["params"]["world_name"], []).append(r)
        for world, wr in by_world.items():
            cells = {}
            for variant in ("graph", "nograph"):
                g = [r for r in wr if r["params"].get("variant") == variant]
                pairs = [(r["metrics"]["ate_rmse_m"], r["metrics"]["ate_rmse_m_raw"]) for r in g
                         if finite(r["metrics"].get("ate_rmse_m")) and finite(r["metrics"].get("ate_rmse_m_raw"))]
                worse = sum(1 for a, b in pairs if a > b)
                tot[variant][0] += worse
                tot[variant][1] += len(pairs)
                cells[variant] = (g, f"{worse} of {len(pairs)}" if pairs else rep.na(
                    "no run with both `ate_rmse_m` and `ate_rmse_m_raw`"))
            g_all = [r for r in wr if r["params"].get("variant") in ("graph", "nograph")]
            out.append("| " + " | ".join([
                f"{drift:g}", world, str(len(cells["graph"][0])), rep.cell(cells["graph"][0], "ate_rmse_m"),
                rep.cell(cells["nograph"][0], "ate_rmse_m"),
                rep.cell([r for r in wr if r["params"].get("variant") == "graph"] or g_all, "ate_rmse_m_raw"),
                cells["graph"][1], cells["nograph"][1]]) + " |")
            any_row = True
        if drift == 2.0 and tot["graph"][1]:
            text = (f"2 °/m: no run worse than its odometry (pose graph: {tot['graph'][0]} of {tot['graph'][1]} "
                    f"worse; `--no-graph`: {tot['nograph'][0]} of {tot['nograph'][1]})")
            (met if tot["graph"][0] == 0 else shortfalls).append(text)
    out.append("")
    return out if any_row else []


def _carmen_runs(carmen):
    """[(log, sensor, drift, {variant: result})]"""
    rows = []
    for c in carmen:
        p = c["params"]
        if c.get("na", {}).get("all"):
            rows.append((p["log_name"], p["sensor"], None, {"na": c["na"]["all"]}))
            continue
        for d in p.get("drifts", []):
            rows.append((p["log_name"], p["sensor"], d,
                         {v: c["runs"].get(f"{d:g}/{v}") for v in ("graph", "nograph")}))
    return rows


def _carmen_table(rep, carmen, shortfalls, met):
    if not carmen:
        return []
    out = ["### CARMEN logs: laser and `--as-sonar pioneer16`, 0 and 1 °/m added", "",
           "Against the logs' corrected poses. Odometry = eval's `_raw` keys of the pose graph's map (the "
           "log's odometry with the added drift). *kept*: at 0 °/m, the corrected ATE within "
           f"{TARGET_ATE_KEEP_M} m of the input's.", "",
           "| log | sensor | added °/m | ASRs | rooms | closures | heading median ° odometry / `--no-graph` / "
           "graph | ATE m odometry / `--no-graph` / graph | RPE 5 m, m odometry / `--no-graph` / graph | kept "
           "`--no-graph` / graph | uncertain ASRs / warnings | solution |",
           "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
    heading_ok = heading_n = kept_ok = kept_n = 0
    bad_heading = []
    for log, sensor, d, v in _carmen_runs(carmen):
        if d is None:
            out.append(f"| {log} | {sensor} | | " + " | ".join([rep.na(v["na"])] * 9) + " |")
            continue
        g, ng = v.get("graph") or {"na": {"all": "not run"}}, v.get("nograph") or {"na": {"all": "not run"}}

        def val(r, k):
            x = r.get("metrics", {}).get(k)
            return x if finite(x) else None

        def f3(r, k, digits=3):
            x = val(r, k)
            if x is not None:
                return f"{x:.{digits}f}" if abs(x) < 10 else fmt_num(x, digits)
            return rep.na(next(iter(r.get("na", {}).values()), f"no `{k}`"))

        gr = g.get("graph") or {}
        kept = "—"
        if d == 0:
            ks = []
            for r in (ng, g):
                a, b = val(r, "ate_rmse_m"), val(r, "ate_rmse_m_raw")
                ks.append("n/a" if a is None or b is None else ("yes" if a <= b + TARGET_ATE_KEEP_M else
                                                                f"**no** (+{fmt_num(a - b)})"))
            kept = " / ".join(ks)
            a, b = val(g, "ate_rmse_m"), val(g, "ate_rmse_m_raw")
            if a is not None and b is not None:
                kept_n += 1
                kept_ok += a <= b + TARGET_ATE_KEEP_M
        h = val(g, "heading_error_deg_median")
        if h is not None:
            heading_n += 1
            if h <= TARGET_HEADING_DEG:
                heading_ok += 1
            else:
                bad_heading.append(f"{log} {sensor} {d:g} °/m: {fmt_num(h, 2)}")
        out.append("| " + " | ".join([
            log, sensor, f"{d:g}", f3(g, "asr_count", 0),
            str(gr["rooms"]) if "rooms" in gr else "n/a",
            f"{gr.get('closures_accepted', 'n/a')} / {gr.get('closure_candidates', 'n/a')}",
            f"{f3(g, 'heading_error_deg_median_raw', 2)} / {f3(ng, 'heading_error_deg_median', 2)} / "
            f"{f3(g, 'heading_error_deg_median', 2)}",
            f"{f3(g, 'ate_rmse_m_raw')} / {f3(ng, 'ate_rmse_m')} / {f3(g, 'ate_rmse_m')}",
            f"{f3(g, 'rpe_5m_trans_m_raw')} / {f3(ng, 'rpe_5m_trans_m')} / {f3(g, 'rpe_5m_trans_m')}",
            kept, f"{gr.get('uncertain_asrs', 'n/a')} / {gr.get('warnings', 'n/a')}",
            gr.get("solution", "n/a")]) + " |")
    out.append("")
    if heading_n:
        text = (f"CARMEN heading median <= {TARGET_HEADING_DEG}° with the pose graph in {heading_ok} of "
                f"{heading_n} runs (logs x sensors x added drift)")
        if bad_heading:
            text += "; over it: " + ", ".join(bad_heading)
        (met if heading_ok == heading_n else shortfalls).append(text)
    if kept_n:
        text = (f"CARMEN at 0 °/m: the pose graph's ATE within {TARGET_ATE_KEEP_M} m of the input's in {kept_ok} "
                f"of {kept_n} runs")
        (met if kept_ok == kept_n else shortfalls).append(text)
    return out


def _revisits(rep, carmen, shortfalls, met):
    rows = [(log, s, d, v) for log, s, d, v in _carmen_runs(carmen) if log == "intel" and d is not None]
    if not rows:
        return []
    out = ["### Revisits: intel", "",
           "One floor driven round several times: ASRs the map made against the physical rooms the pose graph "
           "keeps (a revisit is an accepted closure into a room mapped before; `--no-graph` keeps one room "
           "per ASR).", "",
           "| sensor | added °/m | ASRs | rooms | revisits | closures accepted / candidates | rooms / ASRs |",
           "|---|---:|---:|---:|---:|---:|---:|"]
    for log, sensor, d, v in rows:
        g = v.get("graph") or {}
        gr = g.get("graph") or {}
        n = g.get("metrics", {}).get("asr_count")
        rooms = gr.get("rooms")
        out.append("| " + " | ".join([
            sensor, f"{d:g}", fmt_num(n, 0) if finite(n) else "n/a", str(rooms) if rooms is not None else "n/a",
            str(gr.get("revisits", "n/a")),
            f"{gr.get('closures_accepted', 'n/a')} / {gr.get('closure_candidates', 'n/a')}",
            f"{rooms / n:.2f}" if finite(n) and n and finite(rooms) else "n/a"]) + " |")
        if d == 0 and finite(n) and finite(rooms):
            text = f"intel's ASR count falls towards its spaces: {int(n)} ASRs -> {rooms} rooms ({sensor}, 0 °/m)"
            (met if rooms < n else shortfalls).append(text)
    out.append("")
    return out


def _cost(rep, cost, carmen, shortfalls, met):
    out = []
    if cost:
        p = cost["params"]
        out += [f"### Cost: a generated {p['rooms']}-room building", "",
                f"`cogmap gen-building --rooms {p['rooms']} --corridor-m {fmt_num(cost.get('corridor_m'), 0)}`, "
                "simulated with the 16-sonar ring (no drift) to the end and, with `simulate --max-time`, to "
                f"the first {100 * p['share']:.0f} % of its duration; each log mapped by the whole `cogmap map` "
                "command (reading, every stage, the store, every output file). Peak memory: the command's "
                "own maximum resident set (GNU time; not wait4 from the bench, whose figure starts at the "
                "bench process's own memory, bench/suite/peak_rss.py).", ""]
        if cost.get("na", {}).get("all"):
            out += [rep.na(cost["na"]["all"]), ""]
        else:
            out += ["*map s*, *s / ASR* and *peak MiB* are the whole command's; *mapping* is report.json's part "
                    "before the output files (`mapping_seconds`, `max_rss_kb_mapping`), since the master map's "
                    "images grow with the building's extent, not with the cost of an ASR.", "",
                    "| run | log s | ASRs | rooms | map s | s / ASR | peak MiB | mapping s / ASR | mapping peak MiB | "
                    "x real time | solution |",
                    "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
            for key, label in (("10/graph", f"first {100 * p['share']:.0f} %, pose graph"),
                               ("100/graph", "100 %, pose graph"), ("100/nograph", "100 %, `--no-graph`")):
                r = cost["runs"].get(key)
                if not r:
                    out.append(f"| {label} | " + " | ".join([rep.na(cost.get("na", {}).get("part", "not run"))] * 10)
                               + " |")
                    continue
                if r.get("na", {}).get("all"):
                    # A failed command still has its time and peak memory.
                    st = r.get("steps", {}).get("map", {})
                    why = rep.na(r["na"]["all"])
                    out.append(f"| {label} | " + " | ".join(
                        [why] * 3 + [f"failed after {fmt_num(st['wall_s'])} s" if st else why, why,
                                     fmt_num(st["peak_rss_mib"]) if st else why] + [why] * 4) + " |")
                    continue
                m, gr = r["metrics"], r.get("graph") or {}
                n = m.get("asr_count", m.get("report_asr_count"))
                out.append("| " + " | ".join([
                    label, fmt_num(m.get("report_log_duration_s")), fmt_num(n, 0) if n else "n/a",
                    str(gr.get("rooms", "—")), fmt_num(m.get("map_s")), fmt_num(m.get("seconds_per_asr")),
                    fmt_num(m.get("map_peak_rss_mib")), fmt_num(m.get("mapping_seconds_per_asr")),
                    fmt_num(m["report_max_rss_kb_mapping"] / 1024) if finite(m.get("report_max_rss_kb_mapping"))
                    else "n/a", fmt_num(m.get("times_real_time")),
                    gr.get("solution", "—")]) + " |")
            a, b = cost["runs"].get("10/graph"), cost["runs"].get("100/graph")
            out.append("")
            for key, r in (("100 %", b), (f"{100 * p['share']:.0f} %", a)):
                if r and r.get("na", {}).get("all"):
                    st = r.get("steps", {}).get("map", {})
                    shortfalls.append(
                        f"cost: the pose graph's `cogmap map` of {key} of the {p['rooms']}-room building failed"
                        + (f" after {fmt_num(st['wall_s'])} s at {fmt_num(st['peak_rss_mib'])} MiB peak" if st else "")
                        + f" ({r['na']['all']}), so time and memory at 100 % against 10 % are not measured")
            if a and b and not a.get("na", {}).get("all") and not b.get("na", {}).get("all"):
                ma, mb = a["metrics"], b["metrics"]
                if finite(ma.get("seconds_per_asr")) and finite(mb.get("seconds_per_asr")):
                    rt = mb["seconds_per_asr"] / ma["seconds_per_asr"]
                    rm = mb["map_peak_rss_mib"] / ma["map_peak_rss_mib"]
                    line = (f"100 % over {100 * p['share']:.0f} %: whole command seconds per ASR x{rt:.2f}, peak "
                            f"memory x{rm:.2f}")
                    text = (f"cost at 100 % against 10 % of a {p['rooms']}-room building within "
                            f"x{TARGET_COST_RATIO}: whole command time per ASR x{rt:.2f}, peak memory x{rm:.2f}")
                    ka, kb = "mapping_seconds_per_asr", "report_max_rss_kb_mapping"
                    if all(finite(x.get(k)) and x.get(k) for x in (ma, mb) for k in (ka, kb)):
                        line += (f"; mapping part x{mb[ka] / ma[ka]:.2f} and x{mb[kb] / ma[kb]:.2f}")
                        text += f" (mapping part x{mb[ka] / ma[ka]:.2f}, x{mb[kb] / ma[kb]:.2f})"
                    out += [line + f" (target: within x{TARGET_COST_RATIO}).", ""]
                    (met if rt <= TARGET_COST_RATIO and rm <= TARGET_COST_RATIO else shortfalls).append(text)
    rows = []
    for log, sensor, d, v in _carmen_runs(carmen):
        if log != "intel" or d != 0:
            continue
        cells = []
        for variant in ("graph", "nograph"):
            r = v.get(variant) or {}
            m = r.get("metrics", {})
            cells.append((fmt_num(m.get("times_real_time")) if finite(m.get("times_real_time")) else "n/a",
                          fmt_num(m.get("map_s")) if finite(m.get("map_s")) else "n/a",
                          fmt_num(m.get("map_peak_rss_mib")) if finite(m.get("map_peak_rss_mib")) else "n/a"))
        rows.append(f"| {sensor} | {cells[0][0]} | {cells[1][0]} | {cells[0][1]} | {cells[1][1]} | "
                    f"{cells[0][2]} | {cells[1][2]} |")
    if rows:
        out += ["Speed on intel (0 °/m added; x real time = the log's duration / the whole command's wall clock):",
                "", "| sensor | x real time pose graph | x real time `--no-graph` | map s pose graph | "
                "map s `--no-graph` | peak MiB pose graph | peak MiB `--no-graph` |",
                "|---|---:|---:|---:|---:|---:|---:|"] + rows + [""]
    return out
