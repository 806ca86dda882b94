"""The Python layer's overhead against the command line and Rust (issue 31):

1. a 20 020-point chart (fig11-closed-2000.toml, phi 1000:2000:1 x beta 0:0.95:0.05)
   through Python against the CLI's own compute time (`chart --timing`), and
2. 1 000 single `floquet` calls from Python against the same 1 000 calls from Rust.

Run from the repository root with the wheel installed:

    python python/bench/overhead.py [--repeat 3]

Times are the best of `--repeat` runs (a shared machine is noisy; the best run is the
least disturbed). Needs target/release/rotorshunt (cargo build --release).
"""

import argparse
import re
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

import rotorshunt as rs
from rotorshunt import _rotorshunt as native

ROOT = Path(__file__).resolve().parents[2]
FILE = "problems/fig11-closed-2000.toml"


def cli_chart_seconds(binary: Path) -> float:
    with tempfile.TemporaryDirectory() as tmp:
        out = subprocess.run(
            [str(binary), "chart", FILE, "--phi", "1000:2000:1", "--beta", "0:0.95:0.05", "--out", f"{tmp}/c", "--timing", "--quiet"],
            cwd=ROOT, capture_output=True, text=True, check=True,
        ).stdout
    m = re.search(r"timing: (\d+) points in ([0-9.]+) s wall", out)
    assert m and int(m.group(1)) == 20020, out
    return float(m.group(2))


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    binary = ROOT / "target" / "release" / "rotorshunt"
    p = rs.Problem.from_file(ROOT / FILE)
    p.floquet(1000, 0.1)  # the reduced system, built once, before any clock
    phis = 1000.0 + np.arange(1001) * 1.0
    betas = np.arange(20) * 0.05
    cli, py = [], []
    for _ in range(args.repeat):
        cli.append(cli_chart_seconds(binary))
        t = time.perf_counter()
        c = p.chart(phis, betas)
        py.append(time.perf_counter() - t)
        assert c.max_multiplier.size == 20020
    print(f"chart, 20 020 points: CLI compute {min(cli):.3f} s, Python call {min(py):.3f} s "
          f"(overhead {100 * (min(py) / min(cli) - 1):+.1f} %; runs CLI {['%.3f' % x for x in cli]}, Python {['%.3f' % x for x in py]})")

    points = [(900.0 + 0.7 * k, 0.05 + 0.0004 * k) for k in range(1000)]
    rust, pyf = [], []
    for _ in range(args.repeat):
        rust.append(native._rust_floquet_seconds(p._native, points))
        t = time.perf_counter()
        for phi, beta in points:
            p.floquet(phi, beta)
        pyf.append(time.perf_counter() - t)
    print(f"1 000 floquet calls: Rust {min(rust):.3f} s, Python {min(pyf):.3f} s (ratio {min(pyf) / min(rust):.2f}; "
          f"{1e6 * (min(pyf) - min(rust)) / 1000:.0f} us per call added)")


if __name__ == "__main__":
    main()
