#!/usr/bin/env python3
"""The live node against the offline command on the same run (ctest
ros_node_live_equals_offline): a simulated nine_rooms run is written as a
RosAria-style bag; `cogmap map BAG` maps it offline; then a real roscore, the
node, and `rosbag play` of the bag; `~finish` ends the run. The live map must
have the same ASRs as the offline one with walls within a centimetre, and what
the node published (walls, rooms, map) must match its store."""
import argparse
import json
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import time


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def wait_for(cond, seconds, what):
    end = time.time() + seconds
    while time.time() < end:
        if cond():
            return
        time.sleep(0.2)
    raise SystemExit("timed out waiting for " + what)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--cogmap", required=True)
    ap.add_argument("--node", required=True)
    ap.add_argument("--shared", required=True)
    ap.add_argument("--pythonpath", required=True)
    a = ap.parse_args()
    sys.path.insert(0, a.pythonpath)
    # Its files (a bag, logs and maps: some 14 MB) go once the test passes,
    # and are kept, named, when it fails.
    work = tempfile.mkdtemp(prefix="cogmap-ros-")
    try:
        check(a, work)
    except BaseException:
        print("cogmap node test: its files are kept in " + work, file=sys.stderr)
        raise
    shutil.rmtree(work, ignore_errors=True)


def check(a, work):
    import cogmap  # noqa: E402

    log, bag = os.path.join(work, "run.log"), os.path.join(work, "run.bag")
    subprocess.run([a.cogmap, "simulate", os.path.join(a.shared, "worlds", "nine_rooms.map"), "--seed", "4",
                    "--drift-deg-per-m", "1", "-o", log], check=True, capture_output=True)
    subprocess.run([a.cogmap, "convert", log, "--to", "rosbag", "-o", bag], check=True, capture_output=True)
    offline = os.path.join(work, "offline")
    subprocess.run([a.cogmap, "map", bag, "-o", offline], check=True, capture_output=True)

    env = dict(os.environ)
    port = free_port()
    env["ROS_MASTER_URI"] = "http://127.0.0.1:%d" % port
    env["ROS_HOSTNAME"] = "127.0.0.1"
    env["ROS_HOME"] = os.path.join(work, "ros_home")
    os.environ.update({k: env[k] for k in ("ROS_MASTER_URI", "ROS_HOSTNAME", "ROS_HOME")})
    procs = []
    try:
        procs.append(subprocess.Popen(["roscore", "-p", str(port)], env=env, stdout=subprocess.DEVNULL,
                                      stderr=subprocess.DEVNULL))
        wait_for(lambda: subprocess.run(["rostopic", "list"], env=env, capture_output=True).returncode == 0, 60,
                 "roscore")
        live = os.path.join(work, "live")
        node_log = open(os.path.join(work, "node.log"), "w")
        # A 2 s reorder window: the test machine may be loaded (ctest runs tests in parallel).
        procs.append(subprocess.Popen([a.node, "_output:=" + live, "_reorder_window:=2.0"], env=env, stdout=node_log,
                                      stderr=node_log))
        wait_for(lambda: "/cogmap_node/finish" in subprocess.run(["rosservice", "list"], env=env,
                                                                  capture_output=True, text=True).stdout,
                 60, "the node's services")
        # Played 20x faster than recorded; the node subscribes with deep queues.
        # --wait-for-subscribers only waits for the master to list a subscriber:
        # a message published before its TCP connection is up is lost (ROS 1
        # transport), and a lost first odometry message changes the first
        # record. -d 2 gives the connections time before the first message.
        subprocess.run(["rosbag", "play", "-q", "-r", "20", "-d", "2", "--wait-for-subscribers", bag], env=env,
                       check=True,
                       capture_output=True, timeout=300)
        # The last messages must have reached the node before ~finish (which
        # releases whatever its reorder window holds): 2 s once lost the
        # bag's last record on a loaded machine (6942 of 6943 records).
        time.sleep(5.0)
        out = subprocess.run(["rosservice", "call", "/cogmap_node/finish"], env=env, capture_output=True, text=True,
                             timeout=300)
        print(out.stdout.strip())
        if "success: True" not in out.stdout:
            print(open(os.path.join(work, "node.log")).read())
            raise SystemExit("finish failed: " + out.stdout + out.stderr)

        # What the node published (latched) against its store.
        import rospy
        from nav_msgs.msg import OccupancyGrid
        from visualization_msgs.msg import MarkerArray
        rospy.init_node("cogmap_node_test", anonymous=True, disable_signals=True)
        walls = rospy.wait_for_message("/cogmap_node/walls", MarkerArray, timeout=30)
        rooms = rospy.wait_for_message("/cogmap_node/rooms", MarkerArray, timeout=30)
        grid = rospy.wait_for_message("/cogmap_node/map", OccupancyGrid, timeout=30)
    finally:
        for p in reversed(procs):
            p.terminate()
            try:
                p.wait(timeout=20)
            except subprocess.TimeoutExpired:
                p.kill()

    a_store = cogmap.open_store(os.path.join(offline, "map.sqlite"))
    b_store = cogmap.open_store(os.path.join(live, "map.sqlite"))
    ra = json.load(open(os.path.join(offline, "report.json")))
    rb = json.load(open(os.path.join(live, "report.json")))
    print("offline: %d records, %d ASRs; live: %d records, %d ASRs" % (ra["records"], ra["asr_count"], rb["records"],
                                                                       rb["asr_count"]))
    if a_store.ids() != b_store.ids():
        # Where the live records part from the offline ones.
        off = subprocess.run([a.cogmap, "convert", bag, "-o", os.path.join(work, "offline.log")], capture_output=True)
        diff = subprocess.run(["diff", os.path.join(work, "offline.log"), os.path.join(live, "records.log")],
                              capture_output=True, text=True).stdout
        print("\n".join(diff.splitlines()[:40]))
        raise SystemExit("live ASRs %s, offline %s" % (b_store.ids(), a_store.ids()))
    worst = 0.0
    segments = 0
    for i in a_store.ids():
        wa, wb = a_store.asr(i)["walls"], b_store.asr(i)["walls"]
        assert len(wa) == len(wb), (i, len(wa), len(wb))
        for p, q in zip(wa, wb):
            assert p.shape == q.shape, (i, p.shape, q.shape)
            worst = max(worst, float(abs(p - q).max()) if p.size else 0.0)
            segments += p.shape[0] - 1
    print("walls: largest difference %.6f m over %d ASRs" % (worst, len(a_store.ids())))
    if worst > 0.01:  # where the live records part from the offline ones
        subprocess.run([a.cogmap, "convert", bag, "-o", os.path.join(work, "offline.log")], capture_output=True)
        diff = subprocess.run(["diff", os.path.join(work, "offline.log"), os.path.join(live, "records.log")],
                              capture_output=True, text=True).stdout
        print("\n".join(diff.splitlines()[:40]))
    assert worst <= 0.01, worst
    assert len(walls.markers[0].points) == 2 * segments, (len(walls.markers[0].points), segments)
    assert len(rooms.markers) == len(b_store.ids())
    assert grid.info.width > 0 and any(v == 100 for v in grid.data)
    # Free space: the robot's true path lies in free cells of the whole map
    # (the map frame is the corrected odometry frame, which starts at the true
    # start pose; the raw odometry has drifted by metres at the end).
    free = sum(1 for v in grid.data if v == 0)
    res, ox, oy, w = grid.info.resolution, grid.info.origin.position.x, grid.info.origin.position.y, grid.info.width
    on_free = total = 0
    for line in open(os.path.join(live, "records.log")):
        if not line.startswith("TRUTH"):
            continue
        total += 1
        if total % 25:
            continue
        _, _, x, y, _ = line.split()
        i, j = int((float(x) - ox) / res), int((float(y) - oy) / res)
        on_free += 1 if 0 <= i < w and 0 <= j < grid.info.height and grid.data[j * w + i] == 0 else 0
    share = on_free / float(total // 25)
    if os.environ.get("COGMAP_NODE_MAP_PGM"):  # to look at it
        with open(os.environ["COGMAP_NODE_MAP_PGM"], "wb") as f:
            f.write(b"P5 %d %d 255\n" % (w, grid.info.height))
            f.write(bytes(205 if v < 0 else (0 if v == 100 else 254) for j in range(grid.info.height - 1, -1, -1)
                          for v in grid.data[j * w:(j + 1) * w]))
    print("map: %d free cells (%.1f m2), %.1f %% of the path on free cells" % (free, free * res * res, 100 * share))
    assert share >= 0.9, share
    print("published: %d wall segments, %d rooms, map %dx%d" % (segments, len(rooms.markers), grid.info.width,
                                                               grid.info.height))


if __name__ == "__main__":
    main()
