#!/usr/bin/env bash
# Output identity check: do two versions of rotorshunt write the same outputs?
#
#   scripts/compare-outputs.sh [--keep] [--inputs base|head] BASE [HEAD]
#
# Builds the release binary of git revision BASE and of HEAD (default: the working tree
# this script belongs to, built in place with `cargo build --release`), runs the fixed
# command list below with each binary, normalises wall times and the tool version, and
# compares the two output trees file by file (scripts/compare-outputs/compare.py). Prints
# each differing file with its first differing lines and "N files compared, M differ".
#
# Exit status: 0 identical, 1 outputs differ, 2 usage error (unknown option, missing or
# unknown revision), 3 a build failed (nothing was compared).
#
# Cost: 2.5-3.5 minutes per binary (385 commands: 85 s on a quiet host, 137-208 s for 291 of them on this 2-core
# machine while other engineers' builds ran, load average 6-8), plus the builds: a
# revision is built in a temporary `git worktree` with its own target dir, seeded by
# copying the working tree's target/release (~1.5 GB) so that only rotorshunt itself
# recompiles (1-3 minutes under that load). Set COMPARE_TARGET_DIR=DIR to build
# revisions in DIR instead (kept between runs, so a second comparison against the same
# BASE rebuilds nothing; seed it yourself with `cp -a target/release DIR/` first); set
# COMPARE_NO_SEED=1 to skip the copy (a full build from scratch). Builds run with
# `nice -n 10`.
#
# Options:
#   --keep            keep the temporary folder (its path is printed): base/ and head/
#                     hold the raw outputs, each command's in out/<id>/.
#   --inputs base     (default) both binaries read the problem files of BASE;
#   --inputs head     both read those of HEAD. Either way both read the same bytes.
#   --design-set K=V  add `--set K=V` to every `design` command, on both sides (repeat
#                     for several): shortened designs (for example design.starts=1 and
#                     design.max_iterations=4) take the same code paths in minutes where
#                     the bundled designs with their own settings take about 35 minutes
#                     per binary, one of them past the timeout below.
#
# What is run (function `commands`), each in the same directory, with the same relative
# paths, so that paths in outputs are equal by construction: the inputs are problems/
# (every *.toml and problems/studies/*.toml), tests/fixtures/{bad,good,held_out} and
# scripts/compare-outputs/mixed-study.toml (a small study of its own: one regions case,
# one design case, one failing case). For every command, out/<id>/ holds `command` (the
# arguments), `stdout`, `stderr`, `exit-code` and, for commands with --out, files/.
#   - CLI surface: --help of the tool and of every subcommand, --version;
#   - argument and input errors: a missing file, bad --count/--phi-op/ranges, a bad
#     --set, a response that overflows, and `check` on every tests/fixtures/bad file;
#   - tests/fixtures/{good,held_out}: check, modes --json, floquet --json;
#   - every problems/*.toml: check; modes (text, --json, --speed 0 --count 6); campbell
#     (0:3000:500); floquet at (1230 rad/s, 0.3) (text, --json); chart over
#     1000:1500:25 x 0:0.5:0.05; response (10 periods); regions over 1000:1500 to
#     beta 0.5, edges at 0.3 (text, --json) and over 1150:1300 with --out; band at
#     phi_op = 1230, beta_op = 0.3 (text, and --json with --phi 600:2400); design where
#     the file has a [design] table;
#   - variants on fig11-closed-2000.toml: floquet by the DSTM, chart with --compare-set,
#     with --compare FILE and with --timing, band at an unstable phi_op;
#   - every problems/studies/*.toml and the mixed study: study, then the same study
#     again (the resume).
#
# Normalisation: wall-clock times and the tool version only, by rules anchored on the
# text around each value; the list and the reasons are in compare.py's header. Nothing
# numeric about a result is normalised. PNG files are compared as bytes (plotters'
# bitmap rendering with embedded fonts is deterministic: a run against itself gives
# identical PNGs). The count of replacements each rule made is printed for both sides.
# The trees compared are the whole run folders, input copies included, so a command that
# writes beside or over an input shows as a difference too.
set -euo pipefail

help() { sed -n '2,/^set -euo/p' "${BASH_SOURCE[0]}" | sed -e '$d' -e 's/^# \{0,1\}//'; }
usage() {
    echo "usage: scripts/compare-outputs.sh [--keep] [--inputs base|head] BASE [HEAD] (--help for more)" >&2
    exit 2
}

KEEP=0
DESIGN_SETS=()
INPUTS=base
POSITIONAL=()
while [[ $# -gt 0 ]]; do
    case $1 in
        --keep) KEEP=1 ;;
        --design-set)
            [[ $# -ge 2 && $2 == *=* ]] || { echo "error: --design-set takes KEY=VALUE" >&2; usage; }
            DESIGN_SETS+=(--set "$2")
            shift ;;
        --inputs)
            [[ $# -ge 2 && ( $2 == base || $2 == head ) ]] || { echo "error: --inputs takes base or head" >&2; usage; }
            INPUTS=$2
            shift ;;
        -h | --help) help; exit 0 ;;
        -*) echo "error: unknown option $1" >&2; usage ;;
        *) POSITIONAL+=("$1") ;;
    esac
    shift
done
[[ ${#POSITIONAL[@]} -ge 1 && ${#POSITIONAL[@]} -le 2 ]] || usage
BASE=${POSITIONAL[0]}
HEAD=${POSITIONAL[1]:-}

SCRIPTS=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
ROOT=$(git -C "$SCRIPTS" rev-parse --show-toplevel)
for rev in "$BASE" ${HEAD:+"$HEAD"}; do
    git -C "$ROOT" rev-parse --quiet --verify "$rev^{commit}" >/dev/null || {
        echo "error: $rev is not a git revision of $ROOT" >&2
        exit 2
    }
done
BASE_COMMIT=$(git -C "$ROOT" rev-parse "$BASE^{commit}")
HEAD_COMMIT=${HEAD:+$(git -C "$ROOT" rev-parse "$HEAD^{commit}")}

# A command that runs longer than this is stopped and its exit code recorded as 124.
TIMEOUT=900

WORK=$(mktemp -d "${TMPDIR:-/tmp}/compare-outputs.XXXXXX")
WORKTREES=()
# shellcheck disable=SC2317 # invoked by the EXIT trap
cleanup() {
    local wt
    for wt in ${WORKTREES[@]+"${WORKTREES[@]}"}; do
        git -C "$ROOT" worktree remove --force "$wt" >/dev/null 2>&1 || true
    done
    if [[ $KEEP == 1 ]]; then
        echo "kept $WORK" >&2
    else
        rm -rf "$WORK"
    fi
}
trap cleanup EXIT

say() { echo "compare-outputs: $*" >&2; }

# shellcheck source=scripts/revision.sh
source "$SCRIPTS/revision.sh"

# build_revision REV NAME: the release binary of REV as $WORK/bin/NAME.
build_revision() {
    local rev=$1 name=$2 target
    local src=$WORK/src-$name
    git -C "$ROOT" worktree add --detach --quiet "$src" "$rev"
    WORKTREES+=("$src")
    if [[ -n ${COMPARE_TARGET_DIR:-} ]]; then
        target=$COMPARE_TARGET_DIR
    else
        target=$WORK/target-$name
        seed_target "$ROOT" "$target"
    fi
    say "building $name ($rev) in $src"
    (cd "$src" && CARGO_TARGET_DIR=$target nice -n 10 cargo build --release --locked --bin rotorshunt) ||
        { say "the build of $name failed"; exit 3; }
    cp "$target/release/rotorshunt" "$WORK/bin/$name"
}

# build_tree NAME: the release binary of the working tree as $WORK/bin/NAME.
build_tree() {
    say "building $1 (working tree $ROOT)"
    (cd "$ROOT" && nice -n 10 cargo build --release --bin rotorshunt) || { say "the build of $1 failed"; exit 3; }
    cp "$(tree_target "$ROOT")/release/rotorshunt" "$WORK/bin/$1"
}

# inputs DIR: the problem files both binaries read, and this script's own fixtures.
inputs() {
    local dir=$1 rev
    mkdir -p "$dir/scripts/compare-outputs"
    cp "$SCRIPTS"/compare-outputs/*.toml "$dir/scripts/compare-outputs/"
    if [[ $INPUTS == head && -z $HEAD ]]; then
        local p
        for p in problems tests/fixtures/bad tests/fixtures/good tests/fixtures/held_out; do
            if [[ -d $ROOT/$p ]]; then
                mkdir -p "$dir/$(dirname "$p")"
                cp -r "$ROOT/$p" "$dir/$p"
            fi
        done
    else
        if [[ $INPUTS == head ]]; then rev=$HEAD_COMMIT; else rev=$BASE_COMMIT; fi
        local paths=()
        for p in problems tests/fixtures/bad tests/fixtures/good tests/fixtures/held_out; do
            if [[ -n $(git -C "$ROOT" ls-tree "$rev" -- "$p") ]]; then paths+=("$p"); fi
        done
        git -C "$ROOT" archive "$rev" -- "${paths[@]}" | tar -x -C "$dir"
    fi
}

# run ID ARGS...: one command of the list; @OUT@ in an argument is its output folder.
run() {
    local id=$1 a rc=0
    shift
    local dir=out/$id args=()
    [[ ! -e $dir ]] || { say "internal error: command id $id used twice"; exit 3; }
    mkdir -p "$dir"
    for a in "$@"; do args+=("${a//@OUT@/$dir/files}"); done
    printf '%s\n' "${args[*]}" >"$dir/command"
    timeout "$TIMEOUT" "$BIN" "${args[@]}" >"$dir/stdout" 2>"$dir/stderr" </dev/null || rc=$?
    echo "$rc" >"$dir/exit-code"
}

stem() { local s=${1##*/}; echo "${s%.toml}"; }

# The fixed command list (run in the run folder, paths relative to it).
commands() {
    local f s c
    local fig11=problems/fig11-closed-2000.toml
    local chart_grid=(--phi 1000:1500:25 --beta 0:0.5:0.05)

    run help --help
    run version --version
    for c in check modes campbell floquet chart regions band design study response; do
        run "help-$c" "$c" --help
    done

    run error-missing-file check problems/does-not-exist.toml
    run error-modes-count modes "$fig11" --count 0
    run error-band-phi-op band "$fig11" --phi-op -1 --level 0.3
    run error-chart-range chart "$fig11" --phi 1500:1000:25 --beta 0:0.5:0.05 --out @OUT@
    run error-set check "$fig11" --set shaft.length=-0.7
    run error-response-overflow response "$fig11" --phi 1230 --beta 1e300 --periods 5 --out @OUT@
    for f in tests/fixtures/bad/*.toml; do
        [[ -e $f ]] || continue
        run "check-bad-$(stem "$f")" check "$f"
    done
    for f in tests/fixtures/good/*.toml tests/fixtures/held_out/*.toml; do
        [[ -e $f ]] || continue
        s=$(basename "$(dirname "$f")")-$(stem "$f")
        run "check-$s" check "$f"
        run "modes-json-$s" modes "$f" --json
        run "floquet-json-$s" floquet "$f" --phi 1230 --beta 0.3 --json
    done

    for f in problems/*.toml; do
        s=$(stem "$f")
        run "check-$s" check "$f"
        run "modes-$s" modes "$f"
        run "modes-json-$s" modes "$f" --json
        run "modes-rest-$s" modes "$f" --speed 0 --count 6
        run "campbell-$s" campbell "$f" --speeds 0:3000:500 --out @OUT@
        run "floquet-$s" floquet "$f" --phi 1230 --beta 0.3
        run "floquet-json-$s" floquet "$f" --phi 1230 --beta 0.3 --json
        run "chart-$s" chart "$f" "${chart_grid[@]}" --out @OUT@
        run "response-$s" response "$f" --phi 1230 --beta 0.3 --periods 10 --out @OUT@
        run "regions-$s" regions "$f" --phi 1000:1500 --beta-max 0.5 --level 0.3
        run "regions-json-$s" regions "$f" --phi 1000:1500 --beta-max 0.5 --level 0.3 --json
        run "regions-out-$s" regions "$f" --phi 1150:1300 --beta-max 0.5 --level 0.3 --out @OUT@
        run "band-$s" band "$f" --phi-op 1230 --level 0.3
        run "band-json-$s" band "$f" --phi-op 1230 --level 0.3 --phi 600:2400 --json
        if grep -q '^\[design\]' "$f"; then
            run "design-$s" design "$f" ${DESIGN_SETS[@]+"${DESIGN_SETS[@]}"} --out @OUT@
        fi
    done

    run floquet-dstm-fig11 floquet "$fig11" --phi 1230 --beta 0.3 --set analysis.method=dstm --json
    run chart-compare-set-fig11 chart "$fig11" --set circuit.state=open --compare-set circuit.state=closed \
        "${chart_grid[@]}" --out @OUT@
    run chart-compare-file-fig11 chart "$fig11" --compare problems/fig9-open-2000.toml "${chart_grid[@]}" --out @OUT@
    run chart-timing-fig11 chart "$fig11" "${chart_grid[@]}" --timing --out @OUT@
    run band-unstable-fig11 band "$fig11" --phi-op 1185 --level 0.3

    for f in problems/studies/*.toml scripts/compare-outputs/mixed-study.toml; do
        [[ -e $f ]] || continue
        s=$(stem "$f")
        run "study-$s" study "$f" --out @OUT@
        run "study-resume-$s" study "$f" --out "out/study-$s/files"
    done
}

# outputs NAME: run the list with $WORK/bin/NAME into $WORK/NAME.
outputs() {
    local name=$1 run_dir=$WORK/run started count
    rm -rf "$run_dir"
    mkdir -p "$run_dir"
    inputs "$run_dir"
    # Both binaries run as the same path, so not even argv[0] differs.
    mkdir -p "$WORK/run-bin"
    cp "$WORK/bin/$name" "$WORK/run-bin/rotorshunt"
    BIN=$WORK/run-bin/rotorshunt
    started=$SECONDS
    say "running the command list with $name"
    (cd "$run_dir" && commands)
    count=$(find "$run_dir/out" -name exit-code | wc -l)
    say "$name: $count commands in $((SECONDS - started)) s"
    mv "$run_dir" "$WORK/$name"
}

mkdir -p "$WORK/bin"
build_revision "$BASE_COMMIT" base
if [[ -n $HEAD ]]; then
    build_revision "$HEAD_COMMIT" head
else
    build_tree head
fi
say "base: $BASE ($BASE_COMMIT); head: ${HEAD:-working tree} ${HEAD_COMMIT}; inputs of $INPUTS"
outputs base
outputs head

rc=0
python3 "$SCRIPTS/compare-outputs/compare.py" "$WORK/base" "$WORK/head" || rc=$?
case $rc in
    0) echo "outputs identical" ;;
    1) echo "outputs differ" ;;
    *) say "compare.py failed (exit $rc)"; exit 3 ;;
esac
exit "$rc"
