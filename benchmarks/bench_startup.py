"""Start-up of the command line: whole commands timed beside ``python -c pass`` (``make bench``).

Goals (issue "A layout that shows the model"): ``fingerpad --help`` and ``fingerpad textures``
under 0.3 s, a 64^2 ``fingerpad solve`` under 1 s, whole command, on the 2-core development
machine. Each command runs ``--repeats`` times after one warm-up (which fills the OS file cache
and Numba's on-disk cache); the median and the minimum are reported with the interpreter's own
start-up measured in the same run, so a loaded machine shows as a larger baseline.
"""

from __future__ import annotations

import argparse
import resource
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path

SOLVE = ["solve", "--texture", "caps", "--radius", "50um", "--height", "10um", "--spacing", "100um",
         "--grid", "64", "--pressure", "20kPa"]


def _exe() -> list[str]:
    script = Path(sys.executable).with_name("fingerpad")
    if script.exists():
        return [str(script)]
    found = shutil.which("fingerpad")
    return [found] if found else [sys.executable, "-c", "from fingerpad.cli import main; main()"]


def _cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def _time(cmd: list[str], repeats: int) -> tuple[float, float, float]:
    """Median and minimum wall-clock seconds, and median CPU seconds (user + system) of ``cmd``.

    CPU seconds are the robust figure on a shared machine: other work stretches the wall clock,
    not the work the command itself does.
    """
    subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)  # warm-up
    seconds, cpu = [], []
    for _ in range(repeats):
        c0, t0 = _cpu(), time.perf_counter()
        proc = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, check=False)
        seconds.append(time.perf_counter() - t0)
        cpu.append(_cpu() - c0)
        if proc.returncode != 0:
            raise SystemExit(f"{' '.join(cmd)} failed: {proc.stderr.decode()[-500:]}")
    return statistics.median(seconds), min(seconds), statistics.median(cpu)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=7)
    args = parser.parse_args()
    exe = _exe()
    rows = [
        ("python -c pass", [sys.executable, "-c", "pass"], None),
        ("fingerpad --help", [*exe, "--help"], 0.3),
        ("fingerpad textures", [*exe, "textures"], 0.3),
        ("fingerpad solve (64^2 caps)", [*exe, *SOLVE], 1.0),
    ]
    load = Path("/proc/loadavg").read_text().split()[0] if Path("/proc/loadavg").exists() else "?"
    print(f"load average {load} on {__import__('os').cpu_count()} cores; {args.repeats} runs each after a warm-up")
    print(f"{'command':32s} {'median s':>9s} {'min s':>7s} {'cpu s':>7s} {'goal s':>7s}  {'x python':>8s}")
    base = None
    for label, cmd, goal in rows:
        med, low, cpu = _time(cmd, args.repeats)
        base = base or med
        goal_text = f"{goal:.1f}" if goal else "-"
        print(f"{label:32s} {med:9.3f} {low:7.3f} {cpu:7.3f} {goal_text:>7s}  {med / base:8.1f}")


if __name__ == "__main__":
    main()
