"""The suite's jobs: simulated runs, real logs, micro-benchmarks, peers.

Each job function receives the Job and returns a dict. Metrics that a missing
command or option cannot give are simply absent, and the job records why in
'na' ({metric group: reason}); the report prints n/a with that reason.
"""
import glob
import json
import math
import os
import re
import shutil
import subprocess

from . import runner
from .tool import finite, lookup, parse_json_output, read_json

# The keys `cogmap eval --json` gives for a mapped run (issues 4, 5 and 6).
EVAL_KEYS = [
    "wall_precision_mean_m", "wall_precision_p95_m", "wall_recall", "vertex_count",
    "bytes_grid", "bytes_vertices", "bytes_polylines", "asr_count",
    "room_precision", "room_recall",
    "heading_error_deg_median", "heading_error_deg_max",
    "heading_error_deg_median_raw", "heading_error_deg_max_raw",
] + [
    # The floor plan (issue 11), when the map folder has plan.json.
    "plan_wall_precision_p50_m", "plan_wall_precision_p95_m", "plan_wall_recall", "plan_duplication",
    "room_iou_median", "room_overlap_m2", "plan_vertices_per_m", "plan_walls", "plan_rooms",
]
# Derived by the suite from the map report and the timing of `cogmap map`.
SPEED_KEYS = ["map_s", "log_duration_s", "times_real_time", "seconds_per_asr", "map_peak_rss_mib"]

# Worlds without ground-truth Room cairns cannot give room precision/recall.
ROOM_KEYS = ["room_precision", "room_recall"]


def world_has_rooms(path):
    try:
        with open(path, errors="replace") as f:
            return any(l.startswith("Cairn: Room ") for l in f)
    except OSError:
        return False


def world_has_route(path):
    try:
        with open(path, errors="replace") as f:
            return any(l.startswith("Cairn: GoalWithHeading") for l in f)
    except OSError:
        return False


class Context:
    """What every job needs: the tool, folders and time limits."""

    def __init__(self, cogmap, build_dir, work_dir, docs_dir, shared_dir, step_timeout_s):
        self.cogmap = cogmap
        self.build_dir = build_dir
        self.work_dir = work_dir
        self.docs_dir = docs_dir
        self.shared_dir = shared_dir
        self.step_timeout_s = step_timeout_s

    def run(self, argv, **kw):
        return runner.run_command([str(a) for a in argv], timeout_s=self.step_timeout_s, **kw)


def _step_summary(step):
    return {"wall_s": round(step.wall_s, 4), "cpu_s": round(step.user_s + step.sys_s, 4),
            "peak_rss_mib": round(step.maxrss_kib / 1024.0, 2), "returncode": step.returncode}


def _map_report_speed(report):
    """Total seconds, log duration and per-ASR seconds from a map report.json."""
    out = {}
    if not isinstance(report, dict):
        return out
    total = lookup(report, "total_seconds", "seconds_total", "total_s", "seconds")
    if finite(total):
        out["map_report_s"] = float(total)
    dur = lookup(report, "log_duration_s", "duration_s", "log_seconds")
    if finite(dur):
        out["log_duration_s"] = float(dur)
    per = lookup(report, "seconds_per_asr", "asr_seconds", "per_asr_seconds")
    if isinstance(per, list):
        vals = []
        for v in per:
            if isinstance(v, dict):
                v = lookup(v, "seconds", "total_s", "total_seconds", "s")
            if finite(v):
                vals.append(float(v))
        out["asr_seconds"] = vals
    elif finite(per):
        out["report_seconds_per_asr"] = float(per)
    if "asrs" in report and isinstance(report["asrs"], list) and "asr_seconds" not in out:
        vals = []
        for a in report["asrs"]:
            v = lookup(a, "seconds_total", "total_s", "seconds")
            if isinstance(v, dict):
                v = sum(x for x in v.values() if finite(x))
            if finite(v):
                vals.append(float(v))
        if vals:
            out["asr_seconds"] = vals
    n = lookup(report, "asr_count", "asrs_count")
    if finite(n):
        out["asr_count"] = int(n)
    elif isinstance(report.get("asrs"), list):
        out["asr_count"] = len(report["asrs"])
    for k in ("bytes_grid", "bytes_vertices", "bytes_polylines"):
        v = lookup(report, k)
        if finite(v):
            out[k] = v
    return out


def _speed_metrics(map_step, report_speed, metrics):
    """map_s (our wall clock of `cogmap map`), times real time, s per ASR."""
    m = {}
    m["map_s"] = map_step.wall_s
    m["map_peak_rss_mib"] = map_step.maxrss_kib / 1024.0
    dur = report_speed.get("log_duration_s")
    if finite(dur) and dur > 0:
        m["log_duration_s"] = dur
        m["times_real_time"] = dur / max(map_step.wall_s, 1e-9)
    n = metrics.get("asr_count", report_speed.get("asr_count"))
    if finite(n) and n > 0:
        m["seconds_per_asr"] = map_step.wall_s / n
    return m


def sim_job(ctx, world, robot, drift, seed, map_extra=(), variant=""):
    """simulate -> map -> eval for one world, robot, drift and seed. 'map_extra'
    are more `cogmap map` options (the variant names them in the job)."""

    def run(job):
        p = job.params
        res = {"params": p, "steps": {}, "metrics": {}, "na": {}}
        c = ctx.cogmap
        if not c.has("simulate"):
            res["na"]["all"] = c.missing_reason("simulate")
            return res
        tag = f"{p['world_name']}_{robot}_d{drift:g}_s{seed}"
        log = os.path.join(ctx.work_dir, "sim", tag + (f"_{variant}" if variant else "") + ".log")
        out = os.path.join(ctx.work_dir, "map", tag + (f"_{variant}" if variant else ""))
        os.makedirs(os.path.dirname(log), exist_ok=True)
        argv = [c.binary, "simulate", world, "--robot", robot, "--seed", seed,
                "--drift-deg-per-m", drift, "-o", log]
        if not world_has_route(world):
            if c.has_option("simulate", "--explore"):
                argv.insert(3, "--explore")
            else:
                res["na"]["all"] = "world has no route and `cogmap simulate --explore` is missing"
                return res
        s = ctx.run(argv)
        res["steps"]["simulate"] = _step_summary(s)
        if not s.ok:
            res["na"]["all"] = s.reason()
            return res
        res["log"] = log
        if not c.has("map"):
            res["na"]["map"] = c.missing_reason("map")
            return res
        shutil.rmtree(out, ignore_errors=True)
        argv = [c.binary, "map", log, "-o", out] + list(map_extra)
        for opt in map_extra:
            if str(opt).startswith("--") and not c.has_option("map", opt):
                res["na"]["map"] = f"`cogmap map` has no option {opt}"
                return res
        if c.has_option("map", "--world"):
            argv += ["--world", world]  # room precision / recall in report.json
        s = ctx.run(argv)
        res["steps"]["map"] = _step_summary(s)
        if not s.ok:
            res["na"]["map"] = s.reason()
            return res
        res["map_dir"] = out
        report = read_json(os.path.join(out, "report.json"))
        res["map_report"] = report
        speed = _map_report_speed(report)
        res["asr_seconds"] = speed.get("asr_seconds", [])
        # Metrics that the map's own report gives (eval, below, wins when both do).
        for k in EVAL_KEYS:
            v = lookup(report, k) if isinstance(report, dict) else None
            if finite(v):
                res["metrics"][k] = float(v)
        add_plan(ctx, res, out)
        if not c.has("eval"):
            res["na"]["eval"] = c.missing_reason("eval")
        else:
            s = ctx.run([c.binary, "eval", out, "--world", world, "--json"])
            res["steps"]["eval"] = _step_summary(s)
            if not s.ok:
                res["na"]["eval"] = s.reason()
            else:
                ev = parse_json_output(s.stdout)
                if ev is None:
                    res["na"]["eval"] = "`cogmap eval --json` printed no JSON object"
                else:
                    res["eval"] = ev
                    for k in EVAL_KEYS:
                        v = lookup(ev, k)
                        if finite(v):
                            res["metrics"][k] = float(v)
        for k in ("bytes_grid", "bytes_vertices", "bytes_polylines", "asr_count"):
            if k not in res["metrics"] and finite(speed.get(k)):
                res["metrics"][k] = float(speed[k])
        if not world_has_rooms(world):  # no ground-truth rooms: no room metrics
            for k in ROOM_KEYS:
                res["metrics"].pop(k, None)
        add_heading_errors(ctx, res, out)
        res["metrics"].update(_speed_metrics(_Step(res["steps"]["map"]), speed, res["metrics"]))
        return res

    return runner.Job(name=f"sim/{os.path.basename(world)}/{robot}/{drift:g}/{seed}" +
                      (f"/{variant}" if variant else ""), kind="thesis" if variant else "sim",
                      params={"world": world, "world_name": os.path.splitext(os.path.basename(world))[0],
                              "robot": robot, "drift_deg_per_m": drift, "seed": seed,
                              "variant": variant, "map_extra": [str(a) for a in map_extra]},
                      run=run, cost=3.0 if "hallway" in world or "office" in world else 1.0)


HEADING_KEYS = ["heading_error_deg_median", "heading_error_deg_max",
                "heading_error_deg_median_raw", "heading_error_deg_max_raw"]


def add_plan(ctx, res, out):
    """Until `cogmap map` writes plan.json itself, the suite's helper builds the
    floor plan from OUTDIR/map.sqlite (cogmap::plan::BuildPlan) into
    OUTDIR/plan.json, which `cogmap eval` then scores."""
    if os.path.exists(os.path.join(out, "plan.json")):
        res.setdefault("plan_source", "cogmap map")
        return
    helper = os.path.join(ctx.build_dir, "bench", "cogmap_suite_plan_from_store")
    if not os.access(helper, os.X_OK):
        res["na"]["plan"] = "no plan.json in the map folder and no `cogmap_suite_plan_from_store` built"
        return
    s = ctx.run([helper, out])
    res["steps"]["plan"] = _step_summary(s)
    if not s.ok:
        res["na"]["plan"] = s.reason()
    else:
        res["plan_source"] = "cogmap_suite_plan_from_store"


def add_heading_errors(ctx, res, out):
    """When neither eval nor the map's report gave heading errors, the suite's
    helper computes them from OUTDIR/map.sqlite with the library's own metric
    (cogmap::localize::ComputeHeadingErrors). Marks where they came from."""
    if all(k in res["metrics"] for k in HEADING_KEYS):
        res.setdefault("heading_source", "cogmap eval / report.json")
        return
    helper = os.path.join(ctx.build_dir, "bench", "cogmap_suite_heading_eval")
    if not os.access(helper, os.X_OK):
        return
    s = ctx.run([helper, out])
    res["steps"]["heading_eval"] = _step_summary(s)
    if not s.ok:
        res["na"]["heading"] = s.reason()
        return
    d = parse_json_output(s.stdout) or {}
    got = False
    for k in HEADING_KEYS:
        if finite(d.get(k)) and k not in res["metrics"]:
            res["metrics"][k] = float(d[k])
            got = True
    if got:
        res["heading_source"] = "cogmap_suite_heading_eval"
    elif not d.get("asrs_with_truth"):
        res["na"]["heading"] = "no ASR of the map has a true path (the log has no ground truth)"


class _Step:
    """The summary of a step, looked at like a StepResult (wall_s, maxrss)."""

    def __init__(self, summary):
        self.wall_s = summary["wall_s"]
        self.maxrss_kib = summary["peak_rss_mib"] * 1024.0


# ---- real logs ---------------------------------------------------------------

def real_logs(shared):
    d = os.path.join(shared, "data")
    logs = [
        ("pioneer-sonar", os.path.join(d, "pioneer-sonar-robond"), None),
        ("ev3-69", os.path.join(d, "ev3-sonar", "ev3-69.log"), None),
        ("ev3-154", os.path.join(d, "ev3-sonar", "ev3-154.log"), None),
        ("carmen-intel", os.path.join(d, "carmen", "intel-corrected.log.gz"), None),
        ("carmen-aces", os.path.join(d, "carmen", "aces-corrected.log.gz"), None),
    ]
    return [(n, p, r) for n, p, r in logs if os.path.exists(p)]


DRIFT_OPTIONS = ("--add-drift-deg-per-m", "--add-heading-drift-deg-per-m", "--drift-deg-per-m",
                 "--add-heading-drift", "--add-drift")


def drift_option(cogmap):
    """(command, option) that adds heading drift to a real log's odometry:
    `cogmap map` itself, or `cogmap convert` before mapping; None if neither."""
    for cmd in ("map", "convert"):
        if cogmap.has(cmd):
            for opt in DRIFT_OPTIONS:
                if cogmap.has_option(cmd, opt):
                    return cmd, opt
    return None


def real_job(ctx, name, path, drift):
    def run(job):
        res = {"params": job.params, "steps": {}, "metrics": {}, "na": {}}
        c = ctx.cogmap
        if not c.has("map"):
            res["na"]["all"] = c.missing_reason("map")
            return res
        out = os.path.join(ctx.work_dir, "real", f"{name}_d{drift:g}")
        shutil.rmtree(out, ignore_errors=True)
        argv = [c.binary, "map", path, "-o", out]
        if drift:
            how = drift_option(c)
            if not how:
                res["na"]["all"] = ("neither `cogmap map` nor `cogmap convert` has an option to add "
                                    "heading drift to a log")
                return res
            cmd, opt = how
            if cmd == "map":
                argv += [opt, drift]
            else:
                drifted = os.path.join(ctx.work_dir, "real", f"{name}_d{drift:g}.log")
                s = ctx.run([c.binary, "convert", path, opt, drift, "-o", drifted])
                res["steps"]["convert"] = _step_summary(s)
                if not s.ok:
                    res["na"]["all"] = s.reason()
                    return res
                argv[2] = drifted
        s = ctx.run(argv)
        res["steps"]["map"] = _step_summary(s)
        if not s.ok:
            res["na"]["all"] = s.reason()
            return res
        res["map_dir"] = out
        report = read_json(os.path.join(out, "report.json"))
        res["map_report"] = report
        speed = _map_report_speed(report)
        res["asr_seconds"] = speed.get("asr_seconds", [])
        for k in ("bytes_grid", "bytes_vertices", "bytes_polylines", "asr_count"):
            if finite(speed.get(k)):
                res["metrics"][k] = float(speed[k])
        for k in ("heading_error_deg_median", "heading_error_deg_max",
                  "heading_error_deg_median_raw", "heading_error_deg_max_raw"):
            v = lookup(report, k) if isinstance(report, dict) else None
            if finite(v):
                res["metrics"][k] = float(v)
        # Heading error against the log's own reference poses, when eval gives it
        # without a world (CARMEN corrected logs: the poses are the reference).
        eval_help = c.help("eval") or ""
        if c.has("eval") and re.search(r"--world[^\n]*REQUIRED", eval_help):
            res["na"]["eval"] = "`cogmap eval` needs a world, and a real log has no true walls"
        elif c.has("eval"):
            s2 = ctx.run([c.binary, "eval", out, "--json"])
            res["steps"]["eval"] = _step_summary(s2)
            ev = parse_json_output(s2.stdout) if s2.ok else None
            if ev is not None:
                res["eval"] = ev
                for k in ("heading_error_deg_median", "heading_error_deg_max",
                          "heading_error_deg_median_raw", "heading_error_deg_max_raw"):
                    v = lookup(ev, k)
                    if finite(v):
                        res["metrics"][k] = float(v)
            elif not s2.ok:
                res["na"]["eval"] = s2.reason()
        add_heading_errors(ctx, res, out)
        res["metrics"].update(_speed_metrics(_Step(res["steps"]["map"]), speed, res["metrics"]))
        return res

    return runner.Job(name=f"real/{name}/{drift:g}", kind="real",
                      params={"log_name": name, "log": path, "drift_deg_per_m": drift}, run=run,
                      cost=4.0 if "carmen" in name else 1.0)


# ---- micro-benchmarks ----------------------------------------------------------

def is_google_benchmark(binary):
    try:
        p = subprocess.run([binary, "--help"], capture_output=True, text=True, timeout=60)
        return "--benchmark_filter" in (p.stdout + p.stderr)
    except (OSError, subprocess.TimeoutExpired):
        return False


def micro_benchmarks(build_dir):
    """The Google Benchmark programs among build/bench/*_bench (others, such as
    cogmap_map_bench which takes a log, are run where they belong)."""
    found = sorted(set(glob.glob(os.path.join(build_dir, "bench", "cogmap_*_bench")) +
                       glob.glob(os.path.join(build_dir, "bench", "*_bench"))))
    return [b for b in found if os.access(b, os.X_OK) and os.path.isfile(b) and is_google_benchmark(b)]


def micro_job(ctx, binary, min_time_s):
    def run(job):
        res = {"params": job.params, "na": {}}
        s = ctx.run([binary, "--benchmark_format=json", f"--benchmark_min_time={min_time_s}"],
                    cwd=os.path.dirname(binary))
        res["steps"] = {"run": _step_summary(s)}
        if not s.ok:
            res["na"]["all"] = s.reason()
            return res
        data = parse_json_output(s.stdout)
        if not data:
            res["na"]["all"] = "no JSON from --benchmark_format=json"
            return res
        rows = []
        for b in data.get("benchmarks", []):
            if b.get("run_type") == "aggregate":
                continue
            row = {k: b[k] for k in ("name", "real_time", "cpu_time", "time_unit", "iterations")
                   if k in b}
            for k, v in b.items():
                if k not in row and finite(v) and k not in (
                        "family_index", "per_family_instance_index", "repetitions",
                        "repetition_index", "threads"):
                    row[k] = v
            rows.append(row)
        res["benchmarks"] = rows
        res["context"] = {k: data.get("context", {}).get(k) for k in ("library_build_type", "num_cpus")}
        return res

    return runner.Job(name=f"micro/{os.path.basename(binary)}", kind="micro",
                      params={"binary": os.path.basename(binary)}, run=run, cost=2.0)


# ---- peers -----------------------------------------------------------------------

def mrpt_binary(build_dir):
    b = os.path.join(build_dir, "bench", "cogmap_mrpt_grid_compare")
    return b if os.access(b, os.X_OK) else None


def mrpt_job(ctx, name, log_path, robot=None, extra=()):
    """Four runs of the comparison program on one log: baseline (reading the
    log only), MRPT alone, cogmap alone (peak memory of each), then both (the
    picture and the sizes)."""

    def run(job):
        res = {"params": job.params, "na": {}, "runs": {}}
        b = mrpt_binary(ctx.build_dir)
        if not b:
            res["na"]["all"] = "cogmap_mrpt_grid_compare not built (MRPT not found by CMake)"
            return res
        lp = log_path() if callable(log_path) else log_path
        if not lp or not os.path.exists(lp):
            res["na"]["all"] = f"log for {name} not available (its simulation failed)"
            return res
        base = [b, lp] + (["--robot", robot] if robot else []) + list(extra)
        png = os.path.join(ctx.docs_dir, f"peer_mrpt_{name}.png")
        for engine in ("none", "mrpt", "cogmap", "both"):
            argv = base + ["--engine", engine]
            if engine == "both":
                argv += ["--png", png, "--title", name.upper().replace("_", " ")]
            s = ctx.run(argv)
            if not s.ok:
                res["na"]["all"] = s.reason()
                return res
            data = parse_json_output(s.stdout) or {}
            data["process_peak_rss_kib"] = s.maxrss_kib
            data["process_wall_s"] = s.wall_s
            res["runs"][engine] = data
        res["png"] = os.path.relpath(png, ctx.docs_dir)
        return res

    return runner.Job(name=f"peer/mrpt/{name}", kind="peer_mrpt", params={"name": name}, run=run,
                      cost=5.0)


def opencv_peer_binary(build_dir):
    b = os.path.join(build_dir, "bench", "cogmap_peer_opencv_vectorize")
    return b if os.access(b, os.X_OK) else None


def opencv_job(ctx, name, log_path, world, mode):
    """OpenCV findContours + approxPolyDP against cogmap's vectorization on the
    same cleaned grid of one log (bench/peer_opencv_vectorize.cc)."""

    def run(job):
        res = {"params": job.params, "na": {}}
        b = opencv_peer_binary(ctx.build_dir)
        if not b:
            res["na"]["all"] = "cogmap_peer_opencv_vectorize not built (OpenCV not found by CMake)"
            return res
        lp = log_path() if callable(log_path) else log_path
        if not lp or not os.path.exists(lp):
            res["na"]["all"] = f"log for {name} not available (its simulation failed)"
            return res
        s = ctx.run([b, lp, "--world", world, "--mode", mode])
        res["steps"] = {"run": _step_summary(s)}
        if not s.ok:
            res["na"]["all"] = s.reason()
            return res
        res["result"] = parse_json_output(s.stdout)
        if not res["result"]:
            res["na"]["all"] = "no JSON from cogmap_peer_opencv_vectorize"
        return res

    return runner.Job(name=f"peer/opencv/{name}/{mode}", kind="peer_opencv",
                      params={"name": name, "mode": mode}, run=run, cost=2.0)


def text_job(ctx, binary):
    """A comparison program that prints its own table (no JSON): its output is
    kept as it is, for the report to quote."""

    def run(job):
        res = {"params": job.params, "na": {}}
        s = ctx.run([binary], cwd=os.path.dirname(binary))
        res["steps"] = {"run": _step_summary(s)}
        if not s.ok:
            res["na"]["all"] = s.reason()
        res["stdout"] = s.stdout[-8000:]
        return res

    return runner.Job(name=f"text/{os.path.basename(binary)}", kind="peer_text",
                      params={"binary": os.path.basename(binary)}, run=run, cost=2.0)


def opencv_binaries(build_dir):
    """The vectorization issue's OpenCV comparison program, when built."""
    found = []
    for pattern in ("*opencv*", "*approx*"):
        found += glob.glob(os.path.join(build_dir, "bench", pattern))
    return sorted({f for f in found if os.path.isfile(f) and os.access(f, os.X_OK)
                   and not f.endswith("cogmap_peer_opencv_vectorize")})


def scale_job(ctx, rooms, seed=1):
    """`cogmap gen-building` (issue 5's 1 km world) -> simulate -> map -> eval:
    the run behind the time-per-ASR figure."""

    def run(job):
        res = {"params": job.params, "steps": {}, "metrics": {}, "na": {}}
        c = ctx.cogmap
        for cmd in ("gen-building", "simulate", "map"):
            if not c.has(cmd):
                res["na"]["all"] = c.missing_reason(cmd)
                return res
        world = os.path.join(ctx.work_dir, "scale", f"building_{rooms}.map")
        os.makedirs(os.path.dirname(world), exist_ok=True)
        argv = [c.binary, "gen-building", "-o", world]
        if c.has_option("gen-building", "--rooms"):
            argv += ["--rooms", rooms]
        if c.has_option("gen-building", "--seed"):
            argv += ["--seed", seed]
        s = ctx.run(argv)
        res["steps"]["gen-building"] = _step_summary(s)
        if not s.ok:
            res["na"]["all"] = s.reason()
            return res
        log = os.path.join(ctx.work_dir, "scale", f"building_{rooms}.log")
        s = ctx.run([c.binary, "simulate", world, "--robot", "pioneer16", "--seed", seed,
                     "--drift-deg-per-m", 0, "-o", log])
        res["steps"]["simulate"] = _step_summary(s)
        if not s.ok:
            res["na"]["all"] = s.reason()
            return res
        mb = os.path.join(ctx.build_dir, "bench", "cogmap_map_bench")
        if os.access(mb, os.X_OK):
            store = os.path.join(ctx.work_dir, "scale", f"building_{rooms}_bench.sqlite")
            for f in glob.glob(store + "*"):
                os.remove(f)
            s = ctx.run([mb, log, store])
            res["steps"]["map_bench"] = _step_summary(s)
            res["map_bench"] = parse_json_output(s.stdout) if s.ok else None
            if not s.ok:
                res["na"]["map_bench"] = s.reason()
        else:
            res["na"]["map_bench"] = "cogmap_map_bench not built"
        out = os.path.join(ctx.work_dir, "scale", f"building_{rooms}_map")
        shutil.rmtree(out, ignore_errors=True)
        argv = [c.binary, "map", log, "-o", out]
        if c.has_option("map", "--world"):
            argv += ["--world", world]
        s = ctx.run(argv)
        res["steps"]["map"] = _step_summary(s)
        if not s.ok:
            res["na"]["all"] = s.reason()
            return res
        report = read_json(os.path.join(out, "report.json"))
        res["map_report"] = report
        for k in EVAL_KEYS:
            v = lookup(report, k) if isinstance(report, dict) else None
            if finite(v):
                res["metrics"][k] = float(v)
        speed = _map_report_speed(report)
        res["asr_seconds"] = speed.get("asr_seconds", [])
        for k in ("bytes_grid", "bytes_vertices", "bytes_polylines", "asr_count"):
            if finite(speed.get(k)):
                res["metrics"][k] = float(speed[k])
        if c.has("eval"):
            s = ctx.run([c.binary, "eval", out, "--world", world, "--json"])
            res["steps"]["eval"] = _step_summary(s)
            ev = parse_json_output(s.stdout) if s.ok else None
            if ev:
                res["eval"] = ev
                for k in EVAL_KEYS:
                    v = lookup(ev, k)
                    if finite(v):
                        res["metrics"][k] = float(v)
        add_heading_errors(ctx, res, out)
        res["metrics"].update(_speed_metrics(_Step(res["steps"]["map"]), speed, res["metrics"]))
        return res

    return runner.Job(name=f"scale/building_{rooms}", kind="scale",
                      params={"log_name": f"building_{rooms}", "rooms": rooms, "seed": seed,
                              "drift_deg_per_m": 0.0}, run=run, cost=20.0)
