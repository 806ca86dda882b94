"""rotorshunt: parametric (Floquet) stability of rotors on piezoelectric shunted vibration
rings, and shunt-circuit design, from Python.

The numbers come from the Rust crate (the same code as the ``rotorshunt`` command line);
this package wraps its results, numpy arrays and Python data, and plots them. SI units, rad/s.

>>> import rotorshunt as rs
>>> p = rs.Problem.from_file("problems/paper-open.toml", set={"speed": 2000})
>>> p.modes(count=4).forward()          # doctest: +SKIP
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import Any, Callable, Iterable, Mapping, Optional, Sequence, Union

from . import _rotorshunt as _native
from ._results import (
    BandResult,
    CampbellResult,
    ChartResult,
    DesignResult,
    FloquetResult,
    ModesResult,
    Probe,
    Region,
    RegionsResult,
    UnbalanceResult,
    _refuse,
)
from ._rotorshunt import (
    AnalysisError,
    ArgumentError,
    CostError,
    DesignError,
    Error,
    OutputError,
    ProblemError,
    RossImportError,
    StudyError,
)

__version__ = _native.__version__

__all__ = [
    "Problem",
    "from_ross",
    "from_ross_file",
    "run_study",
    "Error",
    "ProblemError",
    "ArgumentError",
    "CostError",
    "AnalysisError",
    "DesignError",
    "RossImportError",
    "StudyError",
    "OutputError",
    "ModesResult",
    "CampbellResult",
    "FloquetResult",
    "ChartResult",
    "Region",
    "RegionsResult",
    "BandResult",
    "UnbalanceResult",
    "Probe",
    "DesignResult",
]

Progress = Union[None, bool, Callable[[str, int, int], Any]]


def _progress(progress: Progress):
    """A callback for the native call: a callable as given; ``True`` a tqdm bar per phase
    when tqdm is installed (else nothing); ``None``/``False`` nothing; anything else an
    ArgumentError."""
    if progress is None or progress is False:
        return None
    if callable(progress):
        return progress
    if progress is not True:
        _refuse("progress", "None, a bool or a callable (phase, done, total)", progress)
    try:
        from tqdm.auto import tqdm
    except ImportError:
        return None
    state = {"phase": None, "bar": None}

    def update(phase: str, done: int, total: int) -> None:
        if phase != state["phase"]:
            if state["bar"] is not None:
                state["bar"].close()
            state["phase"] = phase
            state["bar"] = tqdm(total=total or None, desc=phase, leave=False)
        bar = state["bar"]
        if total and bar.total != total:
            bar.total = total
        bar.n = done
        bar.refresh()

    return update


class Problem:
    """A loaded, validated problem file (the command line's ``FILE [--set key=value]``).

    Immutable: :meth:`with_set` returns a copy with more overrides. The reduced Floquet
    system is built once, at the first :meth:`floquet` or :meth:`chart` call."""

    __slots__ = ("_native",)

    def __init__(self, native: "_native.NativeProblem"):
        if not isinstance(native, _native.NativeProblem):
            _refuse("native", "a NativeProblem (load a problem with Problem.from_file or Problem.from_toml)", native)
        self._native = native

    # -- loading -------------------------------------------------------------------
    @classmethod
    def from_file(cls, path: Union[str, os.PathLike], set: Union[Mapping[str, Any], Sequence[str], None] = None) -> "Problem":
        """Load a problem file; ``set`` overrides keys, as ``--set`` does: a dict
        ``{"circuit.state": "open", "speed": 1500}`` or strings ``"key.path=value"``."""
        return cls(_native.NativeProblem.from_file(path, set))

    @classmethod
    def from_toml(cls, text: str, name: str = "<string>", set=None) -> "Problem":
        """Parse a problem from its TOML text; ``name`` names it in messages."""
        return cls(_native.NativeProblem.from_toml(text, name, set))

    def with_set(self, set: Union[Mapping[str, Any], Sequence[str]]) -> "Problem":
        """A copy with these overrides applied after the problem's own."""
        return Problem(self._native.with_set(set))

    def to_toml(self) -> str:
        """The problem's data, overrides applied, as TOML (speeds in rad/s)."""
        return self._native.to_toml()

    @property
    def file(self) -> str:
        return self._native.file

    @property
    def title(self) -> str:
        return self._native.title

    @property
    def overrides(self) -> list:
        return self._native.overrides

    @property
    def warnings(self) -> list:
        """Plausibility warnings (values that look like unit mistakes), one line each."""
        return self._native.warnings

    @property
    def speed(self) -> float:
        """The operating speed Ω (rad/s)."""
        return self._native.speed

    def __repr__(self) -> str:
        extra = f" [{', '.join(self.overrides)}]" if self.overrides else ""
        return f"<rotorshunt.Problem {self.file!r}{extra}: {self.title!r}>"

    # -- analyses --------------------------------------------------------------------
    def check(self) -> dict:
        """Validate and summarise the model (`rotorshunt check`): a dict with ``valid``,
        ``file``, ``title``, ``speed``, ``warnings`` and the summary ``text``, plus its
        ``key: value`` lines."""
        text = self._native.check()
        out = {
            "valid": True,
            "file": self.file,
            "title": self.title,
            "speed": self.speed,
            "warnings": self.warnings,
            "text": text,
        }
        for line in text.splitlines()[1:]:
            key, sep, value = line.strip().partition(":")
            if sep and key and key not in out:
                out[key] = value.strip()
        return out

    def modes(self, speed: Optional[float] = None, count: int = 4) -> ModesResult:
        """The lowest ``count`` forward and backward whirls at ``speed`` (rad/s; default
        the problem's), as `rotorshunt modes --json`."""
        return ModesResult(**self._native.modes(speed, count))

    def campbell(self, speeds: Iterable[float], count: int = 4, progress: Progress = None) -> CampbellResult:
        """The Campbell diagram over ``speeds`` (rad/s), ``count`` whirls of each
        direction tracked (`rotorshunt campbell`)."""
        return CampbellResult(**self._native.campbell(speeds, count, _progress(progress)))

    def floquet(self, phi: float, beta: float) -> FloquetResult:
        """The Floquet point at excitation frequency ``phi`` (rad/s) and load ``beta``
        (`rotorshunt floquet`)."""
        return FloquetResult(**self._native.floquet(phi, beta))

    def chart(self, phis: Iterable[float], betas: Iterable[float], progress: Progress = None) -> ChartResult:
        """The stability chart over the grid ``phis`` (rad/s) x ``betas``
        (`rotorshunt chart`): max|μ| and the growth rate as 2-D arrays. Releases the GIL;
        Ctrl-C stops it between φ rows (KeyboardInterrupt)."""
        return ChartResult(**self._native.chart(phis, betas, _progress(progress)))

    def regions(
        self,
        phi_range: Sequence[float],
        beta_max: float,
        level: Optional[float] = None,
        progress: Progress = None,
    ) -> RegionsResult:
        """The catalogue of instability regions in ``phi_range`` = (lo, hi) rad/s with
        onset below ``beta_max``, edges at ``level`` (default ``beta_max``)
        (`rotorshunt regions --json`)."""
        return RegionsResult(self._native.regions(phi_range, beta_max, level, _progress(progress)))

    def band(
        self,
        phi_op: float,
        level: float,
        phi_range: Optional[Sequence[float]] = None,
        progress: Progress = None,
    ) -> BandResult:
        """The stable band around ``phi_op`` (rad/s) at load ``level``, with its margins
        (`rotorshunt band --json`); ``phi_range`` is the search window (lo, hi)."""
        return BandResult(**self._native.band(phi_op, level, phi_range, _progress(progress)))

    def unbalance(self, speeds: Iterable[float], nodes: Iterable[int], progress: Progress = None) -> UnbalanceResult:
        """The synchronous unbalance response over ``speeds`` (rad/s) at shaft ``nodes``
        (`rotorshunt unbalance`): amplitude and phase, x/y and orbit axes in real
        coordinates."""
        native = self._native.unbalance(speeds, nodes, _progress(progress))
        return UnbalanceResult(**{**native, "probes": [Probe(**p) for p in native["probes"]]})

    def design(
        self,
        out: Union[str, os.PathLike, None] = None,
        pareto: Optional[int] = None,
        progress: Progress = None,
        **settings: Any,
    ):
        """Run the file's ``[design]`` (`rotorshunt design`), tolerances, margins and
        speed ranges included. Keyword ``settings`` override ``design.*`` keys (e.g.
        ``starts=2, max_iterations=10``). With ``out``, the report is written there as
        ``design --out`` writes it. With ``pareto=K``, the Pareto front of K points
        (`design --pareto K`): its report.json as a dict (written to ``out`` or a
        temporary folder)."""
        problem = self.with_set({f"design.{k}": v for k, v in settings.items()}) if settings else self
        cb = _progress(progress)
        if pareto is not None:
            if out is not None:
                return problem._native.pareto(pareto, out, cb)
            with tempfile.TemporaryDirectory() as tmp:
                return problem._native.pareto(pareto, Path(tmp) / "pareto", cb)
        return DesignResult(**problem._native.design(out, cb))


def from_ross_file(path: Union[str, os.PathLike], rings: Optional[Sequence[Mapping[str, Any]]] = None, speed: Optional[float] = None, set=None) -> Problem:
    """A problem from a ROSS ``Rotor.save`` file (TOML or JSON), mapped as
    ``rotorshunt import-ross`` maps it; ``rings`` (dicts, the ``[[rings]]`` tables of the
    problem format) are added, ``speed`` (rad/s) becomes the problem's speed."""
    text = _native.import_ross(path, speed, rings)  # checks the path's type
    return Problem.from_toml(text, name=f"{os.fspath(path)} (imported)", set=set)


def from_ross(rotor: Any, rings: Optional[Sequence[Mapping[str, Any]]] = None, speed: Optional[float] = None, set=None) -> Problem:
    """A problem from a live ``ross.Rotor`` (Timoshenko shafts, anisotropic bearings and
    seals included): the rotor is saved by its own ``save`` and imported as
    :func:`from_ross_file` imports a file."""
    if not callable(getattr(rotor, "save", None)):
        _refuse("rotor", "a ross.Rotor (an object with a save(path) method)", rotor)
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "rotor.toml"
        rotor.save(path)
        return from_ross_file(path, rings=rings, speed=speed, set=set)


def run_study(file: Union[str, os.PathLike], out: Union[str, os.PathLike], force: bool = False, allow_non_empty: bool = False, dry_run: bool = False, progress: Progress = None) -> dict:
    """Run a study file into folder ``out`` (`rotorshunt study FILE --out DIR`): a dict
    with the summary ``text`` and the number of ``failed`` cases."""
    text, failed = _native.run_study(file, out, force, allow_non_empty, dry_run, _progress(progress))
    return {"text": text, "failed": failed}
