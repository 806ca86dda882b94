#!/usr/bin/env python3
"""ROSS reference fixtures for rotorshunt's ROSS importer (`rotorshunt import-ross`).

Builds rotors with ROSS (the Python rotordynamics package, `ross-rotordynamics`), saves
them with ROSS's own `Rotor.save` and records ROSS's own `run_modal` results, so that the
Rust importer and its tests can be checked against ROSS without Python. CI never runs this
script; the files it writes are committed.

How to run (ROSS lives in a virtual environment outside the repository):

    python3 -m venv /work/venv-ross
    /work/venv-ross/bin/pip install ross-rotordynamics==2.3.0 "plotly<6"
    /work/venv-ross/bin/python scripts/ross/make_fixtures.py

(plotly 6 and later break `import ross` 2.3.0 on `scattermapbox`; a REFPROP warning
printed on import is harmless.) The fixtures were written with ROSS 2.3.0; the script
stops on another version unless `--any-ross-version` is given, because the saved format
and the results may change between versions.

What it writes into `tests/fixtures/ross/` (or `--out DIR`), all SI units, rad/s:

* `rotor_example_rayleigh.toml` (+ `.json`): the geometry of ROSS's `rotor_example()`
  (Friswell's rotor: 6 solid steel elements of 0.25 m, 0.05 m diameter, two disks at
  nodes 2 and 4) with Rayleigh elements (`shear_effects=False, rotary_inertia=True,
  gyroscopic=True`) and isotropic undamped bearings k = 1e6 N/m at nodes 0 and 6.
* `stepped_hollow.toml` (+ `.json`): a stepped rotor of four sections (one hollow, of a
  second material), 13 elements, an overhung disk at node 0 beyond the bearing at node 2,
  a disk at node 5, and isotropic bearings at the interior nodes 2 and 11, the second
  with isotropic damping.
* `<rotor>.modal.json` for both: ROSS's `run_modal` at three speeds (wn, wd, damping
  ratio, log decrement, eigenvalue, mode type, ROSS's whirl direction, and a whirl
  direction from the amplitude-weighted orbit sense; see `whirl_index` below).
* `speed_dependent.toml` and `speed_dependent.modal.json`: the rotor_example geometry on
  bearings whose (isotropic) coefficients are tabulated against frequency; importable
  only once a speed is chosen. Its modal file is at a tabulated speed (1000 rad/s) and
  between two (750 rad/s, where ROSS's spline is checked to be the table's line).
* `refuse_*.toml`: rotors the importer must refuse; where one element is at fault its
  tag starts with `Refused`: Timoshenko elements (all of them), a tapered outer
  diameter, a tapered bore, an anisotropic bearing (kxx != kyy), anisotropic bearing
  damping (cxx != cyy), a cross-coupled bearing (kxy, kyx != 0), and a bearing linked to
  a point mass (n_link).

Each rotor is saved, loaded back with `Rotor.load`, and the loaded rotor's matrices are
checked to equal the built rotor's; the modal results are computed from the loaded rotor,
so they are the results of exactly what is in the file. ROSS's sparse solver (ARPACK,
the `run_modal` default) is checked against the dense one (`sparse=False`).
"""

import argparse
import json
import math
import os
import sys
from pathlib import Path

# Regenerated fixtures must not differ without cause, but the last digits of ROSS's
# eigenvalues (and the arbitrary mix of a degenerate pair at speed 0) depend on summation
# order. ROSS assembles its matrices over a set of elements hashed by tag, whose order
# follows Python's per-process string hash seed: fix it (it can only be set before the
# interpreter starts, hence the re-exec). The BLAS thread count changes the order too:
# use one thread, set before numpy loads.
if os.environ.get("PYTHONHASHSEED") != "0":
    os.execve(sys.executable, [sys.executable, *sys.argv], {**os.environ, "PYTHONHASHSEED": "0"})
for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

import numpy as np  # noqa: E402
import ross as rs  # noqa: E402

ROSS_VERSION = "2.3.0"

# Lowest 20 modes (run_modal keeps num_modes // 2 of them, axial and torsional ones
# included): enough for at least 4 forward and 4 backward lateral whirls in every rotor.
NUM_MODES = 40

# Lateral modes of an isotropic rotor at speed > 0 are circular, so |whirl_index| is 1 up
# to round-off; below this the orbit is called "Mixed" (it is at speed 0, where forward
# and backward coincide and the solver returns an arbitrary mix of the pair).
CIRCULAR_WHIRL_MIN = 0.99

# Largest relative gap allowed between the sparse (ARPACK) and the dense eigenvalues. The
# dense solver on the state matrix loses about eps * |A| / |eigenvalue| (up to 7e-8 seen
# on the highest kept modes); a missed or spurious mode would differ by order one. The
# fixtures serve a 0.05 % comparison, far above this.
SOLVER_AGREEMENT = 1e-6

# Equality of the matrices of a saved-and-loaded rotor with the built one: floats are
# written in Python's round-trip form, so only the summation order may differ.
ROUND_TRIP = 1e-12

STEEL = rs.materials.steel
# A titanium alloy (Ti-6Al-4V, typical handbook values) for the hollow section of the
# stepped rotor, so that the fixture has two materials.
TITANIUM = rs.Material(name="Ti6Al4V", rho=4430.0, E=113.8e9, G_s=44.0e9)


def rayleigh(L, idl, odl, material, idr=None, odr=None, tag=None, **kw):
    """A ROSS shaft element of the kind rotorshunt imports: a Rayleigh beam."""
    args = dict(shear_effects=False, rotary_inertia=True, gyroscopic=True)
    args.update(kw)
    return rs.ShaftElement(
        L=L, idl=idl, odl=odl, idr=idr, odr=odr, material=material, tag=tag, **args
    )


def example_shaft(**kw):
    """The 6 elements of ROSS's rotor_example(): 0.25 m, solid, 0.05 m, steel."""
    return [rayleigh(0.25, 0.0, 0.05, STEEL, **kw) for _ in range(6)]


def example_disks():
    """The two disks of ROSS's rotor_example() (from geometry, at nodes 2 and 4)."""
    return [
        rs.DiskElement.from_geometry(n=2, material=STEEL, width=0.07, i_d=0.05, o_d=0.28),
        rs.DiskElement.from_geometry(n=4, material=STEEL, width=0.07, i_d=0.05, o_d=0.28),
    ]


def example_bearings():
    """Isotropic, undamped versions of rotor_example()'s bearings (k = 1e6 N/m)."""
    return [rs.BearingElement(n=0, kxx=1e6, cxx=0.0), rs.BearingElement(n=6, kxx=1e6, cxx=0.0)]


def rotor_example_rayleigh():
    return rs.Rotor(example_shaft(), example_disks(), example_bearings())


def stepped_hollow():
    """Four sections: (length m, od m, id m, material, elements)."""
    sections = [
        (0.20, 0.05, 0.0, STEEL, 2),  # nodes 0-2: overhung stub, disk at node 0
        (0.60, 0.08, 0.04, TITANIUM, 6),  # nodes 2-8: hollow span, disk at node 5
        (0.30, 0.06, 0.0, STEEL, 3),  # nodes 8-11: solid span to the second bearing
        (0.10, 0.04, 0.0, STEEL, 2),  # nodes 11-13: stub beyond the second bearing
    ]
    shaft = []
    for L, od, i_d, material, n in sections:
        shaft += [rayleigh(L / n, i_d, od, material) for _ in range(n)]
    disks = [
        # Overhung impeller, from geometry.
        rs.DiskElement.from_geometry(n=0, material=STEEL, width=0.05, i_d=0.05, o_d=0.30),
        # Mid-span disk given by mass and inertias.
        rs.DiskElement(n=5, m=40.0, Id=0.35, Ip=0.60),
    ]
    bearings = [
        rs.BearingElement(n=2, kxx=2.0e7, cxx=0.0),
        rs.BearingElement(n=11, kxx=1.0e7, cxx=1.5e3),
    ]
    return rs.Rotor(shaft, disks, bearings)


# Tabulated bearing coefficients, linear in frequency so that ROSS's spline through them
# and a linear interpolation agree (ROSS fits a scipy UnivariateSpline).
SPEED_TABLE = [0.0, 500.0, 1000.0, 1500.0]
SPEED_K = [1.0e6 + 200.0 * w for w in SPEED_TABLE]
SPEED_C = [100.0 + 0.1 * w for w in SPEED_TABLE]
SPEED_DEPENDENT_AT = 1000.0
# A speed between table points: ROSS's spline there is the line through the table.
SPEED_BETWEEN = 750.0


def speed_dependent():
    bearings = [
        rs.BearingElement(n=n, kxx=SPEED_K, cxx=SPEED_C, frequency=SPEED_TABLE)
        for n in (0, 6)
    ]
    return rs.Rotor(example_shaft(), example_disks(), bearings)


def check_speed_dependent(loaded):
    """ROSS evaluates tabulated coefficients at the speed: the modal result at a tabulated
    speed equals that of constant coefficients with the table's values there."""
    i = SPEED_TABLE.index(SPEED_DEPENDENT_AT)
    for b in loaded.bearing_elements:
        for got, want in ((b.kxx_interpolated, SPEED_K[i]), (b.cxx_interpolated, SPEED_C[i])):
            gap = abs(float(got(SPEED_DEPENDENT_AT)) - want) / want
            if not gap <= ROUND_TRIP:
                sys.exit(f"speed_dependent: ROSS's spline misses the table by {gap:.3e}")
        # Between table points the spline is the table's line.
        for got, want in (
            (b.kxx_interpolated, 1.0e6 + 200.0 * SPEED_BETWEEN),
            (b.cxx_interpolated, 100.0 + 0.1 * SPEED_BETWEEN),
        ):
            gap = abs(float(got(SPEED_BETWEEN)) - want) / want
            if not gap <= ROUND_TRIP:
                sys.exit(f"speed_dependent: ROSS's spline leaves the line by {gap:.3e} at {SPEED_BETWEEN}")
    bearings = [
        rs.BearingElement(n=n, kxx=SPEED_K[i], cxx=SPEED_C[i]) for n in (0, 6)
    ]
    constant = rs.Rotor(example_shaft(), example_disks(), bearings)
    a = loaded.run_modal(speed=SPEED_DEPENDENT_AT, num_modes=NUM_MODES).evalues
    b = constant.run_modal(speed=SPEED_DEPENDENT_AT, num_modes=NUM_MODES).evalues
    n = min(len(a), len(b), NUM_MODES // 2)
    gap = np.max(np.abs(a[:n] - b[:n]) / np.abs(b[:n]))
    if not gap <= SOLVER_AGREEMENT:
        sys.exit(f"speed_dependent: tabulated and constant coefficients differ by {gap:.3e}")


def refuse_timoshenko():
    return rs.Rotor(example_shaft(shear_effects=True), example_disks(), example_bearings())


def refuse_tapered_outer():
    shaft = example_shaft()
    shaft[3] = rayleigh(0.25, 0.0, 0.05, STEEL, idr=0.0, odr=0.06, tag="Refused tapered")
    return rs.Rotor(shaft, example_disks(), example_bearings())


def refuse_tapered_bore():
    shaft = example_shaft()
    shaft[3] = rayleigh(0.25, 0.01, 0.05, STEEL, idr=0.02, odr=0.05, tag="Refused bore")
    return rs.Rotor(shaft, example_disks(), example_bearings())


def refuse_anisotropic():
    bearings = example_bearings()
    bearings[1] = rs.BearingElement(
        n=6, kxx=1e6, kyy=0.8e6, cxx=0.0, tag="Refused anisotropic"
    )
    return rs.Rotor(example_shaft(), example_disks(), bearings)


def refuse_anisotropic_damping():
    bearings = example_bearings()
    bearings[1] = rs.BearingElement(
        n=6, kxx=1e6, cxx=100.0, cyy=200.0, tag="Refused anisotropic damping"
    )
    return rs.Rotor(example_shaft(), example_disks(), bearings)


def refuse_cross_coupled():
    bearings = example_bearings()
    bearings[1] = rs.BearingElement(
        n=6, kxx=1e6, kxy=2e5, kyx=-2e5, cxx=0.0, tag="Refused cross-coupled"
    )
    return rs.Rotor(example_shaft(), example_disks(), bearings)


def refuse_linked_bearing():
    """Bearing at node 6 on a pedestal: a point mass (node 7) on a bearing to ground."""
    bearings = [
        rs.BearingElement(n=0, kxx=1e6, cxx=0.0),
        rs.BearingElement(n=6, kxx=1e6, cxx=0.0, n_link=7, tag="Refused linked"),
        rs.BearingElement(n=7, kxx=1e7, cxx=0.0, tag="Pedestal support"),
    ]
    pedestal = [rs.PointMass(n=7, m=10.0, tag="Pedestal mass")]
    return rs.Rotor(example_shaft(), example_disks(), bearings, point_mass_elements=pedestal)


# name -> (builder, speeds for the modal file or None)
ROTORS = {
    "rotor_example_rayleigh": (rotor_example_rayleigh, [0.0, 500.0, 1500.0]),
    # Speeds where no two lateral whirls are within 2 % of each other.
    "stepped_hollow": (stepped_hollow, [0.0, 800.0, 2500.0]),
    "speed_dependent": (speed_dependent, [SPEED_DEPENDENT_AT, SPEED_BETWEEN]),
    "refuse_timoshenko": (refuse_timoshenko, None),
    "refuse_tapered_outer": (refuse_tapered_outer, None),
    "refuse_tapered_bore": (refuse_tapered_bore, None),
    "refuse_anisotropic": (refuse_anisotropic, None),
    "refuse_anisotropic_damping": (refuse_anisotropic_damping, None),
    "refuse_cross_coupled": (refuse_cross_coupled, None),
    "refuse_linked_bearing": (refuse_linked_bearing, None),
}
# Rotors also saved as JSON (Rotor.save picks the format from the extension).
ALSO_JSON = {"rotor_example_rayleigh", "stepped_hollow"}


def check_round_trip(built, loaded, name):
    """The loaded rotor must have the built rotor's matrices (at two frequencies)."""
    pairs = [
        ("M", built.M(0.0), loaded.M(0.0)),
        ("G", built.G(), loaded.G()),
    ]
    for w in (0.0, SPEED_DEPENDENT_AT):
        pairs += [("K", built.K(w), loaded.K(w)), ("C", built.C(w), loaded.C(w))]
    for label, a, b in pairs:
        scale = max(np.abs(a).max(), 1.0)
        gap = np.abs(a - b).max() / scale
        if not gap <= ROUND_TRIP:
            sys.exit(f"{name}: saved-and-loaded {label} differs from the built one by {gap:.3e}")


# Tolerance of the element check below: both sides are a few products of the same
# inputs, so only round-off may differ.
ELEMENT_MATCH = 1e-12


def check_rayleigh_element(element):
    """ROSS's uniform element with shear_effects=False is the textbook Rayleigh beam.

    Built here independently, per lateral plane on the Hermite cubics of (u, du/dz):
    translational mass rho*A*L/420 [156 22L 54 -13L; ...], rotary inertia
    rho*I/(30L) [36 3L -36 3L; ...], Euler-Bernoulli stiffness E*I/L^3 [12 6L -12 6L; ...],
    with A = pi(od^2 - id^2)/4 and I = pi(od^4 - id^4)/64, and ROSS's rotations
    beta = dx/dz, alpha = -dy/dz. The gyroscopic matrix is rho*Ip * integral of
    (Ba' Bb - Bb' Ba) with Ip = 2I, the same form as ROSS's disk (G[alpha, beta] = +Ip).
    Lateral DOFs must not couple to the axial and torsional ones.
    """
    L, od, i_d = element.L, element.odl, element.idl
    rho, E = element.material.rho, element.material.E
    A = math.pi * (od**2 - i_d**2) / 4
    I = math.pi * (od**4 - i_d**4) / 64
    # fmt: off
    t = L / 420 * np.array([[156, 22 * L, 54, -13 * L], [22 * L, 4 * L * L, 13 * L, -3 * L * L],
                            [54, 13 * L, 156, -22 * L], [-13 * L, -3 * L * L, -22 * L, 4 * L * L]])
    r = 1 / (30 * L) * np.array([[36, 3 * L, -36, 3 * L], [3 * L, 4 * L * L, -3 * L, -L * L],
                                 [-36, -3 * L, 36, -3 * L], [3 * L, -L * L, -3 * L, 4 * L * L]])
    k = 1 / L**3 * np.array([[12, 6 * L, -12, 6 * L], [6 * L, 4 * L * L, -6 * L, 2 * L * L],
                             [-12, -6 * L, 12, -6 * L], [6 * L, 2 * L * L, -6 * L, 4 * L * L]])
    # fmt: on
    # ROSS's local order: x0 y0 z0 alpha0 beta0 theta0, x1 y1 z1 alpha1 beta1 theta1.
    sx = np.zeros((4, 12))  # (x, dx/dz) at both ends
    sy = np.zeros((4, 12))  # (y, dy/dz) at both ends
    for row, (col, sign) in enumerate([(0, 1), (4, 1), (6, 1), (10, 1)]):
        sx[row, col] = sign
    for row, (col, sign) in enumerate([(1, 1), (3, -1), (7, 1), (9, -1)]):
        sy[row, col] = sign
    mass = rho * A * (sx.T @ t @ sx + sy.T @ t @ sy) + rho * I * (sx.T @ r @ sx + sy.T @ r @ sy)
    stiffness = E * I * (sx.T @ k @ sx + sy.T @ k @ sy)
    b_alpha, b_beta = -sy, sx  # alpha = -N' sy q, beta = N' sx q
    gyro = rho * 2 * I * (b_alpha.T @ r @ b_beta - b_beta.T @ r @ b_alpha)
    lateral = [0, 1, 3, 4, 6, 7, 9, 10]
    other = [2, 5, 8, 11]
    for label, ross_matrix, textbook in (
        ("M", element.M(), mass),
        ("K", element.K(), stiffness),
        ("G", element.G(), gyro),
    ):
        block = ross_matrix[np.ix_(lateral, lateral)]
        gap = np.abs(block - textbook[np.ix_(lateral, lateral)]).max() / np.abs(block).max()
        coupling = np.abs(ross_matrix[np.ix_(lateral, other)]).max()
        if not (gap <= ELEMENT_MATCH and coupling == 0.0):
            sys.exit(f"ROSS's Rayleigh element {label} is not the textbook one ({gap:.3e})")


def whirl_index(modal, i, number_dof):
    """Amplitude-weighted orbit sense of mode i: +1 forward circular, -1 backward.

    With x = Re(X e^{jwt}) and y = Re(Y e^{jwt}) at each node (X, Y the eigenvector's
    complex x and y entries, w = wd > 0), a forward (counter-clockwise, from +x to +y,
    the sense of rotation) circular orbit has Y = -jX, a backward one Y = +jX. The index
    is -2 sum Im(conj(X) Y) / sum(|X|^2 + |Y|^2) over all nodes: unlike ROSS's
    whirl_direction(), which needs every node's orbit to agree, it does not depend on the
    noise at a node where the mode has no translation.
    """
    v = modal.evectors[: modal.ndof, i]
    n_nodes = len(modal.nodes)
    x = v[0 : number_dof * n_nodes : number_dof]
    y = v[1 : number_dof * n_nodes : number_dof]
    energy = float(np.sum(np.abs(x) ** 2 + np.abs(y) ** 2))
    return float(-2.0 * np.sum(np.imag(np.conj(x) * y)) / energy)


def finite(value, what):
    value = float(value)
    if not math.isfinite(value):
        sys.exit(f"{what} is not finite: {value}")
    return value


def modal_record(rotor, name, speed):
    modal = rotor.run_modal(speed=speed, num_modes=NUM_MODES)
    dense = rotor.run_modal(speed=speed, num_modes=NUM_MODES, sparse=False)
    n = len(modal.wd)
    if len(dense.wd) < n:
        sys.exit(f"{name} at {speed} rad/s: the dense solver found fewer modes")
    gap = np.max(np.abs(modal.evalues[:n] - dense.evalues[:n]) / np.abs(dense.evalues[:n]))
    if not gap <= SOLVER_AGREEMENT:
        sys.exit(f"{name} at {speed} rad/s: sparse and dense eigenvalues differ by {gap:.3e}")

    whirls = modal.whirl_direction()
    modes = []
    for i in range(n):
        mode_type = modal.shapes[i].mode_type
        ross_whirl = "None" if whirls[i] is None else str(whirls[i])
        record = {
            "wn": finite(modal.wn[i], "wn"),
            "wd": finite(modal.wd[i], "wd"),
            "damping_ratio": finite(modal.damping_ratio[i], "damping ratio"),
            "log_dec": finite(modal.log_dec[i], "log decrement"),
            "eigenvalue_re": finite(modal.evalues[i].real, "Re eigenvalue"),
            "eigenvalue_im": finite(modal.evalues[i].imag, "Im eigenvalue"),
            "mode_type": mode_type,
            "whirl": ross_whirl,
        }
        if mode_type == "Lateral":
            index = whirl_index(modal, i, rotor.number_dof)
            if index >= CIRCULAR_WHIRL_MIN:
                orbit = "Forward"
            elif index <= -CIRCULAR_WHIRL_MIN:
                orbit = "Backward"
            else:
                orbit = "Mixed"
            # ROSS's Forward (Backward) means every node's orbit turns forward
            # (backward), so every term of the index has that sign.
            if (ross_whirl == "Forward" and index <= 0.0) or (
                ross_whirl == "Backward" and index >= 0.0
            ):
                sys.exit(
                    f"{name} at {speed} rad/s, mode {i}: ROSS says {ross_whirl}, "
                    f"the orbit index {index:+.6f}"
                )
            record["whirl_index"] = index
            record["whirl_from_orbit"] = orbit
        else:
            if ross_whirl != "None":
                sys.exit(f"{name}: a {mode_type} mode with whirl {ross_whirl}")
            record["whirl_index"] = None
            record["whirl_from_orbit"] = "None"
        modes.append(record)

    lateral = [m for m in modes if m["mode_type"] == "Lateral"]
    result = {
        "speed": float(speed),
        "modes": modes,
        "lateral_wd": sorted(m["wd"] for m in lateral),
    }
    if speed > 0.0:
        mixed = [m["wd"] for m in lateral if m["whirl_from_orbit"] == "Mixed"]
        if mixed:
            sys.exit(f"{name} at {speed} rad/s: non-circular lateral modes at {mixed}")
        forward = sorted(m["wd"] for m in lateral if m["whirl_from_orbit"] == "Forward")
        backward = sorted(m["wd"] for m in lateral if m["whirl_from_orbit"] == "Backward")
        if len(forward) < 4 or len(backward) < 4:
            sys.exit(f"{name} at {speed} rad/s: fewer than 4 forward or 4 backward whirls")
        result["lateral_forward_wd"] = forward
        result["lateral_backward_wd"] = backward
    elif len(lateral) < 8:
        sys.exit(f"{name} at rest: fewer than 8 lateral modes")
    return result


def modal_file(rotor, name, speeds):
    return {
        "ross_version": rs.__version__,
        "generator": "scripts/ross/make_fixtures.py",
        "rotor_file": f"{name}.toml",
        "call": "Rotor.load(rotor_file).run_modal(speed=speed, num_modes=num_modes)",
        "num_modes": NUM_MODES,
        "modes_kept": NUM_MODES // 2,
        "units": {
            "speed": "rad/s",
            "wn": "rad/s (ROSS: |eigenvalue|)",
            "wd": "rad/s (ROSS: Im eigenvalue)",
            "damping_ratio": "- (ROSS: -Re/|eigenvalue|)",
            "log_dec": "- (ROSS: 2 pi zeta / sqrt(1 - zeta^2))",
            "eigenvalue_re": "1/s",
            "eigenvalue_im": "rad/s",
        },
        "notes": [
            "modes are ROSS's order: wd ascending, the lowest num_modes // 2 with wd > 0",
            "mode_type is ROSS's Shape.mode_type; Axial and Torsional modes have whirl "
            "'None' and are not part of a lateral model",
            "whirl is ROSS's whirl_direction(): 'Mixed' when one node's orbit disagrees, "
            "which happens at a node where the mode has no translation",
            "whirl_from_orbit classifies whirl_index (amplitude-weighted orbit sense, +1 "
            f"forward circular, -1 backward) with |index| >= {CIRCULAR_WHIRL_MIN}, else "
            "'Mixed'; its sign agrees with whirl wherever whirl is Forward or Backward",
            "at speed 0 forward and backward coincide: every lateral frequency appears "
            "twice and its whirl labels are arbitrary",
        ],
        "speeds": [float(w) for w in speeds],
        "results": [modal_record(rotor, name, w) for w in speeds],
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    root = Path(__file__).resolve().parents[2]
    parser.add_argument("--out", type=Path, default=root / "tests" / "fixtures" / "ross")
    parser.add_argument("--any-ross-version", action="store_true")
    args = parser.parse_args()
    if rs.__version__ != ROSS_VERSION and not args.any_ross_version:
        sys.exit(f"ROSS {rs.__version__} found, the fixtures are for {ROSS_VERSION}")
    args.out.mkdir(parents=True, exist_ok=True)
    # A solid and a hollow element of the fixtures, two materials.
    check_rayleigh_element(rayleigh(0.25, 0.0, 0.05, STEEL))
    check_rayleigh_element(rayleigh(0.1, 0.04, 0.08, TITANIUM))

    for name, (build, speeds) in ROTORS.items():
        built = build()
        suffixes = [".toml", ".json"] if name in ALSO_JSON else [".toml"]
        for suffix in suffixes:
            path = args.out / f"{name}{suffix}"
            built.save(path)
            check_round_trip(built, rs.Rotor.load(path), path.name)
        if speeds is not None:
            loaded = rs.Rotor.load(args.out / f"{name}.toml")
            if name == "speed_dependent":
                check_speed_dependent(loaded)
            data = modal_file(loaded, name, speeds)
            text = json.dumps(data, indent=1, allow_nan=False) + "\n"
            (args.out / f"{name}.modal.json").write_text(text)
        print(f"wrote {name}")


if __name__ == "__main__":
    main()
