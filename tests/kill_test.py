#!/usr/bin/env python3
"""Kill test of `cogmap map` (issue 14): SIGKILL at random moments of a run
into a folder that holds a finished map, and what is left afterwards.

Setup: `cogmap gen-building --rooms N` and `cogmap simulate` give a log; an
uninterrupted `cogmap map` of it is the reference (its duration T sets the
range of kill moments, its files the "old" map).

Each trial:
  1. OUT = a copy of the reference folder (the previous, finished map);
  2. `cogmap map LOG -o OUT` (default outputs) is killed with SIGKILL at a
     moment drawn uniformly from [0, 1.1 T] (some runs finish first); in the
     --commit-trials that follow, 0-3 ms after the commit journal appears
     (while the files are being moved into place);
  3. OUT as the kill left it must hold the old map (every file byte-identical
     to the reference) or the new one complete (one run_id in report.json, the
     store and the manifest; the deterministic files equal the reference's),
     or be in the middle of a commit (the commit journal present), which the
     next run must finish; anything else is a mix (a failure);
  4. every store left (OUT/map.sqlite, the staging store of the killed run)
     passes PRAGMA integrity_check (checked on a copy);
  5. the next run (a log whose line 4 is bad) must exit 2 with one line naming
     that log, finish a half-done commit (whose staging folder then goes), set
     the killed run's staging folder aside as failed-run-*-killed otherwise,
     and leave OUT holding the old or the new map whole;
  6. the killed run's ASRs must be identical (every column) to the same ids in
     every other trial's (before the end-of-run rewrite) or to the reference's
     (after it);
  7. resume: the killed run's store, put alone into a folder, is continued by
     `cogmap map TAIL --resume` where TAIL is the log from the record at which
     the store's last ASR was written (its last_raw_pose); it must exit 0 with
     a store that passes integrity_check, keep every stored ASR's walls, and
     its ASR and room counts are compared with the uninterrupted run's, its
     map must be no worse against the building's truth than the
     uninterrupted run's (`cogmap eval --world`: ATE not over it by more than
     5 % + 0.02 m, bench/never_worse's rule); and
     `cogmap map LOG --resume` with the whole log into another copy must skip
     what the store holds (report.json resumed_after_record) and make the
     tail's map (the same ASR count and plan.json).

Prints one line per trial and the figures at the end; exit status 1 when any
check failed.
  python3 tests/kill_test.py --cogmap build/app/cogmap [--rooms 100] [--trials 100] [--commit-trials 20] [--seed 1]
"""
import argparse
import hashlib
import json
import math
import os
import random
import shutil
import signal
import sqlite3
import statistics
import subprocess
import sys
import tempfile
import time

# Files whose bytes do not depend on the run (report.json has timings, the
# store and map.gpkg the run id / times).
DETERMINISTIC = ["plan.svg", "map.geojson", "map.map", "walls.json", "plan.json", "route_graph.geojson"]


def sha(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def visible_files(folder):
    """The folder's files as a reader sees them (no lock, staging, set-aside runs)."""
    out = {}
    for name in os.listdir(folder):
        p = os.path.join(folder, name)
        if name == ".cogmap.lock" or name.startswith(".staging-") or name.startswith("failed-run-"):
            continue
        if os.path.isfile(p):
            out[name] = p
    return out


def integrity(store, scratch):
    """PRAGMA integrity_check of a copy of 'store' (with its -wal), 'ok' or the problem."""
    if os.path.exists(scratch):
        shutil.rmtree(scratch)
    os.makedirs(scratch)
    copy = os.path.join(scratch, "s.sqlite")
    shutil.copyfile(store, copy)
    if os.path.exists(store + "-wal"):
        shutil.copyfile(store + "-wal", copy + "-wal")
    try:
        con = sqlite3.connect(copy)
        res = con.execute("PRAGMA integrity_check").fetchone()[0]
        con.close()
        return res
    except sqlite3.Error as e:
        return "sqlite error: %s" % e


def read_store(store, scratch):
    """(meta dict, {id: row tuple}, placement count) of a copy of 'store'."""
    integrity(store, scratch)  # makes the copy
    con = sqlite3.connect(os.path.join(scratch, "s.sqlite"))
    tables = {r[0] for r in con.execute("SELECT name FROM sqlite_master WHERE type='table'")}
    if not tables:
        # Killed between creating the file (SQLite writes its header when WAL
        # is turned on) and committing the schema: a valid, empty database.
        con.close()
        return {}, {}, 0
    meta = dict(con.execute("SELECT key, value FROM meta").fetchall())
    # Every column but the five timings (sec_grid ... sec_fit), which vary from run to run.
    rows = {r[0]: r[:14] + r[19:] for r in con.execute("SELECT * FROM asr")}
    placements = con.execute("SELECT count(*) FROM placement").fetchone()[0]
    con.close()
    return meta, rows, placements


def same_row(a, b):
    """Rows equal, reals to 1e-9 relative (the end-of-run covariances vary in their last bits)."""
    if a is None or b is None or len(a) != len(b):
        return False
    for x, y in zip(a, b):
        if isinstance(x, float) and isinstance(y, float):
            if abs(x - y) > 1e-9 * max(1.0, abs(x), abs(y)):
                return False
        elif x != y:
            return False
    return True


def run_id_of_store(path, scratch):
    try:
        return read_store(path, scratch)[0].get("run_id")
    except sqlite3.Error:
        return None


def classify(folder, ref_hashes, ref_run_id, scratch):
    """'old', 'new', 'commit' (journal present) or 'mix: why'."""
    files = visible_files(folder)
    if ".cogmap-commit.json" in files:
        return "commit"
    names = set(files)
    if names == set(ref_hashes) and all(sha(files[n]) == ref_hashes[n] for n in names):
        return "old"
    if names != set(ref_hashes):
        return "mix: files %s" % sorted(names ^ set(ref_hashes))
    try:
        report_id = json.load(open(files["report.json"])).get("run_id")
        manifest_id = json.load(open(files[".cogmap-manifest.json"])).get("run_id")
    except (ValueError, OSError) as e:
        return "mix: %s" % e
    store_id = run_id_of_store(files["map.sqlite"], scratch)
    if not (report_id == manifest_id == store_id) or report_id == ref_run_id:
        return "mix: run ids report %s manifest %s store %s" % (report_id, manifest_id, store_id)
    for n in DETERMINISTIC:
        if n in files and sha(files[n]) != ref_hashes[n]:
            return "mix: new %s differs from the reference" % n
    return "new"


def ate_against(cogmap, folder, world):
    """The map's ATE (m) against the world's truth, by `cogmap eval --world --json`."""
    r = subprocess.run([cogmap, "eval", folder, "--world", world, "--json"], capture_output=True, text=True)
    if r.returncode:
        sys.exit("eval of %s failed: %s" % (folder, r.stderr))
    return json.loads(r.stdout)["ate_rmse_m"]


def store_alone(store, folder):
    """A new folder holding a copy of 'store' (and its -wal) alone; returns it."""
    shutil.rmtree(folder, ignore_errors=True)
    os.makedirs(folder)
    shutil.copyfile(store, os.path.join(folder, "map.sqlite"))
    if os.path.exists(store + "-wal"):
        shutil.copyfile(store + "-wal", os.path.join(folder, "map.sqlite-wal"))
    return folder


def index_log(path):
    """Byte offset of the first record line, and (offset, time, x, y, theta) of every ODOM line."""
    header_end, odoms = None, []
    with open(path, "rb") as f:
        offset = 0
        for line in f:
            if header_end is None and not (line.startswith(b"#") or line.startswith(b"robot")):
                header_end = offset
            if line.startswith(b"ODOM "):
                p = line.split()
                odoms.append((offset, float(p[1]), float(p[2]), float(p[3]), float(p[4])))
            offset += len(line)
    return header_end, odoms


def write_tail(log, header_end, start, tail):
    with open(log, "rb") as f, open(tail, "wb") as out:
        out.write(f.read(header_end))
        f.seek(start)
        shutil.copyfileobj(f, out)


def find_resume_record(odoms, end_time, pose):
    """The ODOM line at or after 'end_time' whose pose is 'pose' (the last record the store saw)."""
    best, best_d = None, None
    for off, t, x, y, th in odoms:
        if t < end_time - 1e-9:
            continue
        d = max(abs(x - pose[0]), abs(y - pose[1]), abs(th - pose[2]))
        if best_d is None or d < best_d:
            best, best_d = off, d
        if t > end_time + 60.0:
            break
    return best, best_d


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cogmap", required=True)
    ap.add_argument("--rooms", type=int, default=100)
    ap.add_argument("--trials", type=int, default=100)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--commit-trials", type=int, default=0,
                    help="more trials, each killed 0-3 ms after its commit journal appears")
    ap.add_argument("--work", help="work folder (default: a temporary one, removed at the end)")
    args = ap.parse_args()
    cogmap = os.path.abspath(args.cogmap)
    rng = random.Random(args.seed)
    work = args.work or tempfile.mkdtemp(prefix="cogmap-kill-")
    os.makedirs(work, exist_ok=True)
    j = lambda *p: os.path.join(work, *p)
    scratch = j("scratch")
    failures = []

    def check(cond, what):
        if not cond:
            failures.append(what)
            print("  FAIL:", what, flush=True)
        return cond

    def run(cmd, **kw):
        return subprocess.run(cmd, capture_output=True, text=True, **kw)

    world, log, bad = j("building.map"), j("run.log"), j("bad.log")
    r = run([cogmap, "gen-building", "--rooms", str(args.rooms), "--corridor-m", str(10 * args.rooms),
             "--seed", str(args.seed), "-o", world])
    if r.returncode:
        sys.exit("gen-building failed: " + r.stderr)
    r = run([cogmap, "simulate", world, "--seed", str(args.seed), "-o", log])
    if r.returncode:
        sys.exit("simulate failed: " + r.stderr)
    with open(bad, "w") as f:
        f.write("# cogmap-log 1\nrobot pioneer16\nODOM 0 1 1 0\nSWEEP 0 1 0 nan\n")

    ref = j("ref")
    t0 = time.monotonic()
    r = run([cogmap, "map", log, "-o", ref])
    full_s = time.monotonic() - t0
    if r.returncode:
        sys.exit("reference run failed: " + r.stderr)
    ref_files = visible_files(ref)
    ref_hashes = {n: sha(p) for n, p in ref_files.items()}
    ref_report = json.load(open(ref_files["report.json"]))
    ref_meta, ref_rows, _ = read_store(ref_files["map.sqlite"], scratch)
    ref_asrs, ref_rooms = ref_report["asr_count"], ref_report.get("pose_graph", {}).get("rooms")
    scaled = ((ref_report.get("distance_scale") or {}).get("applied", 1.0)) != 1.0
    check(integrity(ref_files["map.sqlite"], scratch) == "ok", "reference store integrity")
    ref_ate = ate_against(cogmap, ref, world)
    header_end, odoms = index_log(log)
    print("%d rooms: %s, %d records, reference run %.1f s, %d ASRs, %s rooms; %d trials, kill at U(0, %.1f s)"
          % (args.rooms, os.path.basename(log), ref_report["records"], full_s, ref_asrs, ref_rooms, args.trials,
             1.1 * full_s), flush=True)

    states, after_states = {}, {}
    stores_checked = stores_ok = 0
    seen_rows = {}  # ASR id -> row, from killed runs' stores before the end-of-run rewrite
    rows_compared = rows_equal = 0
    resumed, resume_ok, resume_skipped = 0, 0, {}
    same_log_resumed = []
    asr_diffs, room_diffs, resume_secs, kept_asrs, pose_diffs, resumed_ates = [], [], [], [], [], []
    for trial in range(args.trials + args.commit_trials):
        at_commit = trial >= args.trials
        out = j("out")
        shutil.rmtree(out, ignore_errors=True)
        shutil.copytree(ref, out)
        kill_at = rng.uniform(0.0, 0.003 if at_commit else 1.1 * full_s)
        journal = os.path.join(out, ".cogmap-commit.json")
        p = subprocess.Popen([cogmap, "map", log, "-o", out], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        started = time.monotonic()
        if at_commit:  # poll for the journal, then wait kill_at
            while p.poll() is None and not os.path.exists(journal):
                time.sleep(0.0002)
            kill_at += time.monotonic() - started
        try:
            p.wait(timeout=max(0.0, kill_at - (time.monotonic() - started)))
            finished = True
        except subprocess.TimeoutExpired:
            p.send_signal(signal.SIGKILL)
            p.wait()
            finished = False
        state = classify(out, ref_hashes, ref_meta.get("run_id"), scratch)
        states[state.split(":")[0]] = states.get(state.split(":")[0], 0) + 1
        check(not state.startswith("mix"), "trial %d: after the kill: %s" % (trial, state))
        if finished:
            check(p.returncode == 0, "trial %d: finished with exit %d" % (trial, p.returncode))
        # Every store left behind passes integrity_check.
        stagings = [n for n in os.listdir(out) if n.startswith(".staging-")]
        full = [n for n in stagings if os.listdir(os.path.join(out, n))]
        stores = [os.path.join(out, "map.sqlite")] + [os.path.join(out, s, "map.sqlite") for s in stagings]
        for s in stores:
            if os.path.exists(s) and os.path.getsize(s) > 0:
                stores_checked += 1
                res = integrity(s, scratch)
                stores_ok += res == "ok"
                check(res == "ok", "trial %d: %s: integrity_check: %s" % (trial, os.path.relpath(s, work), res))
        # The next run (a bad log) finishes any commit, sets the killed run aside, fails cleanly.
        r = run([cogmap, "map", bad, "-o", out])
        lines = [l for l in r.stderr.splitlines() if l.strip()]
        check(r.returncode == 2 and lines and lines[-1].startswith("cogmap: " + bad + ":4:"),
              "trial %d: next run: exit %d, stderr %r" % (trial, r.returncode, r.stderr))
        after = classify(out, ref_hashes, ref_meta.get("run_id"), scratch)
        after_states[after] = after_states.get(after, 0) + 1
        check(after in ("old", "new"), "trial %d: after the next run: %s" % (trial, after))
        left = sorted(n for n in os.listdir(out) if n.startswith(".staging-"))
        check(not left, "trial %d: staging folders left: %s" % (trial, left))
        killed = sorted(n for n in os.listdir(out) if n.startswith("failed-run-"))
        # Set aside: every staging folder that holds something, except the one of
        # a half-done commit (finished from it, then empty); empty ones are removed.
        check(len(killed) == max(0, len(full) - (state == "commit")) and all(n.endswith("-killed") for n in killed),
              "trial %d: set aside %s for staging %s" % (trial, killed, stagings))
        line = "trial %3d: kill at %5.2f s%s%s: %s -> %s" % (
            trial, kill_at, " (at commit)" if at_commit else "", " (finished)" if finished else "", state, after)
        partial = os.path.join(out, killed[0], "map.sqlite") if killed else None
        if partial and os.path.exists(partial) and os.path.getsize(partial) > 0:
            try:
                meta, rows, placements = read_store(partial, scratch)
            except sqlite3.Error as e:
                check(False, "trial %d: partial store unreadable: %s" % (trial, e))
                meta, rows, placements = {}, {}, 0
            # The killed run's ASRs are the same in every trial (or the reference's, once rewritten).
            for i, row in rows.items():
                want = ref_rows.get(i) if placements else seen_rows.setdefault(i, row)
                rows_compared += 1
                rows_equal += same_row(want, row)
                check(same_row(want, row), "trial %d: ASR %d differs from %s" % (trial, i, "the reference" if placements
                                                                          else "other trials'"))
            line += ", store %d ASRs%s" % (len(rows), " (rewritten)" if placements else "")
            if not rows or placements:
                why = "no ASR stored" if not rows else "run already finished"
                resume_skipped[why] = resume_skipped.get(why, 0) + 1
            else:
                last = rows[max(rows)]
                end_time = last[10]  # end_time_s
                pose = [float(v) for v in meta["last_raw_pose"].split()]
                start, dist = find_resume_record(odoms, end_time, pose)
                # A run that scaled its odometry (report.json distance_scale)
                # stored its last pose scaled: the record is the one it names.
                if (start is None or dist >= 1e-6) and scaled and "last_record" in meta:
                    n = int(meta["last_record"])
                    check(1 <= n <= len(odoms) and odoms[n - 1][1] >= end_time - 1e-9,
                          "trial %d: last_record %d is no ODOM line at or after the last ASR's end" % (trial, n))
                    start, dist = odoms[max(0, min(n, len(odoms)) - 1)][0], 0.0
                check(start is not None and dist < 1e-6,
                      "trial %d: no ODOM line at last_raw_pose %s (nearest %s)" % (trial, pose, dist))
                rdir = store_alone(partial, j("resume"))
                tail = j("tail.log")
                write_tail(log, header_end, start, tail)
                t1 = time.monotonic()
                r = run([cogmap, "map", tail, "--resume", "-o", rdir, "--outputs", "svg"])
                resume_secs.append(time.monotonic() - t1)
                resumed += 1
                ok = check(r.returncode == 0, "trial %d: resume: exit %d: %s" % (trial, r.returncode, r.stderr))
                if ok:
                    res = integrity(os.path.join(rdir, "map.sqlite"), scratch)
                    ok = check(res == "ok", "trial %d: resumed store: %s" % (trial, res))
                if ok:
                    rep = json.load(open(os.path.join(rdir, "report.json")))
                    _, rrows, _ = read_store(os.path.join(rdir, "map.sqlite"), scratch)
                    # Every stored ASR is still there. The killed run's ASRs are placed again
                    # by the resumed run (docs/store.md): compare their final walls (column
                    # 16 here) and corrected positions (4, 5) with the uninterrupted run's.
                    ok = check(all(i in rrows for i in rows), "trial %d: resume lost stored ASRs" % trial)
                    kept_asrs.append(sum(rrows[i][16] == ref_rows[i][16] for i in rows if i in ref_rows) / len(rows))
                    diffs = [math.hypot(rrows[i][4] - ref_rows[i][4], rrows[i][5] - ref_rows[i][5])
                             for i in rows if i in ref_rows]
                    pose_diffs.extend(diffs)
                    ate = ate_against(cogmap, rdir, world)
                    resumed_ates.append(ate)
                    line += ", ATE %.3f m (uninterrupted %.3f)" % (ate, ref_ate)
                    if not check(ate <= 1.05 * ref_ate + 0.02,
                                 "trial %d: the resumed map is worse than the uninterrupted one: ATE %.3f m "
                                 "against %.3f" % (trial, ate, ref_ate)):
                        # Kept for a look: the killed store and its resume.
                        kept = j("trial-%d" % trial)
                        store_alone(partial, os.path.join(kept, "killed"))
                        shutil.copytree(rdir, os.path.join(kept, "resumed"))
                        line += " (kept in %s)" % kept
                    asr_diffs.append(rep["asr_count"] - ref_asrs)
                    rooms = rep.get("pose_graph", {}).get("rooms")
                    if rooms is not None and ref_rooms is not None:
                        room_diffs.append(rooms - ref_rooms)
                    line += ", resumed: %d ASRs (%+d), %s rooms" % (rep["asr_count"], asr_diffs[-1], rooms)
                if ok:
                    # The same store resumed with the whole log: it knows that log (its
                    # fingerprint) and where it stopped, skips to that record and must
                    # make the tail's map.
                    sdir = store_alone(partial, j("resume_same"))
                    r2 = run([cogmap, "map", log, "--resume", "-o", sdir, "--outputs", "svg"])
                    ok = check(r2.returncode == 0, "trial %d: resume with the whole log: exit %d: %s"
                               % (trial, r2.returncode, r2.stderr))
                    if ok:
                        rep2 = json.load(open(os.path.join(sdir, "report.json")))
                        skipped = rep2.get("resumed_after_record", 0)
                        ok = check(skipped > 0, "trial %d: resume with the whole log mapped it from its start" % trial)
                        if ok and rep2["records"] > 0:
                            same = (rep2["asr_count"] == rep["asr_count"] and
                                    open(os.path.join(sdir, "plan.json")).read() ==
                                    open(os.path.join(rdir, "plan.json")).read())
                            ok = check(same, "trial %d: resume with the whole log (%d ASRs) differs from the tail's (%d)"
                                       % (trial, rep2["asr_count"], rep["asr_count"]))
                        same_log_resumed.append(ok)
                        line += ", whole log: after record %d%s" % (skipped, ", same map" if ok else "")
                resume_ok += ok
        print(line, flush=True)

    print("\nfigures (%d random + %d at-commit trials, %d-room building, reference %d ASRs / %s rooms, run %.1f s):"
          % (args.trials, args.commit_trials, args.rooms, ref_asrs, ref_rooms, full_s))
    print("  folder as the kill left it: %s" % ", ".join("%s %d" % kv for kv in sorted(states.items())))
    print("  folder after the next run:  %s" % ", ".join("%s %d" % kv for kv in sorted(after_states.items())))
    print("  stores passing integrity_check: %d of %d" % (stores_ok, stores_checked))
    print("  killed runs' ASRs identical across trials / to the reference: %d of %d" % (rows_equal, rows_compared))
    print("  resumed: %d, succeeded %d; not resumed: %s" % (resumed, resume_ok, resume_skipped or "none"))
    if asr_diffs:
        print("  resumed ASR count - uninterrupted: min %+d median %+g max %+d" % (
            min(asr_diffs), statistics.median(asr_diffs), max(asr_diffs)))
    if room_diffs:
        print("  resumed rooms - uninterrupted: min %+d median %+g max %+d" % (
            min(room_diffs), statistics.median(room_diffs), max(room_diffs)))
    if kept_asrs:
        print("  killed run's ASRs whose final walls equal the uninterrupted run's (byte-identical): median %.0f %%"
              % (100 * statistics.median(kept_asrs)))
    if pose_diffs:
        print("  their final positions against the uninterrupted run's: median %.3f m, max %.3f m"
              % (statistics.median(pose_diffs), max(pose_diffs)))
        # The resumed run replays the killed run's ASRs as that run placed
        # them (docs/store.md): their final poses are the uninterrupted run's
        # but for what the tail's first ASR changes, which can be a revisit
        # found or missed and, through the loops, a metre here (100 rooms,
        # seed 7, killed with 178-181 ASRs stored: 0.92-1.33 m, where the
        # map's own position sigmas are 6-10 m and its ATE the same). Without
        # the path's turns in the store (schema 6) they ended a median 4.6 m
        # away; the ATE check above is the one that says whether the map is
        # worse.
    if resumed_ates:
        print("  resumed maps' ATE against the truth: median %.3f m, max %.3f m (uninterrupted %.3f m)"
              % (statistics.median(resumed_ates), max(resumed_ates), ref_ate))
    if same_log_resumed:
        print("  resumed with the whole log (skipping what the store holds): %d of %d the tail's map"
              % (sum(same_log_resumed), len(same_log_resumed)))
    if resume_secs:
        print("  resume run: median %.1f s" % statistics.median(resume_secs))
    print("  failures: %d" % len(failures))
    if failures:
        print("  work folder kept: %s" % work)
    elif not args.work:
        shutil.rmtree(work, ignore_errors=True)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
