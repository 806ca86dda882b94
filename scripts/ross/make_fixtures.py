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
* `rotor_example_timoshenko.toml` and `.modal.json`: rotor_example_rayleigh with ROSS's
  default Timoshenko elements (`shear_effects=True`, Cowper's shear coefficient), on the
  same isotropic bearings: the Timoshenko path checked against ROSS before anisotropic
  bearings exist.
  Its `.unbalance.json` is `run_unbalance_response` with 1e-3 kg m on the disk at node 2,
  at nodes 2, 3 and 4 over the 100 speeds of rotor_example's.
* `tapered.toml` and `.modal.json`: the rotor_example geometry with Timoshenko elements,
  two of them tapered in the outer diameter (a bulge), one with a tapered bore and
  ROSS's `hutchinson` shear coefficient.
* `held_out.toml` and `.modal.json`: a Timoshenko rotor with three tapered elements, two
  materials, hollow sections, three disks and damped bearings, written to check the
  import on a rotor never used while the Timoshenko and taper code was written (see
  `held_out` below).
* `layered.toml` and `compressor_shaft.toml` (+ `.modal.json`): concentric layers (shaft
  elements of one `n`), on the rotor_example geometry and on ROSS's compressor shaft
  (its 91 elements and 7 disks on isotropic bearings, no seals).
* `rotor_example.toml`, `compressor_example.toml`: ROSS's own `rs.rotor_example()` and
  `rs.compressor_example()`, saved as ROSS saves them (`Rotor.save` with its defaults);
  their `.modal.json` hold the lowest 8 lateral whirls of `run_modal` at three speeds
  (wd, ROSS's whirl_direction() and the orbit's shape), and
  `rotor_example.unbalance.json` holds `run_unbalance_response` at three nodes over 100
  speeds. Both rotors have anisotropic or cross-coupled supports (and the compressor
  concentric shaft layers and seals), which rotorshunt does not represent yet.
* `refuse_*.toml`: rotors the importer must refuse; where one element is at fault its
  tag starts with `Refused`: an anisotropic bearing (kxx != kyy), anisotropic bearing
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

# A node whose orbit's major axis is below this fraction of the mode's largest is at rest:
# its orbit is round-off (1e-11 to 1e-13 of the largest at rotor_example's mid-span node
# in its antisymmetric modes), and its sense does not count in whirl_of_moving_nodes.
# The same threshold as rotorshunt's whirl classification (docs/model.md).
MOVING_NODE = 1e-9

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


def timoshenko(L, idl, odl, material, idr=None, odr=None, tag=None, **kw):
    """A ROSS shaft element with ROSS's defaults: Timoshenko, rotary inertia, gyroscopic,
    Cowper's shear coefficient (unless `shear_method_calc` is given)."""
    return rs.ShaftElement(L=L, idl=idl, odl=odl, idr=idr, odr=odr, material=material, tag=tag, **kw)


def rotor_example_timoshenko():
    """rotor_example_rayleigh with ROSS's default (Timoshenko) elements."""
    shaft = [timoshenko(0.25, 0.0, 0.05, STEEL) for _ in range(6)]
    return rs.Rotor(shaft, example_disks(), example_bearings())


def tapered():
    """The rotor_example geometry, Timoshenko: elements 1 and 2 a bulge of the outer
    diameter (0.05 -> 0.07 -> 0.05 m), element 4 hollow with a tapered bore
    (0.01 -> 0.02 m) and ROSS's hutchinson shear coefficient."""
    shaft = [
        timoshenko(0.25, 0.0, 0.05, STEEL),
        timoshenko(0.25, 0.0, 0.05, STEEL, idr=0.0, odr=0.07, tag="Bulge up"),
        timoshenko(0.25, 0.0, 0.07, STEEL, idr=0.0, odr=0.05, tag="Bulge down"),
        timoshenko(0.25, 0.0, 0.05, STEEL),
        timoshenko(
            0.25, 0.01, 0.05, STEEL, idr=0.02, odr=0.05, shear_method_calc="hutchinson", tag="Tapered bore"
        ),
        timoshenko(0.25, 0.0, 0.05, STEEL),
    ]
    return rs.Rotor(shaft, example_disks(), example_bearings())


# A second material for the held-out rotor: ROSS's own docstring example (materials.py).
AISI4140 = rs.Material(name="AISI4140", rho=7850.0, E=203.2e9, G_s=80e9)


def held_out():
    """Held out: written before any comparison of tapered Timoshenko rotors with ROSS and
    compared only once the code was done (tests/ross_reference.rs). 16 Timoshenko
    elements: a solid steel journal, a taper up, a hollow AISI4140 span, a taper of both
    diameters (hutchinson), a hollow span (hutchinson), a taper down to a solid steel
    stub; an overhung disk at each end and one by mass mid-span; damped isotropic
    bearings at interior nodes 2 and 13."""
    shaft = (
        [timoshenko(0.08, 0.0, 0.06, STEEL) for _ in range(2)]
        + [timoshenko(0.05, 0.0, 0.06, STEEL, idr=0.0, odr=0.09)]
        + [timoshenko(0.1, 0.03, 0.09, AISI4140) for _ in range(6)]
        + [timoshenko(0.06, 0.03, 0.09, AISI4140, idr=0.02, odr=0.07, shear_method_calc="hutchinson")]
        + [timoshenko(0.07, 0.02, 0.07, AISI4140, shear_method_calc="hutchinson") for _ in range(3)]
        + [timoshenko(0.05, 0.0, 0.07, STEEL, idr=0.0, odr=0.05)]
        + [timoshenko(0.06, 0.0, 0.05, STEEL) for _ in range(2)]
    )
    disks = [
        rs.DiskElement.from_geometry(n=0, material=STEEL, width=0.04, i_d=0.06, o_d=0.25),
        rs.DiskElement(n=6, m=25.0, Id=0.2, Ip=0.35),
        rs.DiskElement.from_geometry(n=16, material=STEEL, width=0.03, i_d=0.05, o_d=0.2),
    ]
    bearings = [
        rs.BearingElement(n=2, kxx=5.0e7, cxx=2.0e3),
        rs.BearingElement(n=13, kxx=3.0e7, cxx=1.0e3),
    ]
    return rs.Rotor(shaft, disks, bearings)


def held_out_supports():
    """Held out (issue 28, points 4-5): written into this script, and its fixture made,
    before it was first imported or compared with rotorshunt; compared once, at the end.
    11 Timoshenko elements of two materials (a hollow span, a taper), a disk from
    geometry, a disk by mass; a fluid-film-like bearing with
    all eight coefficients tabulated over 5 frequencies and a constant added mass, an
    anisotropic constant bearing, and a seal with cross-coupled stiffness and damping
    tabulated over 4 frequencies that start above 0."""
    shaft = (
        [timoshenko(0.1, 0.0, 0.06, STEEL) for _ in range(2)]
        + [timoshenko(0.15, 0.02, 0.08, AISI4140) for _ in range(5)]
        + [timoshenko(0.1, 0.02, 0.08, AISI4140, idr=0.0, odr=0.06)]
        + [timoshenko(0.12, 0.0, 0.06, STEEL, shear_method_calc="hutchinson") for _ in range(3)]
    )
    disks = [
        rs.DiskElement.from_geometry(n=4, material=STEEL, width=0.06, i_d=0.08, o_d=0.35),
        rs.DiskElement(n=10, m=12.0, Id=0.08, Ip=0.15),
    ]
    frequency = [0.0, 400.0, 800.0, 1200.0, 1600.0]

    def tab(f):
        return [float(f(w / 1600.0)) for w in frequency]

    bearing = rs.BearingElement(
        n=1,
        kxx=tab(lambda r: 4.0e7 * (1.0 + 0.3 * r**1.5)),
        kyy=tab(lambda r: 2.5e7 * (1.0 + 0.5 * r**1.5)),
        kxy=tab(lambda r: 6.0e6 * r),
        kyx=tab(lambda r: -9.0e6 * r),
        cxx=tab(lambda r: 3.0e4 * (1.0 - 0.2 * r)),
        cyy=tab(lambda r: 4.0e4 * (1.0 - 0.25 * r)),
        cxy=tab(lambda r: 1.5e3 * r),
        cyx=tab(lambda r: 1.5e3 * r),
        mxx=[2.0] * len(frequency),
        frequency=frequency,
        tag="Journal",
    )
    seal_frequency = [200.0, 700.0, 1200.0, 1700.0]

    def seal_tab(f):
        return [float(f(w / 1700.0)) for w in seal_frequency]

    seal = rs.SealElement(
        n=6,
        kxx=seal_tab(lambda r: 2.0e6 * (1.0 + 0.1 * r)),
        kxy=seal_tab(lambda r: 8.0e5 * r),
        kyx=seal_tab(lambda r: -8.0e5 * r),
        cxx=seal_tab(lambda r: 800.0 * (1.0 - 0.1 * r)),
        cxy=seal_tab(lambda r: 120.0 * r),
        cyx=seal_tab(lambda r: -120.0 * r),
        frequency=seal_frequency,
        tag="Balance piston",
    )
    bearings = [bearing, rs.BearingElement(n=9, kxx=3.0e7, kyy=5.0e7, cxx=1.0e3, cyy=1.5e3, tag="Outboard"), seal]
    # No point mass: ROSS 2.3.0 gives every point mass 3 DOFs of its own beyond the shaft
    # (Rotor.ndof), so one on a shaft node leaves them massless and run_modal fails on a
    # singular M; a point mass is a pedestal, refused by the importer.
    return rs.Rotor(shaft, disks, bearings)


# A sleeve material as ROSS's compressor example has one (`shaft_mat_2`): mass, and a
# stiffness of 1 psi, i.e. none.
SLEEVE = rs.Material(name="Sleeve", rho=7833.412, E=6894.75, G_s=6894.75)


def layered():
    """rotor_example_timoshenko with concentric layers (elements of one n): a massless-
    stiffness sleeve over elements 1 and 2 (od 0.05 -> 0.09 m), a steel sleeve over
    element 4 (od 0.05 -> 0.07 m, Rayleigh) and a tapered steel sleeve over element 5."""
    shaft = [timoshenko(0.25, 0.0, 0.05, STEEL, n=k, tag=f"Core {k}") for k in range(6)]
    for k in (1, 2):
        shaft.append(timoshenko(0.25, 0.05, 0.09, SLEEVE, n=k, tag=f"Sleeve {k}"))
    shaft.append(rayleigh(0.25, 0.05, 0.07, STEEL, n=4, tag="Steel sleeve 4"))
    shaft.append(timoshenko(0.25, 0.05, 0.08, STEEL, idr=0.05, odr=0.06, n=5, tag="Tapered sleeve 5"))
    return rs.Rotor(shaft, example_disks(), example_bearings())


def compressor_shaft():
    """ROSS's compressor example's shaft and disks (91 Timoshenko elements, 36 of them
    concentric layers) on isotropic damped bearings at its bearings' nodes 7 and 48,
    without seals: its shaft checked against ROSS before anisotropic supports exist."""
    example = rs.compressor_example()
    bearings = [rs.BearingElement(n=n, kxx=1.0e8, cxx=2.0e3) for n in (7, 48)]
    return rs.Rotor(example.shaft_elements, example.disk_elements, bearings)


def rotor_example():
    """ROSS's own example, as it is: Timoshenko elements, anisotropic bearings."""
    return rs.rotor_example()


def compressor_example():
    """ROSS's own compressor example, as it is: 91 Timoshenko elements (some stacked as
    concentric layers), 7 disks, two bearings and 12 seals with speed tables."""
    return rs.compressor_example()


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


def refuse_magnetic():
    """A magnetic bearing at node 6 (PID controller), saved by ROSS under BearingElement
    with its controller's parameters: refused, naming it."""
    bearings = [
        rs.BearingElement(n=0, kxx=1e6, cxx=0.0),
        rs.MagneticBearingElement(
            n=6, g0=1e-3, i0=1.0, ag=1e-4, nw=200, kp_pid=1.0, kd_pid=1e-3, tag="Refused magnetic"
        ),
    ]
    return rs.Rotor(example_shaft(), example_disks(), bearings)


def refuse_several():
    """Five refusals in one file, listed by one import: proportional damping on element
    2, rotary inertia off on element 4, a bearing at node 6 linked to a pedestal (a point
    mass at node 7 beyond the shaft) and the pedestal's bearing to the ground."""
    shaft = example_shaft()
    shaft[2] = rayleigh(0.25, 0.0, 0.05, STEEL, alpha=2.0, tag="Refused damped")
    shaft[4] = rs.ShaftElement(
        L=0.25,
        idl=0.0,
        odl=0.05,
        material=STEEL,
        shear_effects=False,
        rotary_inertia=False,
        gyroscopic=True,
        tag="Refused no rotary inertia",
    )
    bearings = [
        rs.BearingElement(n=0, kxx=1e6, cxx=0.0),
        rs.BearingElement(n=6, kxx=1e6, cxx=0.0, n_link=7, tag="Refused linked"),
        rs.BearingElement(n=7, kxx=1e7, cxx=0.0, tag="Refused pedestal support"),
    ]
    pedestal = [rs.PointMass(n=7, m=10.0, tag="Refused pedestal")]
    return rs.Rotor(shaft, example_disks(), bearings, point_mass_elements=pedestal)


# name -> (builder, speeds for the modal file or None)
ROTORS = {
    "rotor_example_rayleigh": (rotor_example_rayleigh, [0.0, 500.0, 1500.0]),
    # Speeds where no two lateral whirls are within 2 % of each other.
    "stepped_hollow": (stepped_hollow, [0.0, 800.0, 2500.0]),
    "speed_dependent": (speed_dependent, [SPEED_DEPENDENT_AT, SPEED_BETWEEN]),
    "rotor_example_timoshenko": (rotor_example_timoshenko, [0.0, 500.0, 1500.0]),
    "tapered": (tapered, [0.0, 500.0, 1500.0]),
    "held_out": (held_out, [0.0, 1000.0, 3000.0]),
    "layered": (layered, [0.0, 500.0, 1500.0]),
    "compressor_shaft": (compressor_shaft, [0.0, 500.0, 1000.0]),
    "refuse_anisotropic": (refuse_anisotropic, None),
    "refuse_anisotropic_damping": (refuse_anisotropic_damping, None),
    "refuse_cross_coupled": (refuse_cross_coupled, None),
    "refuse_linked_bearing": (refuse_linked_bearing, None),
    "refuse_magnetic": (refuse_magnetic, None),
    "refuse_several": (refuse_several, None),
}
# ROSS's own examples, saved as they are: name -> (builder, speeds of the whirl file).
# The compressor's speeds lie inside every one of its bearing and seal tables (419 to
# 1152 rad/s), where ROSS interpolates rather than extrapolates.
EXAMPLES = {
    "rotor_example": (rotor_example, [0.0, 500.0, 1500.0]),
    "compressor_example": (compressor_example, [500.0, 800.0, 1100.0]),
    # Speeds inside its seal's table (200 to 1700 rad/s) and its bearing's (0 to 1600).
    "held_out_supports": (held_out_supports, [500.0, 900.0, 1400.0]),
}
# The lowest lateral whirls recorded per speed for ROSS's examples.
EXAMPLE_WHIRLS = 8

# run_unbalance_response of rotor_example: ROSS's own docstring call (node 3, 10 kg m,
# phase 0) on 100 speeds from 10 to 1000 rad/s (no speed 0, where the response is 0),
# recorded at nodes 2, 3 and 4 (the disks and mid-span).
UNBALANCE = {"node": 3, "magnitude": 10.0, "phase": 0.0}
# rotor_example_timoshenko's unbalance, on the disk at node 2 (where rotorshunt places an
# unbalance, as a disk's eccentricity): 1e-3 kg m at phase 0, the same speeds and nodes.
UNBALANCE_ISOTROPIC = {"node": 2, "magnitude": 1.0e-3, "phase": 0.0}
UNBALANCE_SPEEDS = [10.0 * (k + 1) for k in range(100)]
UNBALANCE_NODES = [2, 3, 4]
# held_out_supports's unbalance: 2e-4 kg m at phase 0.5 rad on its disk at node 4, over
# 100 speeds inside its tables (250 to 1537 rad/s), at its two bearings and the disk.
UNBALANCE_HELD_OUT = {"node": 4, "magnitude": 2.0e-4, "phase": 0.5}
UNBALANCE_HELD_OUT_SPEEDS = [250.0 + 13.0 * k for k in range(100)]
UNBALANCE_HELD_OUT_NODES = [1, 4, 9]

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


def check_timoshenko_element(element):
    """ROSS's Timoshenko element (Genta & Gugliotta's conical element as ROSS writes it)
    is the exact integral of the beam energies over Nelson's (1980) shape functions, with
    the shear parameter phi = 12 E I / (kappa G A L^2) of the element's middle section:

        M = int rho A N^T N + int rho I P^T P,   G = 2 int rho I P^T P (as ROSS's disk),
        K = int E I P'^T P' + int kappa G A (N' - P)^T (N' - P),

    A(z) and I(z) of the linearly varying diameters, per lateral plane on (u, du/dz) at
    both ends. rotorshunt builds its elements this way (src/model/element.rs), so this
    check is what lets its Timoshenko and tapered elements be ROSS's. Integrated here by
    8-point Gauss-Legendre (exact: the integrands are polynomials of degree <= 8).
    """
    L, E, G, rho = element.L, element.material.E, element.material.G_s, element.material.rho
    odl, odr, idl, idr = element.odl, element.odr, element.idl, element.idr

    def area(t):
        do, di = odl + (odr - odl) * t, idl + (idr - idl) * t
        return math.pi * (do**2 - di**2) / 4

    def inertia(t):
        do, di = odl + (odr - odl) * t, idl + (idr - idl) * t
        return math.pi * (do**4 - di**4) / 64

    phi = element.phi
    d = 1 + phi
    mass, stiff, gyro = np.zeros((4, 4)), np.zeros((4, 4)), np.zeros((4, 4))
    points, weights = np.polynomial.legendre.leggauss(8)
    for p, w in zip(points, weights):
        t, w = (p + 1) / 2, w * L / 2
        n = np.array([1 - 3 * t**2 + 2 * t**3 + phi * (1 - t), L * (t - 2 * t**2 + t**3 + phi / 2 * (t - t**2)),
                      3 * t**2 - 2 * t**3 + phi * t, L * (-t**2 + t**3 + phi / 2 * (t**2 - t))]) / d
        dn = np.array([-6 * t + 6 * t**2 - phi, L * (1 - 4 * t + 3 * t**2 + phi / 2 * (1 - 2 * t)),
                       6 * t - 6 * t**2 + phi, L * (-2 * t + 3 * t**2 + phi / 2 * (2 * t - 1))]) / (d * L)
        r = np.array([6 * (t**2 - t) / L, 1 - 4 * t + 3 * t**2 + phi * (1 - t),
                      6 * (t - t**2) / L, -2 * t + 3 * t**2 + phi * t]) / d
        dr = np.array([6 * (2 * t - 1) / L, -4 + 6 * t - phi, 6 * (1 - 2 * t) / L, -2 + 6 * t + phi]) / (d * L)
        mass += w * rho * (area(t) * np.outer(n, n) + inertia(t) * np.outer(r, r))
        gyro += w * 2 * rho * inertia(t) * np.outer(r, r)
        stiff += w * E * inertia(t) * np.outer(dr, dr)
        if phi > 0:
            kappa_g = 12 * E * inertia(0.5) / (phi * area(0.5) * L**2)
            strain = dn - r
            stiff += w * kappa_g * area(t) * np.outer(strain, strain)
    x_plane = [0, 4, 6, 10]  # x, beta = dx/dz at both ends
    for label, ross_matrix, textbook in (("M", element.M(), mass), ("K", element.K(), stiff)):
        block = ross_matrix[np.ix_(x_plane, x_plane)]
        gap = np.abs(block - textbook).max() / np.abs(block).max()
        if not gap <= ELEMENT_MATCH:
            sys.exit(f"ROSS's Timoshenko element {label} is not the integral over Nelson's shapes ({gap:.3e})")
    # G couples the planes: G[y-plane rows (y, alpha = -dy/dz), x-plane columns] = -g.
    y_plane, sign = [1, 3, 7, 9], np.diag([1.0, -1.0, 1.0, -1.0])
    block = sign @ element.G()[np.ix_(y_plane, x_plane)]
    gap = np.abs(block + gyro).max() / np.abs(gyro).max()
    if not gap <= ELEMENT_MATCH:
        sys.exit(f"ROSS's Timoshenko element G is not the integral over Nelson's shapes ({gap:.3e})")


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


def example_whirls(rotor, name, speed):
    """The lowest EXAMPLE_WHIRLS lateral modes of run_modal at `speed`, axial and
    torsional ones (whirl "None") left out: wd with ROSS's whirl_direction() verbatim,
    the amplitude-weighted orbit sense (whirl_index) and, per mode, the largest ratio of
    minor to major semi-axis over the nodes (1 circular, 0 a line)."""
    modal = rotor.run_modal(speed=speed, num_modes=NUM_MODES)
    dense = rotor.run_modal(speed=speed, num_modes=NUM_MODES, sparse=False)
    n = len(modal.wd)
    gap = np.max(np.abs(modal.evalues[:n] - dense.evalues[:n]) / np.abs(dense.evalues[:n]))
    if not gap <= SOLVER_AGREEMENT:
        sys.exit(f"{name} at {speed} rad/s: sparse and dense eigenvalues differ by {gap:.3e}")
    whirls = modal.whirl_direction()
    modes = []
    for i in range(n):
        ross_whirl = "None" if whirls[i] is None else str(whirls[i])
        if ross_whirl == "None":
            continue
        v = modal.evectors[: modal.ndof, i]
        nodes = len(modal.nodes)
        x = v[0 : rotor.number_dof * nodes : rotor.number_dof]
        y = v[1 : rotor.number_dof * nodes : rotor.number_dof]
        # Semi-axes of the ellipse traced by (Re X e^{jwt}, Re Y e^{jwt}): x + jy is a
        # forward circle of radius |X + jY|/2 plus a backward one of radius |X - jY|/2,
        # so major = sum of the radii and minor = their difference.
        forward = np.abs(x + 1j * y) / 2
        backward = np.abs(x - 1j * y) / 2
        major = forward + backward
        big = major > 1e-3 * np.max(major)
        ratio = float(np.max(np.abs(forward - backward)[big] / major[big]))
        # ROSS's own rule (every node's orbit sense, Shape._calculate_orbits) over the
        # nodes that move: a node whose orbit is below MOVING_NODE of the largest is at
        # rest, and the sense of its round-off orbit decides nothing.
        orbits = modal.shapes[i].orbits
        largest = max(o.major_axis for o in orbits)
        senses = {o.whirl for o in orbits if o.major_axis >= MOVING_NODE * largest}
        moving = senses.pop() if len(senses) == 1 else "Mixed"
        modes.append(
            {
                "wd": finite(modal.wd[i], "wd"),
                "wn": finite(modal.wn[i], "wn"),
                "damping_ratio": finite(modal.damping_ratio[i], "damping ratio"),
                "eigenvalue_re": finite(modal.evalues[i].real, "Re eigenvalue"),
                "eigenvalue_im": finite(modal.evalues[i].imag, "Im eigenvalue"),
                "mode_type": modal.shapes[i].mode_type,
                "whirl": ross_whirl,
                "whirl_index": whirl_index(modal, i, rotor.number_dof),
                "max_minor_to_major": ratio,
                "whirl_of_moving_nodes": moving,
            }
        )
    modes.sort(key=lambda m: m["wd"])
    if len(modes) < EXAMPLE_WHIRLS:
        sys.exit(f"{name} at {speed} rad/s: only {len(modes)} lateral modes")
    return {"speed": float(speed), "modes": modes[:EXAMPLE_WHIRLS]}


def example_file(rotor, name, speeds):
    return {
        "ross_version": rs.__version__,
        "generator": "scripts/ross/make_fixtures.py",
        "rotor_file": f"{name}.toml",
        "call": "Rotor.load(rotor_file).run_modal(speed=speed, num_modes=num_modes)",
        "num_modes": NUM_MODES,
        "units": {"speed": "rad/s", "wd": "rad/s (ROSS: Im eigenvalue)", "wn": "rad/s (ROSS: |eigenvalue|)"},
        "notes": [
            f"per speed, the lowest {EXAMPLE_WHIRLS} lateral modes by wd; ROSS's axial and "
            "torsional modes (whirl 'None') are left out",
            "whirl is ROSS's whirl_direction() verbatim (Forward, Backward or Mixed)",
            "whirl_index is the amplitude-weighted orbit sense (+1 forward circular, -1 "
            "backward circular); max_minor_to_major the largest minor/major semi-axis "
            "ratio over the nodes that move (1 circular, 0 a straight line)",
            "whirl_of_moving_nodes is ROSS's rule (Forward if every node's orbit turns "
            "forward, Backward if every one turns backward, else Mixed) over the nodes "
            f"whose orbit's major axis is at least {MOVING_NODE:g} of the largest: a node "
            "at rest (the mid-span node of an antisymmetric mode) has a round-off orbit "
            "whose sense is noise",
        ],
        "speeds": [float(w) for w in speeds],
        "results": [example_whirls(rotor, name, w) for w in speeds],
    }


UNDAMPED_NOTE = (
    "the rotor is undamped: amplitudes grow without bound at its critical speeds, "
    "which the speeds (10 to 1000 rad/s in steps of 10) do not hit"
)


def unbalance_file(rotor, name, unbalance=UNBALANCE, speeds=None, at=None, note=UNDAMPED_NOTE):
    """run_unbalance_response of the rotor: x and y amplitude and phase at the nodes `at`
    (default UNBALANCE_NODES) over `speeds` (default UNBALANCE_SPEEDS). ROSS applies F_x = m e^{jp} w^2,
    F_y = -j m e^{jp} w^2 at the node (a forward rotating force) and returns the complex
    amplitudes X, Y with x(t) = Re(X e^{jwt})."""
    speeds = UNBALANCE_SPEEDS if speeds is None else speeds
    at = UNBALANCE_NODES if at is None else at
    response = rotor.run_unbalance_response(
        node=unbalance["node"],
        unbalance_magnitude=unbalance["magnitude"],
        unbalance_phase=unbalance["phase"],
        frequency=np.array(speeds),
    )
    nodes = []
    for node in at:
        x = response.forced_resp[rotor.number_dof * node]
        y = response.forced_resp[rotor.number_dof * node + 1]
        nodes.append(
            {
                "node": node,
                "x_amplitude": [finite(a, "x amplitude") for a in np.abs(x)],
                "x_phase": [finite(a, "x phase") for a in np.angle(x)],
                "y_amplitude": [finite(a, "y amplitude") for a in np.abs(y)],
                "y_phase": [finite(a, "y phase") for a in np.angle(y)],
            }
        )
    return {
        "ross_version": rs.__version__,
        "generator": "scripts/ross/make_fixtures.py",
        "rotor_file": f"{name}.toml",
        "call": "Rotor.load(rotor_file).run_unbalance_response(node, unbalance_magnitude, "
        "unbalance_phase, frequency=speeds)",
        "unbalance": {
            "node": unbalance["node"],
            "magnitude": unbalance["magnitude"],
            "phase": unbalance["phase"],
        },
        "units": {"speeds": "rad/s", "magnitude": "kg m", "phase": "rad", "amplitude": "m"},
        "notes": [
            "ROSS's force at the node: F_x = m e^(j phase) w^2, F_y = -j m e^(j phase) w^2 "
            "(forward); x(t) = Re(X e^(j w t)), amplitude |X|, phase arg X (rad, numpy's "
            "angle, in (-pi, pi])",
            note,
        ],
        "speeds": [float(w) for w in speeds],
        "nodes": nodes,
    }


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

    check_timoshenko_element(timoshenko(0.25, 0.0, 0.05, STEEL))
    check_timoshenko_element(timoshenko(0.1, 0.04, 0.08, TITANIUM, idr=0.03, odr=0.06))

    for name, (build, speeds) in EXAMPLES.items():
        built = build()
        path = args.out / f"{name}.toml"
        built.save(path)
        check_round_trip(built, rs.Rotor.load(path), path.name)
        loaded = rs.Rotor.load(path)
        text = json.dumps(example_file(loaded, name, speeds), indent=1, allow_nan=False) + "\n"
        (args.out / f"{name}.modal.json").write_text(text)
        if name == "rotor_example":
            text = json.dumps(unbalance_file(loaded, name), indent=1, allow_nan=False) + "\n"
            (args.out / f"{name}.unbalance.json").write_text(text)
        if name == "held_out_supports":
            data = unbalance_file(
                loaded,
                name,
                UNBALANCE_HELD_OUT,
                UNBALANCE_HELD_OUT_SPEEDS,
                UNBALANCE_HELD_OUT_NODES,
                "the rotor's bearings and seal are damped; the speeds lie inside every table",
            )
            text = json.dumps(data, indent=1, allow_nan=False) + "\n"
            (args.out / f"{name}.unbalance.json").write_text(text)
        print(f"wrote {name}")

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
            if name == "rotor_example_timoshenko":
                data = unbalance_file(loaded, name, UNBALANCE_ISOTROPIC)
                text = json.dumps(data, indent=1, allow_nan=False) + "\n"
                (args.out / f"{name}.unbalance.json").write_text(text)
        print(f"wrote {name}")


if __name__ == "__main__":
    main()
