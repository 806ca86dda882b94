"""Bad input raises the package's exception of the right kind, with the command line's
message (its `error: ` paragraph), never a crash."""

import math

import numpy as np
import pytest

import rotorshunt as rs
from conftest import ROOT, cli_message


def test_the_hierarchy():
    for kind in (rs.ProblemError, rs.ArgumentError, rs.CostError, rs.AnalysisError, rs.DesignError,
                 rs.RossImportError, rs.StudyError, rs.OutputError):
        assert issubclass(kind, rs.Error)
    assert issubclass(rs.Error, Exception)


def test_the_kind_is_named_as_docs_errors_heads_it(root):
    sections = (root / "docs" / "errors.md").read_text()
    paper = rs.Problem.from_file("problems/paper-open.toml")
    cases = [
        (lambda: rs.Problem.from_file("problems/no-such-file.toml"), rs.ProblemError, "Read"),
        (lambda: paper.modes(count=0), rs.ArgumentError, "OutOfRange"),
        (lambda: paper.floquet(1000, math.nan), rs.ArgumentError, "NotFinite"),
    ]
    for call, cls, kind in cases:
        with pytest.raises(cls) as e:
            call()
        assert e.value.kind == kind
        assert f"### `{kind}`" in sections


def test_a_missing_file(cli):
    _, _, err = cli("check", "problems/no-such-file.toml")
    with pytest.raises(rs.ProblemError) as e:
        rs.Problem.from_file("problems/no-such-file.toml")
    assert str(e.value) == cli_message(err)


def test_an_unknown_key_in_set(cli):
    _, _, err = cli("check", "problems/paper-open.toml", "--set", "shaft.colour=3")
    with pytest.raises(rs.ProblemError) as e:
        rs.Problem.from_file("problems/paper-open.toml", set={"shaft.colour": 3})
    assert str(e.value) == cli_message(err)


def test_a_bad_value_in_set(cli):
    _, _, err = cli("check", "problems/paper-open.toml", "--set", "speed=-5")
    with pytest.raises(rs.ProblemError) as e:
        rs.Problem.from_file("problems/paper-open.toml").with_set({"speed": -5})
    assert str(e.value) == cli_message(err)


def test_a_syntax_error(cli, tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("version = 1\n[shaft\n")
    _, _, err = cli("check", bad)
    with pytest.raises(rs.ProblemError) as e:
        rs.Problem.from_file(bad)
    assert str(e.value) == cli_message(err)
    with pytest.raises(rs.ProblemError):
        rs.Problem.from_toml("version = 1\n[shaft\n")


@pytest.mark.parametrize(
    "args, call",
    [
        (["modes", "--count", "0"], lambda p: p.modes(count=0)),
        (["modes", "--speed=-1"], lambda p: p.modes(speed=-1)),
        (["modes", "--speed", "NaN"], lambda p: p.modes(speed=math.nan)),
        (["floquet", "--phi=-5", "--beta", "0.1"], lambda p: p.floquet(-5, 0.1)),
        (["floquet", "--phi", "1000", "--beta", "inf"], lambda p: p.floquet(1000, math.inf)),
        (["regions", "--phi", "1400:1000", "--beta-max", "1"], lambda p: p.regions((1400, 1000), 1)),
        (["regions", "--phi", "1000:1400", "--beta-max", "1", "--level", "2"], lambda p: p.regions((1000, 1400), 1, 2)),
        (["band", "--phi-op", "0", "--level", "0.3"], lambda p: p.band(0, 0.3)),
        (["band", "--phi-op", "1230", "--level", "NaN"], lambda p: p.band(1230, math.nan)),
    ],
)
def test_argument_errors_carry_the_cli_message(cli, args, call):
    code, _, err = cli(args[0], "problems/fig11-closed-2000.toml", *args[1:])
    assert code == 2
    p = rs.Problem.from_file("problems/fig11-closed-2000.toml")
    with pytest.raises(rs.ArgumentError) as e:
        call(p)
    assert str(e.value) == cli_message(err)


def test_a_node_off_the_shaft(cli, tmp_path):
    _, _, err = cli("unbalance", "problems/paper-closed.toml", "--speeds", "200:300:50", "--nodes", "99", "--out", tmp_path / "u")
    with pytest.raises(rs.ArgumentError) as e:
        rs.Problem.from_file("problems/paper-closed.toml").unbalance([200, 250, 300], [99])
    assert str(e.value) == cli_message(err)


def test_no_design_table(cli, tmp_path):
    _, _, err = cli("design", "problems/paper-open.toml", "--out", tmp_path / "d")
    with pytest.raises(rs.DesignError) as e:
        rs.Problem.from_file("problems/paper-open.toml").design()
    assert str(e.value) == cli_message(err)


def test_a_bad_ross_file(cli, tmp_path, root):
    bad = root / "tests/fixtures/ross/bad_missing_key.toml"
    _, _, err = cli("import-ross", bad, "--out", tmp_path / "x.toml")
    with pytest.raises(rs.RossImportError) as e:
        rs.from_ross_file(bad)
    assert str(e.value) == cli_message(err)


@pytest.mark.parametrize(
    "call",
    [
        lambda p: p.modes(count="3"),
        lambda p: p.modes(count=2.5),
        lambda p: p.modes(speed="fast"),
        lambda p: p.floquet(None, 0.1),
        lambda p: p.floquet([1000], 0.1),
        lambda p: p.chart("1000:1100", [0.1]),
        lambda p: p.chart([1000, "x"], [0.1]),
        lambda p: p.chart([], [0.1]),
        lambda p: p.regions(1000, 1),
        lambda p: p.regions((1000, 1100, 1200), 1),
        lambda p: p.unbalance([100], [-1]),
        lambda p: p.unbalance([100], "16"),
        lambda p: p.with_set(42),
        lambda p: p.with_set({"speed": object()}),
        lambda p: p.campbell([0, math.nan]),
        lambda p: p.campbell([0, 100], count=-3),
    ],
)
def test_wrong_types_raise_the_package_error(call):
    p = rs.Problem.from_file("problems/fig11-closed-2000.toml")
    with pytest.raises(rs.Error) as e:
        call(p)
    assert str(e.value).startswith("argument `")


class _FakeRotor:
    """A stand-in for a ross.Rotor: `save` writes a saved ROSS file (no ROSS needed)."""

    def save(self, path):
        path.write_text((ROOT / "tests/fixtures/ross/rotor_example.toml").read_text())


FIG11 = "problems/fig11-closed-2000.toml"
STUDY = "problems/studies/resistance-speed.toml"


@pytest.mark.parametrize(
    "call, argument, shown",
    [
        # Issue 50, item 9: paths, switches, names, callbacks and objects of the wrong type.
        (lambda: rs.Problem.from_file("problems/design-min-peak-at-speed.toml").design(out=123), "--out", "123 (int)"),
        (lambda: rs.Problem.from_file("problems/design-min-peak-at-speed.toml").design(pareto=2, out=5), "--out", "5 (int)"),
        (lambda: rs.run_study(123, "out/never"), "FILE", "123 (int)"),
        (lambda: rs.run_study(STUDY, 4.5), "--out", "4.5 (float)"),
        (lambda: rs.run_study(STUDY, "out/never", force="yes"), "--force", "'yes' (str)"),
        (lambda: rs.run_study(STUDY, "out/never", dry_run=1), "--dry-run", "1 (int)"),
        (lambda: rs.from_ross_file(123), "FILE", "123 (int)"),
        (lambda: rs.from_ross_file(b"rotor.toml"), "FILE", "b'rotor.toml' (bytes)"),
        (lambda: rs.from_ross(123), "rotor", "123 (int)"),
        (lambda: rs.Problem.from_file(123), "FILE", "123 (int)"),
        (lambda: rs.Problem.from_toml(["version = 1"]), "text", "['version = 1'] (list)"),
        (lambda: rs.Problem.from_toml((ROOT / FIG11).read_text(), name=5), "name", "5 (int)"),
        (lambda: rs.Problem(FIG11), "native", "(str)"),
        (lambda: rs.Problem.from_file(FIG11).chart([1000.0], [0.1], progress=5), "progress", "5 (int)"),
        (lambda: rs.Problem.from_file(FIG11).campbell([0.0], progress="yes"), "progress", "'yes' (str)"),
        (lambda: rs.Problem.from_file(FIG11)._native.band(1230, 0.3, None, 7), "progress", "7 (int)"),
        (lambda: rs.Problem.from_file(FIG11).chart([1000.0], [0.1]).plot_growth(backend="plotlyy"), "backend",
         "'plotlyy' (str)"),
        (lambda: rs.Problem.from_file(FIG11).chart([1000.0], [0.1]).plot(regions=[1]), "regions", "[1] (list)"),
        (lambda: rs.Problem.from_file(FIG11).campbell([0.0]).plot(backend=3), "backend", "3 (int)"),
        (lambda: rs.Problem.from_file(FIG11).campbell([0.0]).plot(ax="left"), "ax", "'left' (str)"),
        # Item 10: no complex numbers, bytes or masked arrays read as real numbers.
        (lambda: rs.Problem.from_file(FIG11).chart(np.array([1000 + 1j, 1010]), [0.1]), "--phi",
         "(1-D ndarray of complex128)"),
        (lambda: rs.Problem.from_file(FIG11).chart(b"\x01\x02", [0.1]), "--phi", "b'\\x01\\x02' (bytes)"),
        (lambda: rs.Problem.from_file(FIG11).chart([1000.0], np.ma.masked_array([0.1, 0.2], mask=[False, True])),
         "--beta", "not a masked array (give `a.compressed()` or `a.filled(value)`), got masked_array(data=[0.1, --], mask="),
        (lambda: rs.Problem.from_file(FIG11).floquet(np.complex128(1000), 0.1), "--phi", "(complex128)"),
        (lambda: rs.Problem.from_file(FIG11).floquet(1000, np.complex64(0.1)), "--beta", "(complex64)"),
        (lambda: rs.Problem.from_file(FIG11).floquet(1000, np.ma.masked), "--beta", "MaskedConstant"),
        (lambda: rs.Problem.from_file(FIG11).campbell([0.0, np.complex128(100)]), "--speeds", "(complex128)"),
        (lambda: rs.Problem.from_file(FIG11).unbalance([100.0, 200.0], b"\x10"), "--nodes", "(bytes)"),
        (lambda: rs.Problem.from_file(FIG11).regions(bytearray(b"\x01\x02"), 1), "--phi", "(bytearray)"),
        (lambda: rs.Problem.from_file(FIG11).with_set({"speed": np.complex128(100)}), "--set", "(complex128)"),
        (lambda: rs.Problem.from_file(FIG11).with_set(b"speed=1"), "--set", "(bytes)"),
        (lambda: rs.from_ross_file("tests/fixtures/ross/rotor_example.toml", rings="notalist"), "rings",
         "'notalist' (str)"),
        (lambda: rs.from_ross(_FakeRotor(), rings="notalist"), "rings", "'notalist' (str)"),
        (lambda: rs.from_ross(_FakeRotor(), rings=[{"node": 3}, 4]), "rings", "as entry 2, got 4 (int)"),
    ],
)
def test_a_wrong_type_is_an_argument_error_naming_the_argument_and_value(call, argument, shown):
    """Issue 50, items 9 and 10: never a TypeError, and never a value read as another."""
    with pytest.raises(rs.ArgumentError) as e:
        call()
    message = str(e.value)
    assert message.startswith(f"argument `{argument}`: expected "), message
    assert shown in message, message
    assert e.value.kind == "Argument"


def test_the_pareto_count_is_checked_against_the_documented_range():
    """Issue 50, item 10: 2 to 50 points, as `design --pareto` and the docs have it."""
    p = rs.Problem.from_file("problems/design-min-peak-at-speed.toml")
    for k in (1, 51):
        with pytest.raises(rs.ArgumentError) as e:
            p.design(pareto=k)
        assert str(e.value) == f"argument `--pareto`: must be a whole number from 2 to 50, found {k}"


def test_rings_given_as_an_empty_list_add_no_rings():
    """Issue 50, item 10: `rings=[]` is no rings (it was a `rings = []` key in the file's
    last table, blamed on `load.rings`)."""
    fixture = "tests/fixtures/ross/rotor_example.toml"
    assert rs.from_ross_file(fixture, rings=[]).to_toml() == rs.from_ross_file(fixture).to_toml()
