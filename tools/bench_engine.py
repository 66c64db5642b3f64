#!/usr/bin/env python3
"""sylva's engine against ninja on equivalent N-node graphs (issue 11; docs/performance.md).

For each N, both tools get N independent actions, each reading one small input file and writing
one output: sylva a recipe of N `import` nodes (a 3-node skeleton text -> tree.sylt), ninja a
build.ninja of N `cp` edges. Rows: start-up, cold build, no-op, one input changed, bytes written
per node, and (if built) the default recipe's no-op. Each timed row is the median of --runs runs
of the whole process: wall time and CPU time (user + sys, from getrusage of the children).

  tools/bench_engine.py --sylva out/build/app/sylva [--sizes 1,100,1000,10000] [--runs 7]
"""
import argparse
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time


def run(cmd, cwd):
    """Runs cmd (output discarded); returns (wall s, CPU s = user + sys of it and its children).
    stderr goes to a temporary file, not a pipe: a cold build of 10,000 nodes logs more than a
    pipe holds, and a pipe read only after wait4 would block the build forever."""
    with tempfile.TemporaryFile() as errf:
        t0 = time.perf_counter()
        p = subprocess.Popen(cmd, cwd=cwd, stdout=subprocess.DEVNULL, stderr=errf)
        _, status, usage = os.wait4(p.pid, 0)
        wall = time.perf_counter() - t0
        p.returncode = os.waitstatus_to_exitcode(status)
        if p.returncode != 0:
            errf.seek(0)
            sys.exit("failed (%d): %s\n%s" % (p.returncode, " ".join(cmd), errf.read().decode(errors="replace")))
    return wall, usage.ru_utime + usage.ru_stime, 0


def bytes_written(cmd, cwd):
    """Bytes cmd and its children passed to write() (wchar): a shell reports its own
    /proc/self/io after reaping cmd, and a reaped child's counts are added to its parent's."""
    script = '"$@" >/dev/null 2>/dev/null || exit $?; cat /proc/$$/io'
    p = subprocess.run(["sh", "-c", script, "sh"] + cmd, cwd=cwd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit("failed (%d): %s" % (p.returncode, " ".join(cmd)))
    for line in p.stdout.splitlines():
        if line.startswith("wchar:"):
            return int(line.split()[1])
    return 0


def median_of(runs, fn):
    walls, cpus = [], []
    for i in range(runs):
        w, c, _ = fn(i)
        walls.append(w)
        cpus.append(c)
    return statistics.median(walls), statistics.median(cpus)


def skeleton(i, variant=0):
    # Distinct per node, so every node is its own action (no two share a cache entry).
    r = 0.2 + i * 1e-7 + variant * 1e-9  # variants 1..99 stay apart from the next node
    return "0 -1 0 0 0 %.9f\n0 -1 0 1 0 0.16\n0 -1 0 2.5 0 0.12\n" % r


def make_graph(root, n):
    os.makedirs(os.path.join(root, "in"))
    with open(os.path.join(root, "recipe.yaml"), "w") as y, open(os.path.join(root, "build.ninja"), "w") as nj:
        y.write("version: 1\nname: bench\nnodes:\n")
        nj.write("rule cp\n  command = cp $in $out\n")
        for i in range(n):
            with open(os.path.join(root, "in", "%d.skel" % i), "w") as f:
                f.write(skeleton(i))
            y.write("  t%d:\n    stage: import\n    with: { file: in/%d.skel }\n" % (i, i))
            nj.write("build out/%d.skel: cp in/%d.skel\n" % (i, i))
    # Both tools see files older than their first run (no racy-timestamp effects in either).
    old = time.time() - 10
    for dirpath, _, files in os.walk(root):
        for f in files:
            os.utime(os.path.join(dirpath, f), (old, old))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sylva", required=True)
    ap.add_argument("--ninja", default=shutil.which("ninja") or "ninja")
    ap.add_argument("--sizes", default="1,100,1000,10000")
    ap.add_argument("--runs", type=int, default=7)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--default-recipe", default="configs/default.yaml",
                    help="recipe whose no-op is measured if it was built into --default-out (skipped otherwise)")
    ap.add_argument("--default-out", default="out")
    ap.add_argument("--keep", action="store_true", help="keep the generated graphs")
    a = ap.parse_args()
    sylva = os.path.abspath(a.sylva)
    ninja = a.ninja
    work = tempfile.mkdtemp(prefix="sylva-bench-")
    rows = []  # (row, sylva (wall, cpu), ninja (wall, cpu) or None, goal)

    def row(name, s, n, goal=""):
        rows.append((name, s, n, goal))
        ratio = "%.1fx" % (s[0] / n[0]) if n else ""
        print("%-34s sylva %8.4f s wall %8.4f s cpu   ninja %s   %s" %
              (name, s[0], s[1], ("%8.4f s wall %8.4f s cpu" % n) if n else "-", ratio), file=sys.stderr)

    try:
        row("start-up (--help / --version)",
            median_of(a.runs, lambda i: run([sylva, "--help"], work)),
            median_of(a.runs, lambda i: run([ninja, "--version"], work)), "<= 10 ms")
        for n in [int(x) for x in a.sizes.split(",")]:
            d = os.path.join(work, "n%d" % n)
            make_graph(d, n)
            sy = [sylva, "--out", "out", "build", "recipe.yaml", "-j", str(a.jobs)]
            nj = [ninja, "-j", str(a.jobs)]
            w, c, _ = run(sy, d)
            w2, c2, _ = run(nj, d)
            row("cold build, N=%d" % n, (w, c), (w2, c2))
            # Bytes per node of a second cold build (fresh outputs and cache; same inputs).
            shutil.rmtree(os.path.join(d, "out"))
            for f in (".ninja_log", ".ninja_deps"):
                if os.path.exists(os.path.join(d, f)):
                    os.remove(os.path.join(d, f))
            bytes_rows = (bytes_written(sy, d) / n, bytes_written(nj, d) / n)
            noop_goal = {1: "<= 20 ms", 10000: "<= 0.3 s"}.get(n, "")
            row("no-op, N=%d" % n, median_of(a.runs, lambda i: run(sy, d)),
                median_of(a.runs, lambda i: run(nj, d)), (noop_goal + "; " if noop_goal else "") + "<= 3x ninja")
            victim = os.path.join(d, "in", "%d.skel" % (n // 2))

            def change(variant, cmd):
                with open(victim, "w") as f:
                    f.write(skeleton(n // 2, variant))
                return run(cmd, d)

            # Each run writes content the node never had (a new variant each time), so each run
            # really rebuilds one node and stores its result, as ninja reruns its edge.
            s_change = median_of(a.runs, lambda i: change(1 + i, sy))
            n_change = median_of(a.runs, lambda i: change(1 + a.runs + i, nj))
            row("one input changed, N=%d" % n, s_change, n_change, "<= 0.5 s" if n == 10000 else "")
            rows.append(("bytes written per node (cold), N=%d" % n, bytes_rows, None, ""))
            print("bytes written per node (cold), N=%d: sylva %.0f  ninja %.0f" % (n, *bytes_rows), file=sys.stderr)
            if not a.keep:
                shutil.rmtree(d, ignore_errors=True)
        recipe_out = os.path.join(a.default_out, "default")
        if os.path.isdir(recipe_out):
            cmd = [sylva, "--out", os.path.abspath(a.default_out), "build", os.path.abspath(a.default_recipe)]
            run(cmd, os.getcwd())  # settle: the first no-op after a build may re-hash racy files
            row("default recipe no-op", median_of(a.runs, lambda i: run(cmd, os.getcwd())), None, "<= 50 ms")
    finally:
        if not a.keep:
            shutil.rmtree(work, ignore_errors=True)

    print("| row | sylva wall | sylva CPU | ninja wall | ninja CPU | sylva/ninja (wall) | goal |")
    print("|---|---|---|---|---|---|---|")
    for name, s, n, goal in rows:
        if name.startswith("bytes"):
            print("| %s | %.0f B | | %.0f B | | %.1fx | |" % (name, s[0], s[1], s[0] / s[1] if s[1] else 0))
            continue
        ms = lambda v: "%.1f ms" % (v * 1000)
        print("| %s | %s | %s | %s | %s | %s | %s |" % (
            name, ms(s[0]), ms(s[1]), ms(n[0]) if n else "-", ms(n[1]) if n else "-",
            "%.1fx" % (s[0] / n[0]) if n else "-", goal))


if __name__ == "__main__":
    main()
