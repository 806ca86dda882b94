"""Shared fixtures of the Python suite: the repository root, the command line's binary
(the references the Python results are compared with) and a runner for it."""

import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _binary() -> Path:
    given = os.environ.get("ROTORSHUNT_BIN")
    if given:
        return Path(given)
    path = ROOT / "target" / "release" / "rotorshunt"
    if not path.exists():
        subprocess.run(["cargo", "build", "--release", "--bin", "rotorshunt"], cwd=ROOT, check=True)
    return path


@pytest.fixture(scope="session")
def root() -> Path:
    return ROOT


@pytest.fixture(scope="session")
def cli():
    """Run the command line from the repository root: (exit code, stdout, stderr)."""
    binary = _binary()

    def run(*args):
        p = subprocess.run([str(binary), *map(str, args)], cwd=ROOT, capture_output=True, text=True)
        return p.returncode, p.stdout, p.stderr

    return run


@pytest.fixture(autouse=True)
def _in_root(monkeypatch):
    """Problem paths are given relative to the repository root, as the CLI is run."""
    monkeypatch.chdir(ROOT)


def cli_message(stderr: str) -> str:
    """The CLI's error paragraph: its `error: ` line without the prefix."""
    lines = [l for l in stderr.splitlines() if l.startswith("error: ")]
    assert lines, stderr
    return lines[-1][len("error: "):]


try:  # figures are drawn off screen
    import matplotlib

    matplotlib.use("Agg")
except ImportError:  # pragma: no cover
    pass
