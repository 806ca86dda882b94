#!/usr/bin/env python3
"""Side-by-side wall and CPU times of two rotorshunt binaries on whole commands.

    scripts/speed-cli.py BASE_BIN HEAD_BIN [ROUNDS]

Runs, from the repository root, the Fig. 11 chart of the README
(`chart problems/fig11-closed-2000.toml --set circuit.state=open --compare-set
circuit.state=closed --phi 100:8000:10 --beta 0:1:0.01`), the widest-band design
(`design problems/design-widest-band.toml`) and the catalogue (`regions
problems/fig11-closed-2000.toml --phi 100:8000 --beta-max 1 --level 0.3 --json`) with
each binary, alternating the order per round (base then head, then head then base, ...), ROUNDS times (default 3). Prints every
measurement, then per job the medians and the paired ratios head/base (below 1 is
faster). Outputs go to a temporary folder, removed at the end. SPEED_JOBS=chart,design,catalogue
(the default) picks the jobs. The host is shared: compare ratios of the same round, and
run it when nothing else builds. Build the base binary with scripts/speed-compare.sh's
approach (a git worktree of the revision, `cargo build --release`).
"""
import os, resource, shutil, statistics, subprocess, sys, tempfile, time

base, head = sys.argv[1], sys.argv[2]
rounds = int(sys.argv[3]) if len(sys.argv) > 3 else 3
root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
jobs = {
    "chart": lambda b, o: [b, "chart", "problems/fig11-closed-2000.toml", "--set", "circuit.state=open",
                           "--compare-set", "circuit.state=closed", "--phi", "100:8000:10", "--beta", "0:1:0.01",
                           "--out", o, "--quiet"],
    "design": lambda b, o: [b, "design", "problems/design-widest-band.toml", "--out", o, "--quiet"],
    "catalogue": lambda b, o: [b, "regions", "problems/fig11-closed-2000.toml", "--phi", "100:8000", "--beta-max", "1",
                               "--level", "0.3", "--json", "--quiet"],
}
picked = os.environ.get("SPEED_JOBS", "chart,design,catalogue").split(",")
work = tempfile.mkdtemp(prefix="rotorshunt-speed-cli.")
res = {}
try:
    for r in range(rounds):
        for side in (("base", "head") if r % 2 == 0 else ("head", "base")):
            for job in picked:
                out = os.path.join(work, f"{side}-{job}-{r}")
                before = resource.getrusage(resource.RUSAGE_CHILDREN)
                t = time.perf_counter()
                subprocess.run(jobs[job](base if side == "base" else head, out), cwd=root, check=True,
                               stdout=subprocess.DEVNULL)
                wall = time.perf_counter() - t
                after = resource.getrusage(resource.RUSAGE_CHILDREN)
                cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
                res.setdefault((job, side, "wall"), []).append(wall)
                res.setdefault((job, side, "cpu"), []).append(cpu)
                print(f"round {r + 1} {side} {job}: wall {wall:.2f} s, cpu {cpu:.2f} s", flush=True)
                shutil.rmtree(out, ignore_errors=True)
finally:
    shutil.rmtree(work, ignore_errors=True)
print()
for job in picked:
    for kind in ("wall", "cpu"):
        b, h = res[(job, "base", kind)], res[(job, "head", kind)]
        ratios = [y / x for x, y in zip(b, h)]
        print(f"{job} {kind}: base median {statistics.median(b):.2f} s, head median {statistics.median(h):.2f} s, "
              f"paired ratios head/base {', '.join(f'{x:.3f}' for x in ratios)}, "
              f"median ratio {statistics.median(ratios):.3f}")
