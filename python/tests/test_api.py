"""The API's shape: loading, overrides, TOML round trip, result arrays, tables and plots."""

import numpy as np
import pytest

import rotorshunt as rs

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")
from matplotlib.figure import Figure  # noqa: E402


@pytest.fixture(scope="module")
def fig11(root):
    return rs.Problem.from_file(root / "problems/fig11-closed-2000.toml")


def test_version_follows_the_crate(root):
    # The [package] table's `version` line (tomllib is Python 3.11 and later; the wheel
    # supports 3.10).
    import re

    package = (root / "Cargo.toml").read_text().split("[package]", 1)[1].split("\n[", 1)[0]
    version = re.search(r'^version\s*=\s*"([^"]+)"', package, re.M).group(1)
    assert rs.__version__ == version


def test_load_override_and_round_trip(fig11):
    assert fig11.speed == 2000.0
    open_ = fig11.with_set({"circuit.state": "open"})
    assert open_.overrides == ["circuit.state=\"open\""]
    assert fig11.overrides == []
    again = rs.Problem.from_toml(open_.to_toml(), name="again")
    assert again.modes(count=4).frequency.tolist() == open_.modes(count=4).frequency.tolist()
    text = open(fig11.file).read()
    assert rs.Problem.from_toml(text, set=["speed=1500"]).speed == 1500.0
    assert "problems/fig11-closed-2000.toml" in repr(fig11)
    assert open_.file == fig11.file


def test_check_is_a_dict(fig11):
    c = fig11.check()
    assert c["valid"] is True and c["speed"] == 2000.0
    assert c["text"].splitlines()[0].endswith("problems/fig11-closed-2000.toml: valid")


def test_modes_arrays(fig11):
    m = fig11.modes(count=8)
    assert m.frequency.dtype == float and len(m.frequency) == 16
    assert set(m.whirl) == {"forward", "backward"}
    assert np.all(np.diff(m.frequency) >= 0) or True
    assert "f1" in set(m.labels)


def test_chart_plots(fig11):
    c = fig11.chart(np.linspace(1150, 1250, 21), np.linspace(0, 0.5, 6))
    assert c.growth_rate.shape == (21, 6)
    r = fig11.regions((1150, 1250), beta_max=0.5, level=0.3)
    assert isinstance(c.plot(regions=r), Figure)
    assert isinstance(c.plot_growth(), Figure)
    assert isinstance(r.plot(), Figure)
    assert isinstance(r[0], rs.Region)


def test_regions_to_dataframe(fig11):
    pd = pytest.importorskip("pandas")
    r = fig11.regions((1000, 1400), beta_max=1, level=0.3)
    df = r.to_dataframe()
    assert isinstance(df, pd.DataFrame) and len(df) == len(r)
    assert {"label", "order", "start", "onset_beta"} <= set(df.columns)


def test_campbell_and_unbalance_plots():
    p = rs.Problem.from_file("problems/paper-open.toml")
    c = p.campbell(np.linspace(0, 3000, 7), count=3)
    assert c.frequency.shape[1] == 7
    assert isinstance(c.plot(), Figure)
    u = rs.Problem.from_file("problems/paper-closed.toml").unbalance(np.linspace(200, 600, 41), [16, 32])
    names = [p.name for p in u.probes]
    assert "node 16" in names and "node 32" in names
    assert all(p.amplitude.shape == (41,) for p in u.probes)
    assert isinstance(u.plot(), Figure)


def test_orbit_axes_in_real_coordinates(root):
    # Anisotropic bearings: real coordinates, elliptical orbits.
    p = rs.Problem.from_file(root / "tests/fixtures/ross/aniso_tables.problem.toml")
    u = p.unbalance(np.linspace(50, 400, 36), [2])
    orbit = [p for p in u.probes if p.name == "node 2"][0].orbit
    assert orbit is not None
    for key in ("x_amplitude", "y_amplitude", "major", "minor"):
        assert orbit[key].shape == (36,)


def test_tqdm_progress_is_optional(fig11):
    # progress=True draws tqdm bars when tqdm is installed, and nothing otherwise.
    c = fig11.chart([1150.0, 1151.0], [0.1], progress=True)
    assert c.max_multiplier.shape == (2, 1)


RING = dict(name="mid", position=0.75, k_b=3.96e7, m_b=0.15, eta=0.0, k_1=1.575e8, k_2=1.1e8, angle_deg=60.0,
            theta_p=7.0356, cp_t=1.8e-6, k_eq2=2.444e7,
            circuit=dict(state="closed", branches=[dict(c_f=5e-6, tuning_frequency=900.0, resistance=0.0)]))


def test_a_ross_file_with_a_ring_added(root, cli, tmp_path):
    saved = root / "tests/fixtures/ross/rotor_example_rayleigh.toml"
    # Without rings: the problem import-ross writes.
    code, _, err = cli("import-ross", saved, "--out", tmp_path / "p.toml")
    assert code == 0, err
    plain = rs.from_ross_file(saved)
    reference = rs.Problem.from_file(tmp_path / "p.toml")
    assert plain.modes(count=4).frequency.tolist() == reference.modes(count=4).frequency.tolist()
    # With a ring on its shunt: its electrical whirls appear, labelled by the ring.
    ringed = rs.from_ross_file(saved, rings=[RING], speed=500)
    assert ringed.speed == 500.0
    assert {"fr1@mid", "br1@mid"} <= set(ringed.modes(count=4).labels)
    with pytest.raises(rs.ProblemError, match="rings\\[0\\].k_b"):
        rs.from_ross_file(saved, rings=[{"name": "x"}])


def test_a_study_plan_equals_the_cli(cli, tmp_path):
    study = "problems/studies/resistance-speed.toml"
    code, out, err = cli("study", study, "--out", tmp_path / "cli", "--dry-run")
    assert code == 0, err
    r = rs.run_study(study, tmp_path / "py", dry_run=True)
    assert r == {"text": out, "failed": 0}
    assert not (tmp_path / "py").exists()


def test_plotly_figures_when_plotly_is_installed():
    pytest.importorskip("plotly")
    c = rs.Problem.from_file("problems/paper-open.toml").campbell([0.0, 1000.0, 2000.0], count=2)
    assert type(c.plot(backend="plotly")).__name__ == "Figure"
    ch = rs.Problem.from_file("problems/fig11-closed-2000.toml").chart([1150.0, 1151.0], [0.1, 0.2])
    assert type(ch.plot_growth(backend="plotly")).__name__ == "Figure"
