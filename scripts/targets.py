#!/usr/bin/env python3
"""The performance targets (start-up, scale, the paper's workload,
evaluation for renderers) measured in one run, with the peers that run here.

Runs, one after the other, so that the figures share the machine's state:
  startup   scripts/startup.py: clothfit --version and a whole-process
            CUReT Lafortune fit beside `python3 -S -c pass`
  material  material_benchmark: Material::F of the satin preset and of two
            grey Lafortune lobes, double and float (medians of 10
            repetitions, with the coefficient of variation)
  paper     the paper's workload from an image stack (synth --gonio plain
            --texels 32 --directions 8 --stack), fitted with --lobes 2
            --mip on 2 threads, 1 thread and 2 threads again (wall, peak
            memory, level-0 mean relative RMS as printed)
  scale     scripts/scale_rows.py: the thread fit at 5 x 10^6 rows, and at
            10^7 rows the thread, Lafortune and cloth fits and eval
  holes     scripts/holes_scale.sh at 4096^2
and prints each tool's table, then one table of the figures against their
targets. The `before` column is version 0.3's figure on this machine
(measured before the work on these targets), or where it says so, the
same run's clothfit-full (which links the image libraries, as every
command did in 0.3). Takes 30-40 minutes and about
5 GB of disk at its peak (the 10^7-row tables).
Usage:
  python3 scripts/targets.py [--parts startup,material,paper,scale,holes]
      [--build build] [--out DIR] [--runs N] [--paper-texels 32]
Results: docs/bench.md ("Targets in one run").
"""
import argparse
import json
import os
import re
import statistics
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import scale_rows  # noqa: E402  (run: a process's wall time and peak)

PARTS = ["startup", "material", "paper", "scale", "holes"]


def tool(command, env=None):
    """A tool's standard output; its failure ends the run."""
    done = subprocess.run(command, stdout=subprocess.PIPE, text=True,
                          env=env, check=False)
    if done.returncode != 0:
        raise SystemExit("targets: %s exited %d" % (command[0],
                                                    done.returncode))
    return done.stdout


def table_rows(markdown):
    """{first cell: [other cells]} of a Markdown table's body."""
    rows, body = {}, False
    for line in markdown.splitlines():
        if not line.startswith("|"):
            body = False
            continue
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if set(cells[0]) <= set("-"):
            body = True  # the separator under the header
        elif body:
            rows[cells[0]] = cells[1:]
    return rows


def startup(args, out, summary):
    text = tool([sys.executable, os.path.join(ROOT, "scripts", "startup.py"),
                 "--runs", str(args.runs), "--build", args.build])
    out.append("### Start-up\n\n" + text)
    rows = table_rows(text)
    python = float(rows["python3 -S -c pass"][0])
    version = float(rows["clothfit --version"][0])
    fit = float(rows["clothfit fit (CUReT linen, 2 lobes, --no-lut)"][0])
    # clothfit-full links the image libraries, as every command did before.
    full_version = float(rows["clothfit-full --version"][0])
    full_fit = float(rows["clothfit-full fit (the same)"][0])
    summary.append(("`clothfit --version`",
                    "%.1f ms (clothfit-full, this run)" % full_version,
                    "%.1f ms" % version, "< 10 ms", version < 10.0))
    summary.append(("whole-process CUReT Lafortune fit / `python3 -S`",
                    "%.1f ms, %.1fx (clothfit-full, this run)" % (
                        full_fit, full_fit / python),
                    "%.1f ms, %.2fx" % (fit, fit / python), "<= 2x",
                    fit <= 2.0 * python))


def material(args, out, summary):
    binary = os.path.join(args.build, "benchmarks", "material_benchmark")
    text = tool([binary, "--benchmark_filter=MaterialF_(SatinPreset|"
                 "Lafortune2Lobes)", "--benchmark_repetitions=10",
                 "--benchmark_min_time=0.2",
                 "--benchmark_report_aggregates_only=true",
                 "--benchmark_format=json"])
    stats = {}
    for b in json.loads(text)["benchmarks"]:
        name, kind = b["run_name"], b.get("aggregate_name")
        stats.setdefault(name, {})[kind] = b["items_per_second"]
    lines = ["| benchmark | median M/s | cv |", "|---|---|---|"]
    for name, s in stats.items():
        lines.append("| %s | %.2f | %.1f %% |" % (
            name, s["median"] / 1e6, 100.0 * s["stddev"] / s["mean"]))
    out.append("### Material::F (one core)\n\n" + "\n".join(lines) + "\n")
    for name, before, target in (
            ("BM_MaterialF_SatinPreset", "1.15 M/s", 3e6),
            ("BM_MaterialF_SatinPreset_Float", "", 3e6),
            ("BM_MaterialF_Lafortune2Lobes", "11 M/s", 20e6),
            ("BM_MaterialF_Lafortune2Lobes_Float", "", 20e6)):
        rate = stats[name]["median"]
        summary.append(("`%s`" % name, before, "%.2f M/s" % (rate / 1e6),
                        ">= %g M/s" % (target / 1e6), rate >= target))


def paper(args, out, summary):
    clothfit = os.path.join(args.build, "apps", "clothfit")
    stack = os.path.join(args.out, "paper_%d" % args.paper_texels, "M.csv")
    if not os.path.exists(stack):
        os.makedirs(os.path.dirname(stack), exist_ok=True)
        tool([clothfit, "synth", "--gonio", "plain", "--texels",
              str(args.paper_texels),
              "--directions", "8", "--stack", stack, "--quiet"])
    lines = ["| threads | wall s | peak MiB | level-0 mean relative RMS | "
             "status |", "|---|---|---|---|---|"]
    walls, peaks = {1: [], 2: []}, []
    for threads in (2, 1, 2):
        log = os.path.join(os.path.dirname(stack), "fit_%d.log" % threads)
        wall, peak, status = scale_rows.run(
            [clothfit, "fit", "--model", "lafortune", "--lobes", "2", "--mip",
             "--stack", stack, "--threads", str(threads), "--out",
             os.path.join(os.path.dirname(stack), "P.exr")], 3600, log)
        with open(log) as f:
            text = f.read()
        # The fit's summary: "level 0: 32x32, ..., mean relative rms R".
        match = re.search(r"level 0:[^\n]*?mean relative rms ([0-9.]+)",
                          text)
        rms = match.group(1) if match else "?"
        walls[threads].append(wall)
        peaks.append(peak)
        lines.append("| %d | %.1f | %.0f | %s | %s |" % (
            threads, wall, peak, rms, status))
    out.append("### The paper's workload (%d x %d texels, 64 x 64 "
               "directions, K = 2, --mip)\n\n" % (
                   args.paper_texels, args.paper_texels) +
               "\n".join(lines) + "\n")
    two, peak = statistics.median(walls[2]), max(peaks)
    name = "the paper's workload" if args.paper_texels == 32 else (
        "a %d x %d-texel workload (not the paper's)" % (args.paper_texels,
                                                        args.paper_texels))
    summary.append((name + ", 2 threads", "44-46 s (CSV)",
                    "%.1f s, %.0f MiB" % (two, peak), "< 20 s, < 1 GB",
                    two < 20.0 and peak * 1024 * 1024 < 1e9))
    speedup = walls[1][0] / two
    summary.append(("the same, 1 to 2 threads", "", "%.2fx" % speedup,
                    ">= 1.8x", speedup >= 1.8))


def scale(args, out, summary):
    script = os.path.join(ROOT, "scripts", "scale_rows.py")
    text = ""
    for rows, jobs in (("5000000", "thread"),
                       ("10000000", "thread,lafortune,eval,cloth")):
        text += tool([sys.executable, script, "--rows", rows, "--jobs", jobs,
                      "--timeout", "900", "--build", args.build, "--out",
                      os.path.join(args.out, "scale_" + rows)])
    for rows in ("5000000", "10000000"):  # eval's output: 1.3 GB at 10^7
        path = os.path.join(args.out, "scale_" + rows, "eval.csv")
        if os.path.exists(path):
            os.remove(path)
    out.append("### Scale\n\n```\n" + text + "```\n")
    befores = {("thread", 5000000): "> 200 s, 7.4 GB (3 iterations: 115 s)",
               ("thread", 10000000): "", ("lafortune", 10000000):
               "37 s, 6.0 GB", ("eval", 10000000): "39 s, 4.1 GB",
               ("cloth", 10000000): ""}
    for line in text.splitlines():
        m = re.match(r"(\w+)\s+(\d+) rows:\s+([0-9.]+) s,\s+([0-9.]+) MiB, "
                     r"(.*)", line)
        if not m:
            continue
        job, rows, wall, peak = m.group(1), int(m.group(2)), float(
            m.group(3)), float(m.group(4))
        # A run stopped at the timeout has no figure (exit 1, a fit that
        # did not converge, has).
        ended = m.group(5) != "timeout"
        now = "%.1f s, %.0f MiB%s" % (wall, peak, "" if ended else
                                      " (stopped: timeout)")
        if rows == 5000000:
            summary.append(("thread fit, 5 x 10^6 rows", befores[(job, rows)],
                            now, "< 60 s", ended and wall < 60.0))
        else:
            summary.append(("%s, 10^7 rows" % job, befores[(job, rows)], now,
                            "< 2 GB", ended and peak * 1024 * 1024 < 2e9))


def holes(args, out, summary):
    env = dict(os.environ, SIZES="4096", RUNS=str(min(args.runs, 3)),
               BUILD_DIR=args.build)
    text = tool(["bash", os.path.join(ROOT, "scripts", "holes_scale.sh")],
                env=env)
    out.append("### holes analyze --distances\n\n" + text)
    # | 4096^2 | BUILD | wall median (min-max) | peak MiB median (min-max) |
    for cells in table_rows(text).values():
        if len(cells) >= 3:
            peak = float(cells[2].split()[0])
            summary.append(("`holes analyze --distances`, 4096^2",
                            "51 s, 8.5 GB", "%s s, %.0f MiB" % (
                                cells[1].split()[0], peak), "< 2 GB",
                            peak * 1024 * 1024 < 2e9))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--parts", default=",".join(PARTS))
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--out", default=os.path.join(
        ROOT, "data_synthetic", "out", "targets"))
    parser.add_argument("--paper-texels", type=int, default=32,
                        help="the paper's workload: 32 x 32 texels; "
                        "fewer for a quick check of the script")
    parser.add_argument("--runs", type=int, default=20,
                        help="start-up runs per command (holes: up to 3)")
    args = parser.parse_args()
    parts = args.parts.split(",")
    unknown = [p for p in parts if p not in PARTS]
    if unknown:
        raise SystemExit("targets: unknown part %s (parts: %s)"
                         % (unknown[0], ",".join(PARTS)))
    os.makedirs(args.out, exist_ok=True)
    out, summary = [], []
    for part in PARTS:
        if part in parts:
            print("targets: %s ..." % part, file=sys.stderr, flush=True)
            globals()[part](args, out, summary)
    print("\n".join(out))
    print("### Against the targets\n")
    print("| figure | before | now | target | met |")
    print("|---|---|---|---|---|")
    for name, before, now, target, met in summary:
        print("| %s | %s | %s | %s | %s |" % (name, before or "-", now,
                                             target, "yes" if met else "no"))


if __name__ == "__main__":
    main()
