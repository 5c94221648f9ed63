"""bench/run_all: the benchmark suite (docs/BENCHMARKS.md). See --help."""
import argparse
import datetime
import json
import math
import os
import shutil
import subprocess
import sys
import time

from . import cases, issue10, machine, plots, report, runner
from .tool import Cogmap, finite

SOURCE_DIR = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
WORLDS = ["nine_rooms", "hallway_loop", "cluttered_lab", "aria/office"]
ROBOTS = ["pioneer16", "pioneer8", "laser"]
DRIFTS = [0.0, 0.5, 1.0, 2.0]
SEEDS = [1, 2, 3, 4, 5]


def parse_args(argv, smoke_default=False):
    ap = argparse.ArgumentParser(
        prog="bench/smoke" if smoke_default else "bench/run_all",
        description="Runs cogmap's benchmark suite and writes docs/BENCHMARKS.md, "
                    "docs/benchmarks/results.json and docs/bench_*.png.")
    ap.add_argument("--build-dir", default=os.path.join(SOURCE_DIR, "build"),
                    help="CMake build folder (default: build/ of the checkout)")
    ap.add_argument("--no-build", action="store_true",
                    help="use the build as it is (default: configure if needed and build)")
    ap.add_argument("--shared", default=os.path.join(os.path.dirname(SOURCE_DIR), "shared"),
                    help="the shared folder with worlds/ and data/ (default: ../shared)")
    ap.add_argument("--docs", default=os.path.join(SOURCE_DIR, "docs"),
                    help="where BENCHMARKS.md, benchmarks/results.json and the figures go")
    ap.add_argument("--work", help="scratch folder for logs and maps (default: BUILD/bench-work)")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 2, help="parallel jobs")
    ap.add_argument("--worlds", default=",".join(WORLDS), help="comma list (names under worlds/)")
    ap.add_argument("--robots", default=",".join(ROBOTS))
    ap.add_argument("--drifts", default=",".join(f"{d:g}" for d in DRIFTS), help="deg per metre")
    ap.add_argument("--seeds", default=",".join(str(s) for s in SEEDS),
                    help="comma list, or a count N for seeds 1..N")
    ap.add_argument("--skip", default="",
                    help="comma list of: sim, real, thesis, scale, micro, peers, issue10 (the pose graph's "
                         "section), issue10-carmen, issue10-cost (its two big pieces)")
    ap.add_argument("--scale-rooms", type=int, default=100,
                    help="rooms of the generated building of the scale run (0: none)")
    ap.add_argument("--cost-rooms", type=int, default=issue10.COST_ROOMS,
                    help="rooms of the generated building of the pose graph's cost run (0: none)")
    ap.add_argument("--step-timeout", type=float, default=600.0, help="seconds per command")
    ap.add_argument("--micro-min-time", type=float, default=0.1,
                    help="--benchmark_min_time of the micro-benchmarks (s)")
    ap.add_argument("--smoke", action="store_true", default=smoke_default,
                    help="one world, one robot, one seed, one drift into a scratch folder; "
                         "exit 1 unless every metric is present and finite")
    ap.add_argument("--quiet", action="store_true")
    return ap.parse_args(argv)


def log(msg, quiet=False):
    if not quiet:
        print(msg, flush=True)


def build(args):
    bd = args.build_dir
    if not os.path.exists(os.path.join(bd, "CMakeCache.txt")):
        log(f"configuring {bd} (Release)", args.quiet)
        subprocess.run(["cmake", "-S", SOURCE_DIR, "-B", bd, "-G", "Ninja",
                        "-DCMAKE_BUILD_TYPE=Release"], check=True, stdout=subprocess.DEVNULL)
    targets = ["cogmap"]
    try:
        help_out = subprocess.run(["cmake", "--build", bd, "--target", "help"], capture_output=True,
                                  text=True, check=True).stdout
        for line in help_out.splitlines():
            name = line.split(":")[0].strip().lstrip(".").strip()
            if name.startswith("cogmap_") and (name.endswith("_bench") or "compare" in name or "peer" in name
                                            or "suite" in name):
                targets.append(name)
    except subprocess.CalledProcessError:
        pass
    log(f"building {' '.join(targets)}", args.quiet)
    failed = []
    p = subprocess.run(["cmake", "--build", bd, "-j", str(args.jobs), "--target", *targets],
                       capture_output=True, text=True)
    if p.returncode != 0:
        # Build what builds, one target at a time, and report the rest as n/a.
        for t in targets:
            q = subprocess.run(["cmake", "--build", bd, "-j", str(args.jobs), "--target", t],
                               capture_output=True, text=True)
            if q.returncode != 0:
                failed.append(t)
    return failed


def build_type(build_dir):
    try:
        with open(os.path.join(build_dir, "CMakeCache.txt")) as f:
            for line in f:
                if line.startswith("CMAKE_BUILD_TYPE:"):
                    return line.split("=", 1)[1].strip() or "default"
    except OSError:
        pass
    return "unknown"


def world_path(shared, name):
    p = os.path.join(shared, "worlds", name if name.endswith(".map") else name + ".map")
    return p


def parse_list(text, conv):
    return [conv(x) for x in text.split(",") if x.strip()]


def main(argv=None, smoke_default=False):
    args = parse_args(argv if argv is not None else sys.argv[1:], smoke_default)
    t_start = time.monotonic()
    started = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M")
    args.build_dir = os.path.abspath(args.build_dir)
    if args.smoke:
        args.worlds, args.robots, args.drifts, args.seeds = "nine_rooms", "pioneer16", "1", "1"
        args.skip = "real,micro"
        args.no_build = args.no_build or smoke_default
    work = os.path.abspath(args.work or os.path.join(args.build_dir, "bench-smoke" if args.smoke else "bench-work"))
    docs = os.path.join(work, "docs") if args.smoke else os.path.abspath(args.docs)
    os.makedirs(work, exist_ok=True)
    os.makedirs(os.path.join(docs, "benchmarks"), exist_ok=True)
    skip = set(parse_list(args.skip, str))
    failed_targets = [] if args.no_build else build(args)

    tool = Cogmap(os.path.join(args.build_dir, "app", "cogmap"))
    if not tool.exists():
        alt = os.path.join(args.build_dir, "cogmap")
        if os.path.exists(alt):
            tool = Cogmap(alt)
    commands = {}
    for c in ("simulate", "map", "eval", "vectorize", "grid", "gen-building"):
        commands[c] = True if tool.has(c) else tool.missing_reason(c)
    ctx = cases.Context(tool, args.build_dir, work, docs, args.shared, args.step_timeout)

    seeds = list(range(1, int(args.seeds) + 1)) if args.seeds.isdigit() and "," not in args.seeds \
        and not args.smoke else parse_list(args.seeds, int)
    if args.smoke:
        seeds = [1]
    worlds = parse_list(args.worlds, str)
    robots = parse_list(args.robots, str)
    drifts = parse_list(args.drifts, float)
    config = {"worlds": worlds, "robots": robots, "drifts": drifts, "seeds": seeds, "jobs": args.jobs,
              "build_type": build_type(args.build_dir), "smoke": args.smoke,
              "failed_targets": failed_targets}

    def progress(i, n, job, res):
        na = res.get("na", {})
        status = "ok" if not na else "n/a: " + "; ".join(f"{k}: {v}" for k, v in na.items())
        log(f"[{i}/{n}] {job.name} {res.get('job_wall_s', 0):.1f}s {status[:200]}", args.quiet)

    results = {"machine": machine.describe(SOURCE_DIR), "config": config, "commands": commands,
               "started_utc": started}
    results["machine"]["load_average_at_start"] = round(os.getloadavg()[0], 2)

    # Phase 1: simulated runs and real logs.
    jobs = []
    if "sim" not in skip:
        for w in worlds:
            wp = world_path(args.shared, w)
            for r in robots:
                for d in drifts:
                    for s in seeds:
                        jobs.append(cases.sim_job(ctx, wp, r, d, s))
    if "real" not in skip:
        for name, path, _ in cases.real_logs(args.shared):
            jobs.append(cases.real_job(ctx, name, path, 0.0))
            if name.startswith("carmen"):
                jobs.append(cases.real_job(ctx, name, path, 1.0))
    if "thesis" not in skip and not args.smoke:
        # The thesis's hallway experiment (§4.2, fig. 4.13): fixed-length ASRs of 4 m.
        for s in seeds[:3]:
            jobs.append(cases.sim_job(ctx, world_path(args.shared, "hallway_loop"), "pioneer16", 0.0, s,
                                      map_extra=("--boundary", "fixed", "--asr-length", "4"),
                                      variant="fixed4m"))
    if "scale" not in skip and not args.smoke and args.scale_rooms > 0:
        jobs.append(cases.scale_job(ctx, args.scale_rooms))
    with_issue10 = "issue10" not in skip and "sim" not in skip
    if with_issue10:
        # The pose graph's runs at 1 and 2 deg/m that the grid does not make.
        jobs += issue10.phase1_jobs(ctx, lambda w: world_path(args.shared, w), {j.name for j in jobs}, seeds,
                                    worlds, args.smoke)
    log(f"phase 1: {len(jobs)} jobs on {args.jobs} workers", args.quiet)
    res1 = runner.run_jobs(jobs, args.jobs, progress)
    sims, reals, graph10 = [], [], []
    for j in jobs:
        r = res1[j.name]
        r["job"] = j.name
        r.setdefault("params", j.params)
        if j.kind == "sim":
            r["params"]["has_rooms"] = cases.world_has_rooms(j.params["world"])
            sims.append(r)
        elif j.kind == "scale":
            results["scale"] = r
        elif j.kind == "thesis":
            results.setdefault("thesis", []).append(r)
        elif j.kind == "issue10_graph":
            graph10.append(r)
        else:
            reals.append(r)
    results["sim"], results["real"] = sims, reals
    if "real" in skip:
        results["real_skipped"] = True

    # Phase 1b: the pose graph's section (issue 10): the same logs without the
    # graph and without correction, the CARMEN logs, the cost run.
    if with_issue10:
        jobs10 = issue10.phase2_jobs(ctx, lambda w: world_path(args.shared, w), seeds, worlds, args.smoke, skip,
                                     args.cost_rooms)
        log(f"phase 1b: {len(jobs10)} pose-graph jobs", args.quiet)
        res10 = runner.run_jobs(jobs10, args.jobs, progress)
        results["issue10"] = issue10.collect(sims + graph10, res10, jobs10)
        for r in graph10:  # results.json keeps only their scalars
            r.pop("map_report", None)
            r.pop("eval", None)

    # Phase 2: peers, on logs of phase 1.
    peers = {"mrpt": [], "opencv": [], "sources": {}}
    if "peers" not in skip:
        pjobs = []

        def sim_log(world, robot):
            for r in sims:
                p = r["params"]
                if p["world_name"] == world and p["robot"] == robot and r.get("log"):
                    if p["drift_deg_per_m"] == min(drifts):
                        return r["log"], r["job"]
            return None, None

        wanted = [("nine_rooms", "pioneer16"), ("nine_rooms", "laser")]
        if args.smoke:
            wanted = [(worlds[0].split("/")[-1], robots[0])]
        for world, robot in wanted:
            lp, job = sim_log(world, robot)
            name = f"{world}_{robot}"
            peers["sources"][name] = ("sim", job)
            wp = world_path(args.shared, next(w for w in worlds if w.split("/")[-1] == world))
            pjobs.append(cases.mrpt_job(ctx, name, lp, extra=("--poses", "truth", "--world", wp)))
        cv_wanted = [("nine_rooms", "pioneer16", "default"), ("nine_rooms", "pioneer16", "paper"),
                     ("nine_rooms", "laser", "default"), ("cluttered_lab", "pioneer16", "default"),
                     ("hallway_loop", "pioneer16", "default"), ("office", "pioneer16", "default")]
        if args.smoke:
            cv_wanted = [(worlds[0].split("/")[-1], robots[0], "default")]
        for world, robot, mode in cv_wanted:
            full = next((w for w in worlds if w.split("/")[-1] == world), None)
            if full is None or robot not in robots:
                continue
            lp, _ = sim_log(world, robot)
            pjobs.append(cases.opencv_job(ctx, f"{world}_{robot}", lp, world_path(args.shared, full), mode))
        if not args.smoke:
            for name, path, _ in cases.real_logs(args.shared):
                if name in ("pioneer-sonar", "carmen-intel"):
                    peers["sources"][name] = ("real", f"real/{name}/0")
                    pjobs.append(cases.mrpt_job(ctx, name, path))
            for b in cases.opencv_binaries(args.build_dir):
                if cases.is_google_benchmark(b):
                    pjobs.append(cases.micro_job(ctx, b, args.micro_min_time))
                else:
                    pjobs.append(cases.text_job(ctx, b))
        log(f"phase 2: {len(pjobs)} peer jobs", args.quiet)
        res2 = runner.run_jobs(pjobs, args.jobs, progress)
        for j in pjobs:
            r = res2[j.name]
            r["job"] = j.name
            r.setdefault("params", j.params)
            if j.kind == "peer_mrpt":
                peers["mrpt"].append(r)
            elif j.kind == "peer_opencv":
                peers.setdefault("opencv_vectorize", []).append(r)
            else:
                peers["opencv"].append(r)
    results["peers"] = peers
    rep = report.Report(results)
    for p in peers["mrpt"]:
        p["polyline_bytes"] = rep._polyline_bytes_for(p["params"]["name"])[0]

    # Phase 3: micro-benchmarks, one at a time so that they have a core each.
    micro = []
    if "micro" not in skip:
        mjobs = [cases.micro_job(ctx, b, args.micro_min_time) for b in cases.micro_benchmarks(args.build_dir)]
        log(f"phase 3: {len(mjobs)} micro-benchmarks", args.quiet)
        res3 = runner.run_jobs(mjobs, 1, progress)
        micro = [dict(res3[j.name], job=j.name) for j in mjobs]
    results["micro"] = micro

    figs, notes = plots.make_all(results, docs)
    results["figures"] = figs
    results["figure_notes"] = notes
    results["suite_wall_s"] = time.monotonic() - t_start
    results["machine"]["load_average_at_end"] = round(os.getloadavg()[0], 2)

    # Keep results.json small: the per-ASR lists of each map's report are in
    # its map folder; the suite keeps only the per-ASR seconds (asr_seconds).
    runs = results["sim"] + results["real"] + results.get("thesis", []) + (
        [results["scale"]] if results.get("scale") else [])
    for r in runs:
        rep_ = r.get("map_report")
        if isinstance(rep_, dict):
            r["map_report"] = {k: v for k, v in rep_.items() if not isinstance(v, (list, dict))}
    with open(os.path.join(docs, "benchmarks", "results.json"), "w") as f:
        json.dump(results, f, indent=1, default=str)
    md_path = os.path.join(docs, "BENCHMARKS.md")
    md = keep_hand_sections(report.Report(results).markdown(), md_path)
    with open(md_path, "w") as f:
        f.write(md)
    log(f"wrote {md_path} and {os.path.join(docs, 'benchmarks', 'results.json')} "
        f"in {results['suite_wall_s'] / 60:.1f} min", args.quiet)

    if args.smoke:
        return smoke_check(results)
    return 0


def _sections(md):
    """[(heading or None for the text before the first '## '), text], in order."""
    out, title, lines = [], None, []
    for line in md.splitlines(keepends=True):
        if line.startswith("## "):
            out.append((title, "".join(lines)))
            title, lines = line[3:].strip(), []
        lines.append(line)
    out.append((title, "".join(lines)))
    return out


def keep_hand_sections(md, old_path):
    """The generated markdown, plus every '## ' section of the existing file
    that the suite does not write (measured by hand: reading speeds, memory,
    ...), in their old order, before '## Figures'."""
    try:
        with open(old_path) as f:
            old = _sections(f.read())
    except OSError:
        return md
    new = _sections(md)
    generated = {t for t, _ in new if t}
    kept = [text.rstrip("\n") + "\n\n" for t, text in old if t and t not in generated]
    if not kept:
        return md
    out, placed = [], False
    for t, text in new:
        if t == "Figures" and not placed:
            out += kept
            placed = True
        out.append(text)
    if not placed:
        out += kept
    return "".join(out)


def smoke_check(results):
    """Every metric of the smoke run present and finite, or exit 1 naming them."""
    problems = []
    keys = cases.EVAL_KEYS + cases.SPEED_KEYS
    if not results["sim"]:
        problems.append("no simulated run")
    if "issue10" in results:
        problems += issue10.smoke_problems(results["issue10"])
    for r in results["sim"]:
        for k in keys:
            if not finite(r.get("metrics", {}).get(k)):
                why = "; ".join(f"{g}: {v}" for g, v in r.get("na", {}).items())
                problems.append(f"{r['job']}: {k} missing or not finite" + (f" ({why})" if why else ""))
        if not r.get("asr_seconds"):
            problems.append(f"{r['job']}: no per-ASR seconds in the map's report.json")
    notes = []
    for p in results["peers"]["mrpt"]:
        if p.get("na", {}).get("all"):
            # The peers are optional packages (install-deps.sh --peers): a
            # program not built for want of its library is noted, not failed.
            (notes if "not built" in p["na"]["all"] else problems).append(f"{p['job']}: {p['na']['all']}")
            continue
        for engine, side in (("mrpt", "mrpt"), ("cogmap", "cogmap")):
            d = p["runs"][engine].get(side, {})
            for k in ("insert_s", "readings_per_s", "known_area_m2", "grid_bytes_in_memory"):
                if not finite(d.get(k)):
                    problems.append(f"{p['job']}: {side}.{k} missing or not finite")
        sizes = p["runs"]["both"].get("sizes", {})
        for k in ("grid_png_bytes", "grid_pgm_bytes", "mrpt_gridmap_gz_bytes"):
            if not finite(sizes.get(k)):
                problems.append(f"{p['job']}: sizes.{k} missing or not finite")
        if not finite(p.get("polyline_bytes")):
            problems.append(f"{p['job']}: no cogmap polyline bytes for its log")
    for p in results["peers"].get("opencv_vectorize", []):
        if p.get("na", {}).get("all"):
            (notes if "not built" in p["na"]["all"] else problems).append(f"{p['job']}: {p['na']['all']}")
            continue
        for side in ("cogmap", "opencv"):
            for k in ("seconds", "vertex_count", "bytes_polylines", "wall_precision_mean_m",
                      "wall_precision_p95_m", "wall_recall"):
                if not finite(p["result"].get(side, {}).get(k)):
                    problems.append(f"{p['job']}: {side}.{k} missing or not finite")
    for note in results.get("figure_notes", []):
        if "matplotlib" in note:  # optional (install-deps.sh --peers), like the peers
            notes.append("figure " + note)
    for n in notes:
        print("bench smoke: skipped, " + n)
    if problems:
        print("bench smoke: FAILED", file=sys.stderr)
        for p in problems:
            print("  " + p, file=sys.stderr)
        return 1
    print("bench smoke: every metric present and finite")
    return 0
