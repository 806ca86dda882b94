#!/usr/bin/env python3
"""ROSS reference fixtures for rotorshunt's general (real-coordinate) path (issue 28).

A rotor on anisotropic, cross-coupled, damped bearings whose coefficients are tabulated
against speed, built with ROSS (`ross-rotordynamics` 2.3.0) and analysed by ROSS's own
`run_modal` and `run_unbalance_response`, so that rotorshunt's modes (whirl frequencies
and whirl directions) and unbalance orbits can be checked against ROSS without Python.
CI never runs this script; the files it writes are committed. It is separate from
`make_fixtures.py` (the importer's fixtures).

How to run (ROSS lives in a virtual environment outside the repository):

    python3 -m venv /work/rossvenv
    /work/rossvenv/bin/pip install ross-rotordynamics==2.3.0 "plotly<6"
    /work/rossvenv/bin/python scripts/ross/make_aniso_fixtures.py

What it writes into `tests/fixtures/ross/` (or `--out DIR`), SI units and rad/s:

* `aniso_tables.toml`: the rotor saved by ROSS's `Rotor.save` (for the importer).
* `aniso_tables.problem.toml`: the same rotor as a rotorshunt problem file, written from
  the same numbers (shaft of `rotor_example()`'s geometry as Rayleigh elements, its two
  disks by mass and inertias as ROSS computes them from geometry, the bearings' tables).
* `aniso_tables.modal.json`: ROSS's `run_modal` at three speeds between table points
  (wd of the lateral modes, ROSS's whirl direction per mode) and the bearing
  coefficients ROSS interpolates there.
* `aniso_tables.unbalance.json`: ROSS's `run_unbalance_response` for an unbalance on the
  disk at node 2 over 100 speeds: x and y amplitude at nodes 0, 2 and 4.

The shaft elements are Rayleigh beams (`shear_effects=False, rotary_inertia=True,
gyroscopic=True`); Timoshenko comparisons are left to the branch that adds them.
"""

import argparse
import json
import math
import os
import sys
from pathlib import Path

if os.environ.get("PYTHONHASHSEED") != "0":
    os.execve(sys.executable, [sys.executable, *sys.argv], {**os.environ, "PYTHONHASHSEED": "0"})
for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

import numpy as np  # noqa: E402
import ross as rs  # noqa: E402

ROSS_VERSION = "2.3.0"
STEEL = rs.materials.steel

# Bearing tables: smooth, not polynomial in the speed (so the spline is exercised), with
# kxx != kyy, cross-coupled stiffness of opposite signs (a fluid film's), damping with a
# symmetric cross term small enough to stay positive semi-definite.
TABLE = [0.0, 300.0, 600.0, 900.0, 1200.0, 1500.0]


def table(f):
    return [float(f(w)) for w in TABLE]


BEARINGS = {
    0: dict(
        kxx=table(lambda w: 1.0e6 * (1.0 + 0.3 * math.sqrt(w / 1500.0))),
        kyy=table(lambda w: 0.8e6 * (1.0 + 0.5 * math.sqrt(w / 1500.0))),
        kxy=table(lambda w: 1.2e5 * math.sin(w / 1000.0)),
        kyx=table(lambda w: -1.6e5 * math.sin(w / 1000.0)),
        cxx=table(lambda w: 800.0 * math.exp(-w / 3000.0)),
        cyy=table(lambda w: 600.0 * math.exp(-w / 3000.0)),
        cxy=table(lambda w: 60.0 * math.exp(-w / 3000.0)),
        cyx=table(lambda w: 40.0 * math.exp(-w / 3000.0)),
    ),
    6: dict(
        kxx=table(lambda w: 1.1e6 * (1.0 + 0.2 * math.sqrt(w / 1500.0))),
        kyy=table(lambda w: 0.7e6 * (1.0 + 0.6 * math.sqrt(w / 1500.0))),
        kxy=table(lambda w: 0.9e5 * math.sin(w / 1200.0)),
        kyx=table(lambda w: -1.3e5 * math.sin(w / 1200.0)),
        cxx=table(lambda w: 700.0 * math.exp(-w / 2500.0)),
        cyy=table(lambda w: 900.0 * math.exp(-w / 2500.0)),
        cxy=table(lambda w: -50.0 * math.exp(-w / 2500.0)),
        cyx=table(lambda w: -30.0 * math.exp(-w / 2500.0)),
    ),
}
# Speeds of the modal comparison: between table points.
MODAL_SPEEDS = [150.0, 750.0, 1350.0]
NUM_MODES = 40
# Unbalance on the disk at node 2, response over 100 speeds inside the table.
UNBALANCE_NODE = 2
UNBALANCE_MAGNITUDE = 1.0e-3  # kg m
UNBALANCE_PHASE = 0.0
UNBALANCE_SPEEDS = [20.0 + (1480.0 - 20.0) * i / 99 for i in range(100)]
RESPONSE_NODES = [0, 2, 4]


def rotor():
    shaft = [
        rs.ShaftElement(L=0.25, idl=0.0, odl=0.05, material=STEEL, shear_effects=False, rotary_inertia=True, gyroscopic=True)
        for _ in range(6)
    ]
    disks = [
        rs.DiskElement.from_geometry(n=2, material=STEEL, width=0.07, i_d=0.05, o_d=0.28),
        rs.DiskElement.from_geometry(n=4, material=STEEL, width=0.07, i_d=0.05, o_d=0.28),
    ]
    bearings = [rs.BearingElement(n=n, frequency=TABLE, **c) for n, c in BEARINGS.items()]
    return rs.Rotor(shaft, disks, bearings)


def problem_text(r):
    lines = [
        "# Written by scripts/ross/make_aniso_fixtures.py from the numbers it gives ROSS.",
        "version = 1",
        'title = "rotor_example geometry on anisotropic cross-coupled tabulated bearings (ROSS fixture)"',
        "speed = 0.0",
        "",
        "[[sections]]",
        "length = 1.5",
        "outer_diameter = 0.05",
        f"youngs_modulus = {STEEL.E!r}",
        f"density = {STEEL.rho!r}",
        "elements = 6",
        "",
    ]
    for d in r.disk_elements:
        e = UNBALANCE_MAGNITUDE / d.m if d.n == UNBALANCE_NODE else 0.0
        lines += [
            "[[disks]]",
            f"node = {d.n}",
            f"mass = {float(d.m)!r}",
            f"polar_inertia = {float(d.Ip)!r}",
            f"diametral_inertia = {float(d.Id)!r}",
            f"eccentricity = {e!r}",
            "",
        ]
    for n, c in BEARINGS.items():
        lines += ["[[bearings]]", f"node = {n}", f"speeds = {TABLE!r}"]
        for k in ("kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy"):
            lines.append(f"{k} = {[float(v) for v in c[k]]!r}")
        lines.append("")
    lines += ["[load]", "alpha = 0.0", "critical_load = 1.0", ""]
    return "\n".join(lines)


def lateral(modal):
    """Indices of the lateral modes (ROSS's mode_type), lowest first."""
    return [i for i, s in enumerate(modal.shapes) if s.mode_type == "Lateral"]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=str(Path(__file__).resolve().parents[2] / "tests/fixtures/ross"))
    ap.add_argument("--any-ross-version", action="store_true")
    args = ap.parse_args()
    if rs.__version__ != ROSS_VERSION and not args.any_ross_version:
        sys.exit(f"ROSS {rs.__version__}: the fixtures are for {ROSS_VERSION} (--any-ross-version to go on)")
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    built = rotor()
    built.save(str(out / "aniso_tables.toml"))
    r = rs.Rotor.load(str(out / "aniso_tables.toml"))
    (out / "aniso_tables.problem.toml").write_text(problem_text(r))
    modal = []
    for w in MODAL_SPEEDS:
        m = r.run_modal(speed=w, num_modes=NUM_MODES, sparse=False)
        idx = lateral(m)
        whirl = m.whirl_direction()
        coefficients = {
            str(b.n): {k: float(getattr(b, f"{k}_interpolated")(w)) for k in ("kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy")}
            for b in r.bearing_elements
        }
        modal.append(
            {
                "speed": w,
                "wd": [float(m.wd[i]) for i in idx],
                "damping_ratio": [float(m.damping_ratio[i]) for i in idx],
                "whirl": [str(whirl[i]) for i in idx],
                "coefficients": coefficients,
            }
        )
    (out / "aniso_tables.modal.json").write_text(
        json.dumps({"ross_version": rs.__version__, "speeds": modal}, indent=1) + "\n"
    )
    resp = r.run_unbalance_response(
        node=[UNBALANCE_NODE],
        unbalance_magnitude=[UNBALANCE_MAGNITUDE],
        unbalance_phase=[UNBALANCE_PHASE],
        frequency=np.array(UNBALANCE_SPEEDS),
    )
    nd = r.number_dof
    probes = {}
    for n in RESPONSE_NODES:
        x = resp.forced_resp[nd * n + 0, :]
        y = resp.forced_resp[nd * n + 1, :]
        probes[str(n)] = {
            "x_amplitude": [float(abs(v)) for v in x],
            "y_amplitude": [float(abs(v)) for v in y],
            "x_phase": [float(np.angle(v)) for v in x],
            "y_phase": [float(np.angle(v)) for v in y],
        }
    (out / "aniso_tables.unbalance.json").write_text(
        json.dumps(
            {
                "ross_version": rs.__version__,
                "node": UNBALANCE_NODE,
                "magnitude": UNBALANCE_MAGNITUDE,
                "phase": UNBALANCE_PHASE,
                "speeds": UNBALANCE_SPEEDS,
                "probes": probes,
            },
            indent=1,
        )
        + "\n"
    )


if __name__ == "__main__":
    main()
