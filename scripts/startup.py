#!/usr/bin/env python3
"""Start-up time of clothfit, side by side with Python's (issue: small jobs).

Runs each command N times, round-robin (so that the machine's load falls on
all of them alike), and prints the median wall time with the 10th-90th
percentile spread, in milliseconds. Usage:
  python3 scripts/startup.py [--runs N] [--build build] [--data CURET.csv]
Results: docs/bench.md ("Start-up").
"""
import argparse
import os
import statistics
import subprocess
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=30)
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument(
        "--data",
        default=os.path.join(ROOT, "..", "shared", "data", "curet",
                             "curet_44_linen.csv"))
    args = parser.parse_args()
    light = os.path.join(args.build, "apps", "clothfit")
    full = os.path.join(args.build, "apps", "clothfit-full")
    out = os.path.join(tempfile.mkdtemp(prefix="clothfit_startup_"), "p.json")
    fit = ["fit", "--model", "lafortune", "--lobes", "2", "--no-lut",
           "--data", args.data, "--out", out]
    commands = [
        ("python3 -S -c pass", ["python3", "-S", "-c", "pass"]),
        ("clothfit --version", [light, "--version"]),
        ("clothfit-full --version", [full, "--version"]),
        ("clothfit fit (CUReT linen, 2 lobes, --no-lut)", [light] + fit),
        ("clothfit-full fit (the same)", [full] + fit),
    ]
    times = {name: [] for name, _ in commands}
    for _ in range(args.runs):
        for name, command in commands:
            start = time.perf_counter()
            done = subprocess.run(command, stdout=subprocess.DEVNULL,
                                  stderr=subprocess.DEVNULL)
            times[name].append((time.perf_counter() - start) * 1e3)
            if done.returncode not in (0, 1):
                raise SystemExit(f"startup: {name} exited {done.returncode}")
    print(f"| command | median ms | 10-90 % ms | runs |")
    print(f"|---|---|---|---|")
    for name, _ in commands:
        t = sorted(times[name])
        q = statistics.quantiles(t, n=10)
        print(f"| {name} | {statistics.median(t):.1f} | "
              f"{q[0]:.1f}-{q[-1]:.1f} | {len(t)} |")


if __name__ == "__main__":
    main()
