#!/usr/bin/env python3
"""End to end: a simulated nine_rooms run, converted to a RosAria-style ROS 1
bag by `cogmap convert --to rosbag`, maps like the native log: same ASR count,
same number of wall polylines, every wall vertex within a centimetre. The same
run as an MRPT rawlog (`--to rawlog`) gives the same ASR count (its odometry
and readings are separate records, so walls are not compared)."""
import argparse
import json
import os
import subprocess
import sys
import tempfile


def run(*args):
    subprocess.run(args, check=True, stdout=subprocess.DEVNULL)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--cogmap", required=True)
    ap.add_argument("--world", required=True)
    a = ap.parse_args()
    failures = 0
    with tempfile.TemporaryDirectory() as tmp:
        log, bag = os.path.join(tmp, "run.log"), os.path.join(tmp, "run.bag")
        run(a.cogmap, "simulate", a.world, "--seed", "4", "-o", log)
        run(a.cogmap, "convert", log, "--to", "rosbag", bag)
        rawlog = os.path.join(tmp, "run.rawlog")
        run(a.cogmap, "convert", log, "--to", "rawlog", rawlog)
        info = subprocess.run([a.cogmap, "log-info", bag], check=True, capture_output=True, text=True).stdout
        if "robot hint:     pioneer16" not in info or "/RosAria/sonar" not in info:
            print("log-info of the bag does not show the pioneer16 sonar ring:\n" + info)
            failures += 1
        out = {}
        for name, path in (("log", log), ("bag", bag), ("rawlog", rawlog)):
            folder = os.path.join(tmp, "out_" + name)
            run(a.cogmap, "map", path, "-o", folder)
            with open(os.path.join(folder, "report.json")) as f:
                report = json.load(f)
            with open(os.path.join(folder, "walls.json")) as f:
                walls = json.load(f)["polylines"]
            out[name] = (report["asr_count"], walls)
        (n_log, w_log), (n_bag, w_bag) = out["log"], out["bag"]
        print(f"ASRs: native log {n_log}, bag {n_bag}; polylines {len(w_log)} vs {len(w_bag)}")
        if n_log != n_bag or n_log < 2:
            failures += 1
        print(f"ASRs from the rawlog: {out['rawlog'][0]}")
        if out["rawlog"][0] != n_log:
            failures += 1
        if len(w_log) != len(w_bag):
            failures += 1
        else:
            worst = 0.0
            for p, q in zip(w_log, w_bag):
                if len(p) != len(q):
                    failures += 1
                    print(f"a polyline of {len(p)} vertices has {len(q)} from the bag")
                    continue
                for u, v in zip(p, q):
                    worst = max(worst, abs(u[0] - v[0]), abs(u[1] - v[1]))
            print(f"largest wall vertex difference: {worst:.4f} m")
            if worst > 0.01:
                failures += 1
    print(f"{1 - min(failures, 1)} passed, {min(failures, 1)} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
