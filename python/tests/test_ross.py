"""A live ROSS rotor imported with rotorshunt.from_ross, its whirls against ROSS's own
run_modal to 0.05 % (problems/README.md: ross-rotor-example). Skipped, saying why, when
ROSS is not installed."""

import numpy as np
import pytest

import rotorshunt as rs

RTOL = 5e-4


def ross_or_skip():
    try:
        import ross
    except Exception as e:  # ImportError, or ROSS failing on import (plotly 7)
        pytest.skip(f"ROSS is not installed here ({type(e).__name__}: {e}); pip install ross-rotordynamics 'plotly<6'")
    return ross


def lateral_whirls(rotor, speed, count):
    modal = rotor.run_modal(speed=speed, num_modes=4 * count)
    wd = np.asarray(modal.wd)
    whirl = modal.whirl_direction()
    forward = sorted(w for w, d in zip(wd, whirl) if str(d).lower() == "forward" and w > 1e-6)
    backward = sorted(w for w, d in zip(wd, whirl) if str(d).lower() == "backward" and w > 1e-6)
    return np.array(forward[:count]), np.array(backward[:count])


def friswell_rotor(ross, timoshenko):
    steel = ross.materials.steel
    shaft = [
        ross.ShaftElement(L=0.25, idl=0.0, odl=0.05, material=steel, shear_effects=timoshenko,
                          rotary_inertia=True, gyroscopic=True)
        for _ in range(6)
    ]
    disks = [ross.DiskElement.from_geometry(n=n, material=steel, width=0.07, i_d=0.05, o_d=0.28) for n in (2, 4)]
    bearings = [ross.BearingElement(n=0, kxx=1e6, kyy=8e5, cxx=0, scale_factor=2),
                ross.BearingElement(n=6, kxx=1e6, kyy=8e5, cxx=0, scale_factor=2)]
    if timoshenko:  # and a seal with cross-coupled stiffness
        bearings.append(ross.SealElement(n=3, kxx=2e5, kyy=2e5, kxy=5e4, kyx=-5e4, cxx=0, cyy=0))
    return ross.Rotor(shaft, disks, bearings)


@pytest.mark.parametrize("timoshenko", [False, True])
def test_a_live_ross_rotor_matches_run_modal(timoshenko):
    ross = ross_or_skip()
    rotor = friswell_rotor(ross, timoshenko)
    problem = rs.from_ross(rotor)
    worst = 0.0
    for speed in (0.0, 500.0):
        fwd, bwd = lateral_whirls(rotor, speed, 3)
        m = problem.modes(speed=speed, count=6)
        ours = np.sort(m.frequency)
        for w in np.concatenate([fwd, bwd]):
            nearest = ours[np.argmin(abs(ours - w))]
            worst = max(worst, abs(nearest / w - 1))
            assert nearest == pytest.approx(w, rel=RTOL), (speed, w, ours)
    print(f"\nlive ROSS rotor ({'Timoshenko, seal' if timoshenko else 'Rayleigh'}): largest deviation from run_modal {worst:.3e}")
