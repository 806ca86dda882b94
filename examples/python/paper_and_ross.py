"""rotorshunt from Python, in a few lines each:

1. the paper's Fig. 11 comparison: the closed two-branch shunt opens new instability
   regions at ω_b1 + ω_r and ω_f1 + ω_r that the open circuit does not have;
2. the widest-band design of problems/design-widest-band.toml, before and after;
3. if ROSS is installed, a ROSS rotor's Campbell diagram from rotorshunt next to ROSS's
   own.

    pip install .  # from the repository root (or maturin build, then pip install the wheel)
    python examples/python/paper_and_ross.py [--out DIR] [--quick]

Figures are written to DIR (default: the current folder) as PNG files.
"""

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import rotorshunt as rs  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]


def fig11(out: Path) -> None:
    closed = rs.Problem.from_file(ROOT / "problems/fig11-closed-2000.toml")
    opened = closed.with_set({"circuit.state": "open"})
    phis, betas = np.arange(1000.0, 1400.5, 2.0), np.arange(0.0, 0.501, 0.025)
    fig, axes = plt.subplots(1, 2, figsize=(13, 5), sharey=True)
    for ax, problem, name in ((axes[0], opened, "open circuit"), (axes[1], closed, "closed circuit")):
        chart = problem.chart(phis, betas)
        regions = problem.regions((1000, 1400), beta_max=0.5, level=0.3)
        chart.plot(ax=ax, regions=regions, title=f"Fig. 11, {name}: {chart.unstable} of {chart.max_multiplier.size} unstable")
        print(f"{name}: first-order regions {sorted({r.label for r in regions if r.order == 1})}")
    fig.tight_layout()
    fig.savefig(out / "fig11-open-vs-closed.png", dpi=120)


def widest_band(out: Path, quick: bool) -> None:
    problem = rs.Problem.from_file(ROOT / "problems/design-widest-band.toml")
    design = problem.design(starts=1, max_iterations=3) if quick else problem.design(starts=2, max_iterations=10)
    print(f"design {design.status} (verified {design.verified}): {design.variables} {design.before} -> {design.after}; "
          f"band {design.bands('before')} -> {design.bands('after')}")
    design.plot().savefig(out / "design-widest-band.png", dpi=120)


def ross_campbell(out: Path) -> None:
    try:
        import ross
    except Exception as e:  # noqa: BLE001 - ROSS may fail on import (plotly 7)
        print(f"ROSS is not installed ({type(e).__name__}); skipping the ROSS comparison")
        return
    rotor = ross.rotor_example()
    speeds = np.linspace(0, 800, 17)
    ours = rs.from_ross(rotor).campbell(speeds, count=3)
    theirs = rotor.run_campbell(speeds, frequencies=6)
    fig, (a, b) = plt.subplots(1, 2, figsize=(13, 5), sharey=True)
    ours.plot(ax=a, title="rotorshunt (from_ross)")
    for k in range(theirs.wd.shape[1]):
        style = "--" if np.mean(theirs.whirl_values[:, k]) > 0.5 else "-"
        b.plot(speeds, theirs.wd[:, k], style)
    b.plot(speeds, speeds, "k:", lw=1)
    b.set_title("ROSS run_campbell")
    b.set_xlabel("speed Ω (rad/s)")
    fig.tight_layout()
    fig.savefig(out / "ross-campbell.png", dpi=120)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", type=Path, default=Path("."))
    ap.add_argument("--quick", action="store_true", help="a shorter design run")
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    fig11(args.out)
    widest_band(args.out, args.quick)
    ross_campbell(args.out)


if __name__ == "__main__":
    main()
