#!/usr/bin/env python3
"""Rewrites a native cogmap sonar log as a CARMEN log with SONAR messages.

    tests/data/native_to_carmen_sonar.py run.log > run.clf

Every record becomes an ODOM line; every record with readings also a SONAR line
(CARMEN's writelog.c fields: cone_angle n r1..rn x1 y1 theta1 .. xn yn thetan
timestamp host logger_timestamp) holding the latest range of every transducer
(CARMEN's base publishes the whole ring each cycle), once each has fired.
The robot line must be a sonar robot: pioneer16, pioneer8, p2at16, or robot-json.
"""
import json
import math
import sys

# The built-in Pioneer rings (cogmap/sensors/robot.cc): x, y in mm, heading in
# degrees; pioneer8 is the front half of pioneer16. Beam width 30 degrees.
PIONEER16 = [(69, 136, 90), (114, 119, 50), (148, 78, 30), (166, 27, 10),
             (166, -27, -10), (148, -78, -30), (114, -119, -50), (69, -136, -90),
             (-157, -136, -90), (-203, -119, -130), (-237, -78, -150), (-255, -27, -170),
             (-255, 27, 170), (-237, 78, 150), (-203, 119, 130), (-157, 136, 90)]
P2AT16 = [(147, 136, 90), (193, 119, 50), (227, 79, 30), (245, 27, 10),
          (245, -27, -10), (227, -79, -30), (193, -119, -50), (147, -136, -90),
          (-144, -136, -90), (-189, -119, -130), (-223, -79, -150), (-241, -27, -170),
          (-241, 27, 170), (-223, 79, 150), (-189, 119, 130), (-144, 136, 90)]
RINGS = {"pioneer16": PIONEER16, "pioneer8": PIONEER16[:8], "p2at16": P2AT16}


def robot_sensors(line):
    kind, _, rest = line.partition(" ")
    if kind == "robot-json":
        j = json.loads(rest)
        mm = 0.001 if j.get("units") == "mm" else 1.0
        deg = j.get("angles", "deg") == "deg"
        out = []
        for s in j["sensors"]:
            th = math.radians(s["heading"]) if deg else s["heading"]
            bw = s.get("beam_width", 30 if deg else math.radians(30))
            out.append((s["x"] * mm, s["y"] * mm, th, math.radians(bw) if deg else bw))
        return out
    name = rest.strip()
    if name not in RINGS:
        sys.exit("robot '%s' is not a sonar ring this script knows (%s, or robot-json)" % (name, ", ".join(RINGS)))
    return [(x / 1000.0, y / 1000.0, math.radians(h), math.radians(30)) for x, y, h in RINGS[name]]


def main():
    lines = open(sys.argv[1]).read().splitlines()
    sensors = None
    latest = {}
    out = sys.stdout
    out.write("# CARMEN Logfile rewritten from %s\n" % sys.argv[1])
    odom = None
    for line in lines:
        if not line or line.startswith("#"):
            continue
        f = line.split()
        if f[0] in ("robot", "robot-json"):
            sensors = robot_sensors(line)
        elif f[0] == "ODOM":
            odom = f[1:5]
            out.write("ODOM %s %s %s 0 0 0 %s sim %s\n" % (odom[1], odom[2], odom[3], odom[0], odom[0]))
        elif f[0] == "SWEEP":
            n = int(f[2])
            for i in range(n):
                latest[int(f[3 + 2 * i])] = f[4 + 2 * i]
            if len(latest) < len(sensors):
                continue
            t = f[1]
            ranges = " ".join(latest[i] for i in range(len(sensors)))
            offsets = " ".join("%.17g %.17g %.17g" % s[:3] for s in sensors)
            out.write("SONAR %.17g %d %s %s %s sim %s\n" % (sensors[0][3], len(sensors), ranges, offsets, t, t))


main()
