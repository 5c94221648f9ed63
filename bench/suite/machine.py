"""The machine and the commit a benchmark run came from."""
import os
import platform
import subprocess


def _cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def _cpu_mhz():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("cpu MHz"):
                    return float(line.split(":", 1)[1])
    except (OSError, ValueError):
        pass
    return None


def _mem_total_gib():
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemTotal:"):
                    return int(line.split()[1]) / (1024 * 1024)
    except (OSError, ValueError):
        pass
    return None


def _git(source_dir, *args):
    try:
        return subprocess.run(["git", "-C", source_dir, *args], capture_output=True, text=True,
                              check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return None


def describe(source_dir):
    commit = _git(source_dir, "rev-parse", "HEAD")
    dirty = _git(source_dir, "status", "--porcelain", "--untracked-files=no")
    return {
        "nproc": os.cpu_count(),
        "cpu_model": _cpu_model(),
        "cpu_mhz": _cpu_mhz(),
        "mem_total_gib": round(_mem_total_gib() or 0, 1),
        "os": platform.platform(),
        "python": platform.python_version(),
        "commit": commit,
        "commit_subject": _git(source_dir, "log", "-1", "--format=%s"),
        # Tracked files modified in the checkout when the suite ran.
        "dirty": bool(dirty),
    }
