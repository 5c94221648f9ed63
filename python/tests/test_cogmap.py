"""The Python bindings against the command on the same log: reading, mapping
(whole and record by record), the store, the floor plan, evaluation, bad input,
and the docs' example."""
import json
import os
import subprocess
import sys

import numpy as np
import pytest

import cogmap

COGMAP = os.environ["COGMAP_BIN"]
SHARED = os.environ["COGMAP_SHARED_DIR"]


@pytest.fixture(scope="module")
def sim_log(tmp_path_factory):
    """A simulated nine_rooms run with 1 deg/m of drift (native log)."""
    path = tmp_path_factory.mktemp("log") / "nine_rooms.log"
    subprocess.run([COGMAP, "simulate", os.path.join(SHARED, "worlds", "nine_rooms.map"), "--seed", "5",
                    "--drift-deg-per-m", "1", "-o", str(path)], check=True, capture_output=True)
    return str(path)


@pytest.fixture(scope="module")
def command_map(sim_log, tmp_path_factory):
    out = tmp_path_factory.mktemp("cmd")
    subprocess.run([COGMAP, "map", sim_log, "-o", str(out)], check=True, capture_output=True)
    with open(out / "report.json") as f:
        return out, json.load(f)


def test_read_log_gives_arrays_of_the_whole_run(sim_log):
    log = cogmap.read_log(sim_log)
    n = log["time"].shape[0]
    assert n > 1000
    assert log["odom"].shape == (n, 3)
    assert log["truth"].shape == (n, 3)
    assert not np.isnan(log["truth"]).any()  # simulated runs carry the truth
    assert np.all(np.diff(log["time"]) >= 0)
    r = log["ranges"]
    assert r.shape[1] == 3
    assert r[:, 0].min() >= 0 and r[:, 0].max() < n
    assert set(np.unique(r[:, 1]).astype(int)) <= set(range(16))
    assert log["robot"]["name"] == "pioneer16"
    assert len(log["robot"]["sensors"]) == 16


def test_read_log_counts_equal_the_commands(sim_log):
    info = subprocess.run([COGMAP, "log-info", sim_log], check=True, capture_output=True, text=True).stdout
    log = cogmap.read_log(sim_log)
    assert str(log["time"].shape[0]) in info


def test_map_log_equals_the_command(sim_log, command_map, tmp_path):
    out, cmd_report = command_map
    report = cogmap.map_log(sim_log, str(tmp_path / "py"))
    for key in ("asr_count", "exit_count", "records", "bytes_polylines"):
        assert report[key] == cmd_report[key], key
    assert report["pose_graph"]["rooms"] == cmd_report["pose_graph"]["rooms"]
    a = cogmap.open_store(str(out / "map.sqlite"))
    b = cogmap.open_store(str(tmp_path / "py" / "map.sqlite"))
    assert a.ids() == b.ids()
    for i in a.ids():
        np.testing.assert_allclose(a.asr(i)["pose"], b.asr(i)["pose"], atol=1e-9)


def test_map_log_second_pass_equals_the_command(sim_log, tmp_path):
    """second_pass=True is `cogmap map --second-pass`: the drift found removed inside each room."""
    out = tmp_path / "cmd"
    subprocess.run([COGMAP, "map", sim_log, "--second-pass", "-o", str(out)], check=True, capture_output=True)
    with open(out / "report.json") as f:
        cmd_report = json.load(f)
    report = cogmap.map_log(sim_log, str(tmp_path / "py"), second_pass=True)
    removed = report["pose_graph"]["second_pass"]["drift_removed_deg_per_m"]
    assert removed == pytest.approx(cmd_report["pose_graph"]["second_pass"]["drift_removed_deg_per_m"], abs=1e-9)
    assert removed == pytest.approx(1.0, abs=0.3)  # the drift the log was simulated with
    assert cogmap.map_log(sim_log, str(tmp_path / "one"))["pose_graph"]["second_pass"] is None
    a = cogmap.open_store(str(out / "map.sqlite"))
    b = cogmap.open_store(str(tmp_path / "py" / "map.sqlite"))
    assert a.ids() == b.ids()
    for i in a.ids():
        np.testing.assert_allclose(a.asr(i)["pose"], b.asr(i)["pose"], atol=1e-9)


def test_map_log_distance_scale_equals_the_command(tmp_path, sim_log):
    """distance_scale is `cogmap map --distance-scale`: measured by default, a number applied as given."""
    out = tmp_path / "cmd"
    subprocess.run([COGMAP, "map", sim_log, "--distance-scale", "0.98", "-o", str(out)], check=True,
                   capture_output=True)
    with open(out / "report.json") as f:
        cmd_report = json.load(f)
    report = cogmap.map_log(sim_log, str(tmp_path / "py"), distance_scale="0.98")
    assert report["distance_scale"] == cmd_report["distance_scale"] == {"mode": "given", "applied": 0.98}
    measured = cogmap.map_log(sim_log, str(tmp_path / "auto"))["distance_scale"]
    assert measured["mode"] == "auto" and measured["runs"] > 0
    assert cogmap.map_log(sim_log, str(tmp_path / "off"), distance_scale="off")["distance_scale"] is None
    with pytest.raises(Exception, match="--distance-scale"):
        cogmap.map_log(sim_log, str(tmp_path / "bad"), distance_scale="two")


def test_map_log_scan_match_equals_the_command(tmp_path):
    """scan_match="on" is `cogmap map --scan-match on`: a laser's scans correct its odometry first."""
    log = tmp_path / "laser.log"
    subprocess.run([COGMAP, "simulate", os.path.join(SHARED, "worlds", "nine_rooms.map"), "--robot", "laser",
                    "--seed", "2", "--drift-deg-per-m", "2", "-o", str(log)], check=True, capture_output=True)
    out = tmp_path / "cmd"
    subprocess.run([COGMAP, "map", str(log), "--scan-match", "on", "-o", str(out)], check=True, capture_output=True)
    with open(out / "report.json") as f:
        cmd_report = json.load(f)
    report = cogmap.map_log(str(log), str(tmp_path / "py"), scan_match="on")
    assert report["scan_match"] == cmd_report["scan_match"]
    assert report["scan_match"]["matched"] > 0.95 * report["scan_match"]["scans"]
    assert cogmap.map_log(str(log), str(tmp_path / "wheels"), scan_match="off")["scan_match"] is None
    # By default (auto) a laser scanning 10 times a second is dense enough to match.
    auto = cogmap.map_log(str(log), str(tmp_path / "auto"))["scan_match"]
    assert auto["mode"] == "auto" and auto["active"] and auto["decided_mean_step"] <= 1.0
    a = cogmap.open_store(str(out / "map.sqlite"))
    b = cogmap.open_store(str(tmp_path / "py" / "map.sqlite"))
    assert a.ids() == b.ids()


def test_mapper_record_by_record_equals_the_command(sim_log, command_map, tmp_path):
    _, cmd_report = command_map
    log = cogmap.read_log(sim_log)
    closed = []
    m = cogmap.Mapper(str(tmp_path / "stream.sqlite"), robot="pioneer16")
    m.on_asr_closed(closed.append)
    ranges = log["ranges"]
    starts = np.searchsorted(ranges[:, 0], np.arange(len(log["time"]) + 1))
    for k in range(len(log["time"])):
        rk = ranges[starts[k]:starts[k + 1]]
        m.push(log["time"][k], log["odom"][k], [(int(s), float(r)) for _, s, r in rk], truth=log["truth"][k])
    result = m.finish()
    assert result["records"] == cmd_report["records"]
    assert result["asrs"] == cmd_report["asr_count"] == len(closed)
    assert closed == list(range(len(closed)))  # in closing order, on this thread
    assert result["rooms"] == cmd_report["pose_graph"]["rooms"]
    assert result["drift_rate_deg_per_m"] == pytest.approx(cmd_report["pose_graph"]["drift_rate_deg_per_m"], abs=1e-9)
    assert result["drift_rate_sigma_deg_per_m"] == pytest.approx(
        cmd_report["pose_graph"]["drift_rate_sigma_deg_per_m"], abs=1e-9)
    assert result["drift_rate_sigma_deg_per_m"] > 0.0
    assert result["drift_rate_spread_sigma_deg_per_m"] == pytest.approx(
        cmd_report["pose_graph"]["drift_rate_spread_sigma_deg_per_m"], abs=1e-9)
    assert result["drift_rate_spread_sigma_deg_per_m"] >= result["drift_rate_sigma_deg_per_m"]
    assert result["building_directions_deg"] == pytest.approx(cmd_report["pose_graph"]["building_directions_deg"])
    assert result["odometry_heading_fitted_factor"] == cmd_report["pose_graph"]["odometry_heading_fitted_factor"]
    assert result["odometry_heading_held"] == cmd_report["pose_graph"]["odometry_heading_held"]


def test_store_gives_walls_paths_and_rooms(command_map):
    out, cmd_report = command_map
    store = cogmap.open_store(str(out / "map.sqlite"))
    ids = store.ids()
    assert len(ids) == cmd_report["asr_count"]
    x = store.asr(ids[0])
    assert x["pose"].shape == (3,)
    assert x["path"].shape[1] == 3 and x["path"].shape[0] > 10
    assert all(w.ndim == 2 and w.shape[1] == 2 and w.shape[0] >= 2 for w in x["walls"])
    assert store.room_of(ids[0]) == x["room"]
    with pytest.raises(KeyError):
        store.asr(10**6)


def test_evaluate_equals_the_command(command_map):
    out, _ = command_map
    world = os.path.join(SHARED, "worlds", "nine_rooms.map")
    cmd = json.loads(subprocess.run([COGMAP, "eval", str(out), "--world", world, "--json"], check=True,
                                    capture_output=True, text=True).stdout)
    py = cogmap.evaluate(str(out), world=world)
    assert py.keys() == cmd.keys()
    for key in ("wall_precision_p95_m", "wall_recall", "ate_rmse_m", "room_recall", "asr_count"):
        assert py[key] == pytest.approx(cmd[key]), key
    assert py["ate_rmse_m"] < py["ate_rmse_m_raw"]  # the pose graph corrects the 1 deg/m drift


def test_a_bad_log_is_an_input_error_naming_file_and_line(tmp_path):
    bad = tmp_path / "bad.log"
    bad.write_text("# cogmap-log 1\nrobot pioneer16\nODOM 0 0 0 0\nSWEEP 0 1 0 nan\n")
    with pytest.raises(cogmap.InputError) as e:
        cogmap.read_log(str(bad))
    assert "bad.log:4" in str(e.value)
    with pytest.raises(cogmap.InputError):
        cogmap.map_log(str(bad), str(tmp_path / "out"))
    assert not (tmp_path / "out" / "map.sqlite").exists()


def test_options_are_checked():
    with pytest.raises(cogmap.InputError):
        cogmap.robot("no-such-robot")
    with pytest.raises(cogmap.InputError):
        cogmap.Mapper("/tmp/never.sqlite", mode="fast")
    with pytest.raises(cogmap.InputError):
        cogmap.Mapper("/tmp/never.sqlite", threads=3)


def assert_plan_equals_json(plan, j):
    """A floor_plan() dict against plan.json, field by field (exact: the JSON round-trips doubles)."""
    assert len(plan["walls"]) == len(j["walls"])
    for w, jw in zip(plan["walls"], j["walls"]):
        np.testing.assert_array_equal(w["points"], np.array(jw["points"]))
        for key in ("free_on_left", "two_sided", "squared", "weight", "asr_ids"):
            assert w[key] == jw[key], key
    assert plan["wall_segments"].shape == (sum(len(w["points"]) - 1 for w in j["walls"]), 4)
    assert len(plan["rooms"]) == len(j["rooms"])
    for r, jr in zip(plan["rooms"], j["rooms"]):
        np.testing.assert_array_equal(r["polygon"], np.array(jr["polygon"]))
        np.testing.assert_array_equal(r["label"], np.array(jr["label"]))
        for key in ("id", "name", "corridor", "area_m2", "doors", "asr_ids", "graph_rooms"):
            assert r[key] == jr[key], key
    assert len(plan["doors"]) == len(j["doors"])
    for d, jd in zip(plan["doors"], j["doors"]):
        np.testing.assert_array_equal(d["a"], np.array(jd["a"]))
        np.testing.assert_array_equal(d["b"], np.array(jd["b"]))
        assert d["width_m"] == pytest.approx(np.hypot(*(np.array(jd["b"]) - np.array(jd["a"]))))
        for key in ("id", "room_a", "room_b", "from_asr", "to_asr"):
            assert d[key] == jd[key], key
    assert plan["graph"]["nodes"] == [r["id"] for r in j["rooms"]]
    np.testing.assert_array_equal(plan["graph"]["edges"].reshape(-1, 3),
                                  np.array([[e["room_a"], e["room_b"], e["door"]] for e in j["edges"]]).reshape(-1, 3))
    np.testing.assert_array_equal(plan["bounds"], np.array([j["bounds"]["min"], j["bounds"]["max"]]))
    np.testing.assert_array_equal(plan["home"], np.array([j["home"][k] for k in ("x", "y", "theta")]))
    assert plan["dominant_direction_rad"] == j["dominant_direction_rad"]


def test_floor_plan_equals_the_commands_plan_json(command_map):
    out, cmd_report = command_map
    with open(out / "plan.json") as f:
        j = json.load(f)
    assert len(j["rooms"]) >= 5 and len(j["walls"]) > 10 and len(j["edges"]) >= 4  # a real plan
    assert_plan_equals_json(cogmap.floor_plan(str(out)), j)                    # the folder: its plan.json
    assert_plan_equals_json(cogmap.floor_plan(str(out / "plan.json")), j)
    assert_plan_equals_json(cogmap.floor_plan(str(out / "map.sqlite")), j)     # built from the store
    assert_plan_equals_json(cogmap.open_store(str(out / "map.sqlite")).floor_plan(), j)


def test_floor_plan_of_a_folder_without_plan_json_is_built_from_its_store(command_map, tmp_path):
    out, _ = command_map
    (tmp_path / "m").mkdir()
    (tmp_path / "m" / "map.sqlite").write_bytes((out / "map.sqlite").read_bytes())
    with open(out / "plan.json") as f:
        assert_plan_equals_json(cogmap.floor_plan(str(tmp_path / "m")), json.load(f))


def test_floor_plan_errors_name_the_file(tmp_path):
    with pytest.raises(cogmap.InputError) as e:
        cogmap.floor_plan(str(tmp_path))
    assert "no plan.json or map.sqlite" in str(e.value)
    bad = tmp_path / "plan.json"
    bad.write_text('{"format": "cogmap-plan", "version": 1, "walls": 3}')
    with pytest.raises(cogmap.InputError) as e:
        cogmap.floor_plan(str(tmp_path))
    assert "plan.json" in str(e.value)


def test_the_docs_matplotlib_example_runs(sim_log, tmp_path):
    """docs/python.md's first example, on the simulated run: it writes its picture."""
    # Needs Debian's python3-matplotlib (scripts/install-deps.sh).
    doc = open(os.path.join(os.path.dirname(__file__), "..", "..", "docs", "python.md")).read()
    code = doc.split("## Example: map a log and plot it", 1)[1].split("```python", 1)[1].split("```", 1)[0]
    env = dict(os.environ, MPLBACKEND="Agg")
    subprocess.run([sys.executable, "-c", code.replace('"run.log"', repr(sim_log))], cwd=tmp_path, env=env,
                   check=True, capture_output=True)
    png = tmp_path / "plan.png"
    assert png.exists() and png.stat().st_size > 10000
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
