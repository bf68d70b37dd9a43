#!/usr/bin/env python3
"""Time and peak memory of clothfit's fits against the rows of a table.

For each row count (10^3, 10^4, ... up to --max-rows) it writes a synthetic
table (`clothfit synth`, 1 % noise, sigma column dropped so that the fits
use their default relative noise) and times, one process each:
  thread     fit --model thread (default settings)
  lafortune  fit --model lafortune --lobes 2 --no-lut
  eval       eval --params (the thread's parameters) --dirs (the table)
  cloth      fit --model cloth --preset linen_plain (default settings) on
             a table of its own, synthesised from that preset the same way
Wall time and the process's peak resident memory (os.wait4) go to
DIR/scale_rows.csv, and DIR/scale_rows.svg draws both against the rows on
log axes with the slope of the last two points of each line. A run that
takes longer than --timeout seconds is stopped and recorded as such.
Usage:
  python3 scripts/scale_rows.py [--max-rows 1000000] [--timeout 600]
      [--build build] [--out DIR] [--jobs thread,lafortune,eval,cloth]
      [--rows 5000000,10000000]
Results: docs/reliability.md ("Scale").
"""
import argparse
import csv
import math
import os
import signal
import subprocess
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
THREAD = ('{"model": "thread", "eta": 1.55, "kd": 0.3, "gamma_s_deg": 8, '
          '"gamma_v_deg": 20, "albedo": [0.4, 0.3, 0.2]}\n')


def run(command, timeout, output=None):
    """(wall s, peak MiB, status) of one process; status 'timeout' if it
    ran past `timeout` and was killed. Its standard output and error go
    to the file `output` (a path), or nowhere."""
    start = time.monotonic()
    sink = open(output, "w") if output else subprocess.DEVNULL
    try:
        proc = subprocess.Popen(command, stdout=sink,
                                stderr=subprocess.STDOUT if output
                                else subprocess.DEVNULL)
    finally:
        if output:
            sink.close()
    status = None
    while True:
        pid, code, usage = os.wait4(proc.pid, os.WNOHANG)
        if pid != 0:
            status = "exit %d" % os.waitstatus_to_exitcode(code)
            break
        if time.monotonic() - start > timeout:
            proc.send_signal(signal.SIGKILL)
            pid, code, usage = os.wait4(proc.pid, 0)
            status = "timeout"
            break
        time.sleep(0.05)
    proc.returncode = code  # reaped by wait4
    return time.monotonic() - start, usage.ru_maxrss / 1024.0, status


def drop_sigma(src, dst):
    """The table without its sigma columns (theta_i..b are the first 7)."""
    with open(src) as f, open(dst, "w") as g:
        for line in f:
            if line.startswith("#"):
                g.write(line)
            else:
                g.write(",".join(line.rstrip("\n").split(",")[:7]) + "\n")


def svg(rows, path):
    """Two log-log panels (wall s, peak MiB) against rows, a line per job."""
    colours = {"thread": "#1f77b4", "lafortune": "#d62728", "eval": "#2ca02c",
               "cloth": "#9467bd"}
    width, height, margin = 460, 340, 60
    out = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" '
           'font-family="sans-serif" font-size="12">' % (2 * width, height)]
    for panel, (key, label) in enumerate([("wall_s", "wall time [s]"),
                                          ("peak_mib", "peak memory [MiB]")]):
        # Runs that ended (exit 1: a fit that did not converge) count.
        ok = [r for r in rows if r["status"] != "timeout"]
        if not ok:
            continue
        xs = [math.log10(r["rows"]) for r in ok]
        ys = [math.log10(max(r[key], 1e-3)) for r in ok]
        x0, x1 = math.floor(min(xs)), math.ceil(max(xs))
        y0, y1 = math.floor(min(ys)), math.ceil(max(ys))
        x1, y1 = max(x1, x0 + 1), max(y1, y0 + 1)
        left = panel * width + margin
        px = lambda v: left + (v - x0) / (x1 - x0) * (width - 1.5 * margin)
        py = lambda v: height - margin - (v - y0) / (y1 - y0) * (
            height - 1.8 * margin)
        out.append('<text x="%d" y="20" font-weight="bold">%s against rows '
                   '(log-log)</text>' % (left, label))
        for d in range(x0, x1 + 1):
            out.append('<line x1="%.1f" y1="%.1f" x2="%.1f" y2="%.1f" '
                       'stroke="#ddd"/>' % (px(d), py(y0), px(d), py(y1)))
            out.append('<text x="%.1f" y="%d" text-anchor="middle">1e%d'
                       '</text>' % (px(d), height - margin + 16, d))
        for d in range(y0, y1 + 1):
            out.append('<line x1="%.1f" y1="%.1f" x2="%.1f" y2="%.1f" '
                       'stroke="#ddd"/>' % (px(x0), py(d), px(x1), py(d)))
            out.append('<text x="%.1f" y="%.1f" text-anchor="end">1e%d'
                       '</text>' % (px(x0) - 4, py(d) + 4, d))
        out.append('<text x="%.1f" y="%d" text-anchor="middle">rows</text>'
                   % ((px(x0) + px(x1)) / 2, height - 12))
        legend = 0
        for job, colour in colours.items():
            pts = [(math.log10(r["rows"]), math.log10(max(r[key], 1e-3)))
                   for r in ok if r["job"] == job]
            if not pts:
                continue
            out.append('<polyline fill="none" stroke="%s" stroke-width="2" '
                       'points="%s"/>' % (colour, " ".join(
                           "%.1f,%.1f" % (px(a), py(b)) for a, b in pts)))
            slope = ""
            if len(pts) >= 2:
                (a0, b0), (a1, b1) = pts[-2], pts[-1]
                slope = ", slope %.2f" % ((b1 - b0) / (a1 - a0))
            out.append('<text x="%.1f" y="%d" fill="%s">%s%s</text>'
                       % (px(x0) + 6, 40 + 15 * legend, colour, job, slope))
            legend += 1
    out.append("</svg>")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--max-rows", type=int, default=1000000)
    parser.add_argument("--timeout", type=float, default=600.0)
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--out", default=os.path.join(
        ROOT, "data_synthetic", "out", "scale_rows"))
    parser.add_argument("--jobs", default="thread,lafortune,eval,cloth")
    parser.add_argument("--rows", default="",
                        help="comma-separated row counts, in place of "
                        "the powers of ten up to --max-rows")
    args = parser.parse_args()
    clothfit = os.path.join(args.build, "apps", "clothfit")
    jobs = args.jobs.split(",")
    os.makedirs(args.out, exist_ok=True)
    params = os.path.join(args.out, "thread.json")
    with open(params, "w") as f:
        f.write(THREAD)
    rows_list = []
    n = 1000
    while n <= args.max_rows:
        rows_list.append(n)
        n *= 10
    if args.rows:
        try:
            rows_list = [int(r) for r in args.rows.split(",")]
        except ValueError:
            parser.error("--rows: comma-separated row counts, got %r"
                         % args.rows)
        if min(rows_list) < 1:
            parser.error("--rows: row counts must be >= 1")
    results = []
    for n in rows_list:
        full = os.path.join(args.out, "t%d_sigma.csv" % n)
        table = os.path.join(args.out, "t%d.csv" % n)
        cloth_table = os.path.join(args.out, "c%d.csv" % n)
        for source, out in ((["--params", params], table),
                            (["--preset", "linen_plain"], cloth_table)):
            if out == cloth_table and "cloth" not in jobs:
                continue
            subprocess.run([clothfit, "synth"] + source + [
                "--rows", str(n), "--noise", "0.01", "--seed", "7", "--out",
                full], check=True, stdout=subprocess.DEVNULL)
            drop_sigma(full, out)
            os.remove(full)
        commands = {
            "thread": [clothfit, "fit", "--model", "thread", "--data", table,
                       "--out", os.path.join(args.out, "thread_fit.json")],
            "lafortune": [clothfit, "fit", "--model", "lafortune", "--lobes",
                          "2", "--no-lut", "--data", table, "--out",
                          os.path.join(args.out, "lafortune_fit.json")],
            "eval": [clothfit, "eval", "--params", params, "--dirs", table,
                     "--out", os.path.join(args.out, "eval.csv")],
            "cloth": [clothfit, "fit", "--model", "cloth", "--preset",
                      "linen_plain", "--data", cloth_table, "--out",
                      os.path.join(args.out, "cloth_fit.json")],
        }
        for job in jobs:
            wall, peak, status = run(commands[job], args.timeout)
            results.append({"job": job, "rows": n, "wall_s": wall,
                            "peak_mib": peak, "status": status})
            print("%-9s %9d rows: %8.2f s, %7.0f MiB, %s"
                  % (job, n, wall, peak, status), flush=True)
        os.remove(table)
        if os.path.exists(cloth_table):
            os.remove(cloth_table)
    with open(os.path.join(args.out, "scale_rows.csv"), "w",
              newline="") as f:
        writer = csv.DictWriter(f, ["job", "rows", "wall_s", "peak_mib",
                                    "status"])
        writer.writeheader()
        writer.writerows(results)
    svg(results, os.path.join(args.out, "scale_rows.svg"))
    print("wrote %s" % os.path.join(args.out, "scale_rows.svg"))


if __name__ == "__main__":
    main()
