# Shared by scripts/compare-outputs.sh and scripts/speed-compare.sh (sourced, not run):
# where the working tree builds, and how a revision's own target dir is seeded from it.

# tree_target ROOT: the target dir of the working tree at ROOT (CARGO_TARGET_DIR and
# .cargo/config respected).
tree_target() {
    (cd "$1" && cargo metadata --format-version 1 --no-deps) |
        python3 -c 'import json, sys; print(json.load(sys.stdin)["target_directory"])'
}

# seed_target ROOT DIR: copy ROOT's target/release into DIR (~1.5 GB), so that building a
# revision there recompiles only rotorshunt itself; skipped with COMPARE_NO_SEED=1.
seed_target() {
    local seed
    seed=$(tree_target "$1")/release
    mkdir -p "$2"
    if [[ -z ${COMPARE_NO_SEED:-} && -d $seed ]]; then
        echo "seeding $2 from $seed" >&2
        cp -a "$seed" "$2/"
    fi
}
