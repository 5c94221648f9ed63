"""What the `cogmap` binary of a build offers: commands and their options.

The suite asks the binary itself (`cogmap CMD --help`) instead of assuming, so
that a metric whose command or option is missing shows as n/a with that reason.
"""
import json
import math
import os
import re
import subprocess


class Cogmap:
    def __init__(self, binary):
        self.binary = binary
        self._help = {}

    def exists(self):
        return os.path.isfile(self.binary) and os.access(self.binary, os.X_OK)

    def help(self, command):
        if command not in self._help:
            if not self.exists():
                self._help[command] = None
            else:
                try:
                    p = subprocess.run([self.binary, command, "--help"], capture_output=True,
                                       text=True, timeout=30)
                    self._help[command] = p.stdout + p.stderr if p.returncode == 0 else None
                except (OSError, subprocess.TimeoutExpired):
                    self._help[command] = None
        return self._help[command]

    def commands(self):
        """The subcommands `cogmap --help` lists."""
        if not hasattr(self, "_commands"):
            self._commands = set()
            if self.exists():
                try:
                    p = subprocess.run([self.binary, "--help"], capture_output=True, text=True,
                                       timeout=30)
                    listing = False
                    for line in p.stdout.splitlines():
                        if line.strip().lower().startswith("subcommands"):
                            listing = True
                        elif listing and line.startswith("  ") and line.strip():
                            self._commands.add(line.split()[0])
                except (OSError, subprocess.TimeoutExpired):
                    pass
        return self._commands

    def has(self, command):
        return command in self.commands() and self.help(command) is not None

    def has_option(self, command, option):
        text = self.help(command)
        return bool(text) and re.search(r"(^|[\s,\[])" + re.escape(option) + r"\b", text) is not None

    def missing_reason(self, command):
        if not self.exists():
            return f"no cogmap binary at {self.binary}"
        return f"`cogmap {command}` is not in this build"


def read_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def parse_json_output(text):
    """The JSON object printed by a command (the last {...} block of stdout)."""
    text = text.strip()
    try:
        return json.loads(text)
    except ValueError:
        pass
    start = text.rfind("\n{")
    while start >= -1:
        try:
            return json.loads(text[start + 1:])
        except ValueError:
            start = text.rfind("\n{", 0, max(start, 0))
            if start < 0:
                break
    return None


def finite(x):
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def lookup(d, *names):
    """First present key among 'names' in d, searching one level of nesting."""
    if not isinstance(d, dict):
        return None
    for n in names:
        if n in d:
            return d[n]
    for v in d.values():
        if isinstance(v, dict):
            for n in names:
                if n in v:
                    return v[n]
    return None
