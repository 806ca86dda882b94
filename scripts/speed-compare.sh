#!/usr/bin/env bash
# Speed check of two versions of rotorshunt, measured in the same run:
#
#   scripts/speed-compare.sh BASE [ROUNDS]
#
# Builds the criterion benches and the release binary of git revision BASE (in a
# temporary `git worktree`, target dir seeded from this tree's target/release as
# scripts/compare-outputs.sh does; COMPARE_TARGET_DIR=DIR builds in DIR and keeps it) and
# of the working tree, then alternates the two builds ROUNDS times (default 3), back to
# back: per round and build,
#   - `floquet` bench, "fig11 chart 22837 points, fast" (the Fig. 11 chart),
#   - `regions` bench, "catalogue 100..8000, beta_max 1, level 0.3" (the catalogue),
#     each a criterion median (estimates.json of its own CRITERION_HOME),
#   - `rotorshunt design problems/design-widest-band.toml` end to end: wall and CPU time
#     (user + system of the child).
# SPEED_JOBS=chart,catalogue,design (the default) picks the jobs.
# Prints every measurement, then per job the median over rounds of the paired ratios
# head/base (a ratio below 1 is faster). The host is shared: read the ratio of each round
# as well as the median, and run it when nothing else builds.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
base="${1:?usage: scripts/speed-compare.sh BASE [ROUNDS]}"
rounds="${2:-3}"
cd "$here"
git rev-parse --verify -q "$base^{commit}" >/dev/null || { echo "unknown revision $base" >&2; exit 2; }

# shellcheck source=scripts/revision.sh
source "$here/scripts/revision.sh"
work="$(mktemp -d /tmp/rotorshunt-speed.XXXXXX)"
target="${COMPARE_TARGET_DIR:-$work/target}"
tree="$work/base-tree"
git worktree add -q --detach "$tree" "$base"
# The worktree and the whole work folder go (the seeded target with it, unless it is
# COMPARE_TARGET_DIR, kept for the next run).
trap 'git -C "$here" worktree remove --force "$tree" >/dev/null 2>&1 || true; rm -rf "$work"' EXIT
[ -n "${COMPARE_TARGET_DIR:-}" ] || seed_target "$here" "$target"

# The bench executables of a tree, one per line: name<TAB>path.
benches() {
  (cd "$1" && nice -n 10 cargo bench --no-run --message-format=json "${@:2}" 2>/dev/null) |
    python3 -c '
import json, sys
for line in sys.stdin:
    try: m = json.loads(line)
    except ValueError: continue
    if m.get("reason") == "compiler-artifact" and m.get("executable") and "bench" in m["target"]["kind"]:
        print(m["target"]["name"] + "\t" + m["executable"])'
}
echo "building $base in $tree" >&2
(cd "$tree" && CARGO_TARGET_DIR="$target" nice -n 10 cargo build --release --locked -q)
CARGO_TARGET_DIR="$target" benches "$tree" > "$work/base.benches"
echo "building the working tree" >&2
(cd "$here" && nice -n 10 cargo build --release -q)
benches "$here" > "$work/head.benches"

python3 - "$work" "$rounds" "$target/release/rotorshunt" "$(tree_target "$here")/release/rotorshunt" "$here" <<'EOF'
import json, os, resource, statistics, subprocess, sys, tempfile, time
work, rounds, base_bin, head_bin, here = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4], sys.argv[5]
exe = {side: dict(l.split("\t") for l in open(f"{work}/{side}.benches").read().split("\n") if l) for side in ("base", "head")}
picked = os.environ.get("SPEED_JOBS", "chart,catalogue,design").split(",")
jobs = [("floquet", "fig11 chart 22837 points, fast", "chart"),
        ("regions", "catalogue 100..8000, beta_max 1, level 0.3", "catalogue")]
jobs = [j for j in jobs if j[2] in picked]
bins = {"base": base_bin, "head": head_bin}
results = {}

def bench(side, r, name, filt):
    home = f"{work}/criterion-{side}-{r}-{name}"
    env = dict(os.environ, CRITERION_HOME=home)
    subprocess.run([exe[side][name], "--bench", filt], cwd=here, env=env, check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    for root, _, files in os.walk(home):
        if root.endswith("/new") and "estimates.json" in files:
            return json.load(open(f"{root}/estimates.json"))["median"]["point_estimate"] / 1e9
    raise SystemExit(f"no estimates.json for {side} {name}")

def design(side):
    out = tempfile.mkdtemp(dir=work)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    subprocess.run([bins[side], "design", "problems/design-widest-band.toml", "--out", f"{out}/d"], cwd=here,
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    wall = time.perf_counter() - t
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)

for r in range(rounds):
    for side in (("base", "head") if r % 2 == 0 else ("head", "base")):
        for name, label, filt in jobs:
            v = bench(side, r, name, label)
            results.setdefault((label, side), []).append(v)
            print(f"round {r + 1} {side}: {label}: median {v:.4f} s", flush=True)
        if "design" in picked:
            wall, cpu = design(side)
            results.setdefault(("design wall", side), []).append(wall)
            results.setdefault(("design cpu", side), []).append(cpu)
            print(f"round {r + 1} {side}: widest-band design: wall {wall:.2f} s, cpu {cpu:.2f} s", flush=True)
print()
for label in [j[1] for j in jobs] + (["design wall", "design cpu"] if "design" in picked else []):
    b, h = results[(label, "base")], results[(label, "head")]
    ratios = [y / x for x, y in zip(b, h)]
    print(f"{label}: base median {statistics.median(b):.4f} s, head median {statistics.median(h):.4f} s, "
          f"paired ratios head/base {', '.join(f'{x:.3f}' for x in ratios)}, median ratio {statistics.median(ratios):.3f}")
EOF
