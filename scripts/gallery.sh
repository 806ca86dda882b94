#!/bin/sh
# Regenerate docs/gallery/: one PNG of every plot kind, from the bundled problems.
# Usage: scripts/gallery.sh [path/to/rotorshunt]   (default: target/release/rotorshunt,
# built with `cargo build --release` first). Takes about a minute (the two designs).
set -eu
cd "$(dirname "$0")/.."
bin=${1:-target/release/rotorshunt}
[ -x "$bin" ] || cargo build --release
out=docs/gallery
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"
q=--quiet
tuned="--set circuit.branches[0].tuning_frequency=733.75 --set circuit.branches[0].resistance=13.708"
# Campbell diagram, the issue's case: tuned widest-band circuit, lowest six of each whirl.
"$bin" $q campbell problems/design-widest-band.toml --speeds 0:3000:50 --count 6 --out "$work/campbell" $tuned >/dev/null
cp "$work/campbell/campbell.png" "$out/campbell.png"
# Stability chart and growth map, open against closed circuit (Fig. 9 / Fig. 11).
"$bin" $q chart problems/fig9-open-2000.toml --phi 100:3000:5 --beta 0:0.5:0.0125 --out "$work/chart" \
    --set circuit.state=open --compare-set circuit.state=closed >/dev/null
cp "$work/chart/chart.png" "$out/chart-compare.png"
cp "$work/chart/growth.png" "$out/growth.png"
# Tracked instability regions with their labels (Fig. 11 closed circuit).
"$bin" $q regions problems/fig11-closed-2000.toml --phi 1000:1500 --beta-max 0.5 --level 0.3 --out "$work/regions" >/dev/null
cp "$work/regions/regions.png" "$out/regions.png"
# Time response in physical DOFs.
"$bin" $q response problems/fig9-open-2000.toml --phi 1000 --beta 0.3 --periods 20 --out "$work/response" >/dev/null
cp "$work/response/response.png" "$out/response.png"
# Unbalance Bode plot, tuned and damped shunt against the open circuit (Fig. 8b rotor).
"$bin" $q unbalance problems/fig8-eta200.toml --speeds 250:500:0.5 --out "$work/unbalance" \
    --set circuit.state=closed --set 'circuit.branches[0].tuning_frequency=359.6' \
    --set 'circuit.branches[0].resistance=100' --compare-set circuit.state=open >/dev/null
cp "$work/unbalance/bode.png" "$out/bode.png"
# Design charts: the bands found at β_op (widest band), and operating bands with their
# clearances (clear bands); the optimiser's history.
"$bin" $q design problems/design-widest-band.toml --out "$work/design-widest" >/dev/null
cp "$work/design-widest/charts.png" "$out/design-widest-band.png"
cp "$work/design-widest/history.png" "$out/design-history.png"
"$bin" $q design problems/design-clear-bands.toml --out "$work/design-clear" >/dev/null
cp "$work/design-clear/charts.png" "$out/design-clear-bands.png"
# A study's figure: the band width against the swept speed, a line per resistance.
"$bin" $q study problems/studies/resistance-speed.toml --out "$work/study" >/dev/null
cp "$work/study/summary/figure.png" "$out/study.png"
du -ch "$out"/*.png | tail -1
