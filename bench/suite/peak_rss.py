"""The peak resident memory of one command, measured so that the launcher's
own memory does not leak into it.

Linux keeps a process's peak resident set across exec: a command started
from Python (fork or vfork, then exec) reports at least the Python process's
resident set in wait4's ru_maxrss. A bench process holding its results at
38 MiB made a 28 MiB `cogmap map` read 38 MiB. GNU time (Debian `time`)
forks from its own small image and writes the child's ru_maxrss to a file, so
commands are started through it when it is installed; without it the figure
falls back to wait4's (an upper bound) and `exact` says so.
"""
import os
import tempfile

TIME = "/usr/bin/time"


def exact():
    """True when peaks are measured through GNU time."""
    return os.access(TIME, os.X_OK)


class Measured:
    """Wraps argv so that its peak resident set is measured on its own.

        m = Measured(argv)
        p = subprocess.Popen(m.argv, start_new_session=True, ...)
        _, status, usage = os.wait4(p.pid, 0)
        kib = m.peak_kib(usage.ru_maxrss)

    Start the command in a session of its own and kill the process group
    (os.killpg) to stop it: a kill of GNU time alone leaves the command.
    """

    def __init__(self, argv):
        argv = [str(a) for a in argv]
        self._path = None
        if exact():
            fd, self._path = tempfile.mkstemp(prefix="cogmap-peak-", suffix=".txt")
            os.close(fd)
            self.argv = [TIME, "-q", "-f", "%M", "-o", self._path, "--"] + argv
        else:
            self.argv = argv

    def peak_kib(self, wait4_maxrss_kib):
        """The command's own peak (KiB); wait4's figure when GNU time gave none."""
        if self._path is None:
            return wait4_maxrss_kib
        try:
            with open(self._path) as f:
                lines = [l.strip() for l in f if l.strip()]
            # GNU time writes "Command exited with non-zero status N" (or
            # "terminated by signal") before the figure when the command fails.
            return int(lines[-1]) if lines and lines[-1].isdigit() else wait4_maxrss_kib
        except OSError:
            return wait4_maxrss_kib
        finally:
            try:
                os.unlink(self._path)
            except OSError:
                pass
