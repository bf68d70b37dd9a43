#!/usr/bin/python3
"""Fits a Lafortune texel map in blocks on Dask distributed, then merges.

  scripts/dask_fit.py --stack M.csv --out P.exr
      [--scheduler tcp://HOST:8786 | --workers N] [--block B]
      [--clothfit PATH] [--parts-dir D] [--retries R] [-- FIT OPTIONS]

One Dask task per B x B block (`clothfit blocks`) runs
`clothfit fit --model lafortune --stack M.csv --mip --region X0,Y0,B,B
--out D/part_X0_Y0.exr FIT OPTIONS` as a subprocess on a worker; clothfit
writes each part atomically, so a part that exists is complete. Parts already
in D for the same block, stack and options are kept (a run that stopped
resumes). Failed tasks are retried (--retries; a worker that dies is replaced
and its task run again). At the end `clothfit merge` assembles the parts and
fits the levels above the blocks: the same map as one `clothfit fit` of the
whole stack, bit for bit (docs/scale.md).

Without --scheduler, a LocalCluster of N worker processes (one thread each)
runs here. With one, the workers must see the stack, the clothfit executable
and D at the same paths (a shared filesystem). Debian's Dask
(python3-distributed) is for the system Python: run this as
/usr/bin/python3 scripts/dask_fit.py or as the executable.

Exit status: clothfit merge's (0 written, 1 written with texels not
converged, 2 bad input), 1 when a block failed after its retries, 2 on bad
usage.
"""

import argparse
import json
import os
import signal
import subprocess
import sys
import time

# Test hooks (tests/dask_fit_test.sh): the first attempt at block "X0,Y0"
# kills its own worker process mid-task (KILL) or fails (FAIL); a marker file
# in the parts folder makes it the first attempt only.
KILL_ENV = "CLOTHFIT_DASK_TEST_KILL"
FAIL_ENV = "CLOTHFIT_DASK_TEST_FAIL"


def parse_args(argv):
    fit_options = []
    if "--" in argv:
        cut = argv.index("--")
        argv, fit_options = argv[:cut], argv[cut + 1:]
    parser = argparse.ArgumentParser(
        prog="dask_fit.py",
        description="Fit a Lafortune texel map in blocks on Dask, then "
        "merge (docs/scale.md). Fit options go after --.")
    parser.add_argument("--stack", required=True, help="image-stack manifest")
    parser.add_argument("--out", required=True, help="the merged map (.exr)")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--scheduler", help="tcp://HOST:PORT of a running "
                       "dask scheduler")
    where.add_argument("--workers", type=int, default=os.cpu_count() or 1,
                       help="worker processes of a LocalCluster (default: "
                       "the cores)")
    parser.add_argument("--block", type=int, default=64,
                        help="block side in texels, a power of two dividing "
                        "the texture (default 64)")
    parser.add_argument("--clothfit", help="the clothfit executable (default: "
                        "build/apps/clothfit of this repository, else PATH's)")
    parser.add_argument("--parts-dir", help="folder of the parts (default: "
                        "OUT.parts); shared by all workers")
    parser.add_argument("--retries", type=int, default=3,
                        help="runs again of a failed block (default 3)")
    parser.add_argument("--threads", type=int, default=1,
                        help="threads of each clothfit fit (default 1: one "
                        "task per worker thread)")
    args = parser.parse_args(argv)
    if args.workers is not None and args.workers < 1:
        parser.error("--workers must be at least 1")
    if args.retries < 0:
        parser.error("--retries must be >= 0")
    args.fit_options = absolute_init(fit_options)
    return args


def absolute_init(options):
    """--init made absolute, as the part records it (clothfit fit)."""
    out = []
    i = 0
    while i < len(options):
        word = options[i]
        if word == "--init" and i + 1 < len(options):
            out += [word, os.path.abspath(options[i + 1])]
            i += 2
            continue
        if word.startswith("--init="):
            word = "--init=" + os.path.abspath(word[len("--init="):])
        out.append(word)
        i += 1
    return out


def default_clothfit():
    here = os.path.dirname(os.path.abspath(__file__))
    built = os.path.join(os.path.dirname(here), "build", "apps", "clothfit")
    return built if os.access(built, os.X_OK) else "clothfit"


def fit_arguments(fit_options):
    """The fit's options as clothfit fit records them in a part."""
    words = ["--model", "lafortune"]
    if "--mip" not in fit_options:
        words.append("--mip")
    return words + fit_options


def part_record(block, texture, stack, fit_words):
    """What metadata.part of a part of this run holds (clothfit fit)."""
    return {"format": 1, "block": list(block), "texture": list(texture),
            "mip": True, "stack": stack, "fit": fit_words}


def part_is_valid(path, record):
    """Whether the part at path is one of this run: its index (the JSON
    beside it, written atomically as the EXR is) records the same block,
    texture, stack and fit options. The merge checks the EXR itself."""
    try:
        with open(path + ".json", encoding="utf-8") as f:
            part = json.load(f)["metadata"]["part"]
    except (OSError, ValueError, KeyError, TypeError):
        return False
    return os.path.exists(path) and all(
        part.get(key) == value for key, value in record.items())


def fit_block(clothfit, stack, block, part, fit_words, threads, record,
              markers):
    """One Dask task: the part of one block (skipped when it is there)."""
    if part_is_valid(part, record):
        return {"block": block, "status": "kept"}
    where = "%d,%d" % block[:2]
    marker = os.path.join(markers, ".attempted_%d_%d" % block[:2])
    first = not os.path.exists(marker)
    if first and where in (os.environ.get(KILL_ENV), os.environ.get(FAIL_ENV)):
        open(marker, "w").close()
    command = [clothfit, "fit", "--stack", stack,
               "--region", "%d,%d,%d,%d" % block, "--threads", str(threads),
               "--out", part] + fit_words
    child = subprocess.Popen(command, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True)
    if first and os.environ.get(KILL_ENV) == where:
        time.sleep(0.3)  # mid-task
        child.kill()
        os.kill(os.getpid(), signal.SIGKILL)  # the worker dies
    out, err = child.communicate()
    if first and os.environ.get(FAIL_ENV) == where:
        raise RuntimeError("block %s: failed on purpose (%s)" % (where,
                                                                 FAIL_ENV))
    # 1: written, with texels not converged (named on stderr).
    if child.returncode not in (0, 1) or not part_is_valid(part, record):
        raise RuntimeError("block %s: clothfit fit exited %d: %s" % (
            where, child.returncode, err.strip().splitlines()[-1:]))
    return {"block": block, "status": "fitted", "exit": child.returncode,
            "stderr": err.strip()}


def blocks_of(clothfit, stack, block):
    run = subprocess.run([clothfit, "blocks", "--stack", stack, "--block",
                          str(block)], capture_output=True, text=True)
    if run.returncode != 0:
        sys.stderr.write(run.stderr)
        sys.exit(2)
    blocks = [tuple(int(v) for v in line.split(","))
              for line in run.stdout.split()]
    width = max(b[0] + b[2] for b in blocks)
    height = max(b[1] + b[3] for b in blocks)
    return blocks, (width, height)


def main(argv):
    args = parse_args(argv)
    try:
        from distributed import Client, LocalCluster, as_completed
    except ImportError:
        sys.stderr.write("error: dask_fit.py: no module 'distributed' (install "
                         "python3-distributed; run with /usr/bin/python3)\n")
        return 2
    clothfit = os.path.abspath(args.clothfit) if args.clothfit else \
        default_clothfit()
    stack = os.path.normpath(os.path.abspath(args.stack))
    out = os.path.abspath(args.out)
    parts_dir = os.path.abspath(args.parts_dir or out + ".parts")
    os.makedirs(parts_dir, exist_ok=True)
    blocks, texture = blocks_of(clothfit, stack, args.block)
    fit_words = fit_arguments(args.fit_options)

    started = time.monotonic()
    if args.scheduler:
        client = Client(args.scheduler)
    else:
        cluster = LocalCluster(n_workers=args.workers, processes=True,
                               threads_per_worker=1, dashboard_address=None)
        client = Client(cluster)
    parts = []
    futures = []
    for block in blocks:
        part = os.path.join(parts_dir, "part_%d_%d.exr" % block[:2])
        parts.append(part)
        record = part_record(block, texture, stack, fit_words)
        futures.append(client.submit(
            fit_block, clothfit, stack, block, part, fit_words, args.threads,
            record, parts_dir, key="block-%d-%d" % block[:2], pure=False,
            retries=args.retries))
    done = kept = failed = 0
    for future in as_completed(futures):
        try:
            result = future.result()
            kept += result["status"] == "kept"
            if result.get("exit") == 1:
                sys.stderr.write("\ndask_fit: block %s: %s\n" % (
                    ",".join(map(str, result["block"])),
                    result["stderr"].splitlines()[-1]))
        except Exception as error:  # the block's last retry failed
            failed += 1
            sys.stderr.write("\nerror: dask_fit: %s\n" % error)
        done += 1
        sys.stderr.write("\rdask_fit: %d/%d blocks (%d kept from before, %d "
                         "failed) %.0f s" % (done, len(futures), kept, failed,
                                             time.monotonic() - started))
        sys.stderr.flush()
    sys.stderr.write("\n")
    client.close()
    if not args.scheduler:
        cluster.close()
    if failed:
        sys.stderr.write("error: dask_fit: %d block(s) failed; run again to "
                         "fit them (the others are kept)\n" % failed)
        return 1
    fitted = time.monotonic()
    merge = subprocess.run([clothfit, "merge", "--parts", ",".join(parts),
                            "--stack", stack, "--out", out])
    sys.stderr.write("dask_fit: blocks %.1f s, merge %.1f s\n" % (
        fitted - started, time.monotonic() - fitted))
    return merge.returncode


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
