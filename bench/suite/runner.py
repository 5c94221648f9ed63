"""Runs the suite's jobs on a small process pool and measures each command.

A job is a list of steps (commands) run in order; a step that fails ends its job
and the failure (exit status and the last line of stderr) is kept as the reason
that the job's metrics are n/a. Every command is timed (wall clock) and its peak
resident memory taken from the kernel: ru_maxrss in KiB, of the command alone
through GNU time (suite/peak_rss.py: wait4 on a child of this Python process
would report this process's memory as the floor).
"""
import concurrent.futures
import dataclasses
import os
import re
import subprocess
import threading
import time

from . import peak_rss


@dataclasses.dataclass
class StepResult:
    argv: list
    returncode: int
    wall_s: float
    user_s: float
    sys_s: float
    maxrss_kib: int
    stdout: str
    stderr: str

    @property
    def ok(self):
        return self.returncode == 0

    def reason(self):
        """A one-line reason for a failed step (for the n/a cells)."""
        lines = [l for l in self.stderr.strip().splitlines() if l.strip()]
        last = lines[-1].strip() if lines else ""
        name = " ".join(os.path.basename(a) if i == 0 else a for i, a in enumerate(self.argv[:2]))
        if self.returncode == 124:
            return f"`{name}` timed out"
        # Folders differ from run to run; keep the file name so that one
        # reason covers every run it applies to.
        last = re.sub(r"(/[^\s:/]+)+/", "…/", last)
        return f"`{name}` exited {self.returncode}: {last[:160]}"


def run_command(argv, cwd=None, timeout_s=None, env=None):
    """Runs argv, returns a StepResult with wall time and peak memory."""
    start = time.monotonic()
    out_path = None
    measured = peak_rss.Measured(argv)
    with subprocess.Popen(measured.argv, cwd=cwd, env=env, stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, text=True, errors="replace",
                          start_new_session=True) as p:
        # Drain the pipes on threads so that wait4 (which gives us rusage) can
        # own the child's exit status.
        chunks = {"out": [], "err": []}

        def drain(stream, key):
            for line in stream:
                chunks[key].append(line)

        threads = [threading.Thread(target=drain, args=(p.stdout, "out"), daemon=True),
                   threading.Thread(target=drain, args=(p.stderr, "err"), daemon=True)]
        for t in threads:
            t.start()
        timer = None
        timed_out = []
        if timeout_s:
            def kill():
                timed_out.append(True)
                try:
                    os.killpg(p.pid, 9)  # GNU time and the command under it
                except ProcessLookupError:
                    pass
            timer = threading.Timer(timeout_s, kill)
            timer.start()
        _, status, usage = os.wait4(p.pid, 0)
        if timer:
            timer.cancel()
        p.returncode = os.waitstatus_to_exitcode(status)
        for t in threads:
            t.join()
    wall = time.monotonic() - start
    rc = 124 if timed_out else p.returncode
    return StepResult(list(map(str, argv)), rc, wall, usage.ru_utime, usage.ru_stime,
                      measured.peak_kib(usage.ru_maxrss), "".join(chunks["out"]), "".join(chunks["err"]))


@dataclasses.dataclass
class Job:
    """A named list of steps. 'run' is called in a worker thread with the job
    and returns a dict of results (anything JSON-serialisable)."""
    name: str
    kind: str
    params: dict
    run: callable
    cost: float = 1.0  # rough relative cost, for scheduling the longest first


def run_jobs(jobs, workers, progress=None):
    """Runs jobs on 'workers' threads, each driving one child process at a time
    (so at most 'workers' commands run at once). Longest jobs start first.
    Returns {job.name: result dict}."""
    results = {}
    ordered = sorted(jobs, key=lambda j: -j.cost)
    done = [0]
    lock = threading.Lock()

    def one(job):
        t0 = time.monotonic()
        try:
            res = job.run(job)
        except Exception as e:  # a bug in a job must not stop the suite
            res = {"error": f"suite error: {type(e).__name__}: {e}"}
        res.setdefault("job_wall_s", time.monotonic() - t0)
        with lock:
            done[0] += 1
            if progress:
                progress(done[0], len(ordered), job, res)
        return job.name, res

    with concurrent.futures.ThreadPoolExecutor(max_workers=workers) as ex:
        for name, res in ex.map(one, ordered):
            results[name] = res
    return results
