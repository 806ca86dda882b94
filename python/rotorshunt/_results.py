"""Result objects of the Python API: numpy arrays over the command line's JSON, and plots.

Every number here comes from the Rust library through the native module; this file only
reshapes it (lists into arrays) and draws it with matplotlib.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional

import numpy as np


def _pyplot():
    try:
        import matplotlib.pyplot as plt
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise ImportError("plotting needs matplotlib: pip install matplotlib") from e
    return plt


def _plotly():
    try:
        import plotly.graph_objects as go
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise ImportError("backend='plotly' needs plotly: pip install plotly") from e
    return go


def _new_axes(ax=None):
    plt = _pyplot()
    if ax is not None:
        return ax.figure, ax
    fig, ax = plt.subplots(figsize=(8, 5))
    return fig, ax


@dataclass(frozen=True)
class ModesResult:
    """The lowest forward and backward whirls at a speed (`rotorshunt modes --json`).

    Arrays are in the order of the command's list: by frequency (rad/s)."""

    speed: float
    critical_load: float
    static_load: float
    frequency: np.ndarray
    whirl: np.ndarray
    damping_ratio: np.ndarray
    label: np.ndarray
    kind: np.ndarray
    eigenvalue: np.ndarray
    json: Dict[str, Any] = field(repr=False)

    @property
    def labels(self) -> np.ndarray:
        """The modes' tags, e.g. ``f1``, ``b1``, ``fr1``."""
        return np.array([_tag(w, l) for w, l in zip(self.whirl, self.label)])

    @classmethod
    def _of(cls, text: str) -> "ModesResult":
        d = json.loads(text)
        m = d["modes"]
        return cls(
            speed=d["speed"],
            critical_load=d["critical_load"],
            static_load=d["static_load"],
            frequency=np.array([x["frequency"] for x in m], dtype=float),
            whirl=np.array([x["whirl"] for x in m], dtype=object),
            damping_ratio=np.array([x["damping_ratio"] for x in m], dtype=float),
            label=np.array([x["label"] for x in m], dtype=object),
            kind=np.array([x["kind"] for x in m], dtype=object),
            eigenvalue=np.array([complex(*x["eigenvalue"]) for x in m], dtype=complex),
            json=d,
        )

    def forward(self) -> np.ndarray:
        """Frequencies of the forward whirls (rad/s)."""
        return self.frequency[self.whirl == "forward"]

    def backward(self) -> np.ndarray:
        """Frequencies of the backward whirls (rad/s)."""
        return self.frequency[self.whirl == "backward"]


def _tag(whirl: str, label: str) -> str:
    prefix = {"forward": "f", "backward": "b"}.get(whirl, "")
    if label and not label[0].isdigit():
        return prefix + label
    return prefix + label


@dataclass(frozen=True)
class CampbellResult:
    """Whirl frequencies over speed (`rotorshunt campbell`'s campbell.json).

    ``frequency[i, j]`` is track i at ``speeds[j]`` (rad/s), NaN where the track has no
    point."""

    speeds: np.ndarray
    tags: List[str]
    whirl: List[str]
    frequency: np.ndarray
    damping_ratio: np.ndarray
    operating_speeds: np.ndarray
    critical_speeds: List[Dict[str, Any]]
    json: Dict[str, Any] = field(repr=False)

    @classmethod
    def _of(cls, text: str) -> "CampbellResult":
        d = json.loads(text)
        c = d["campbell"]
        speeds = np.array(c["speeds"], dtype=float)
        index = {s: j for j, s in enumerate(c["speeds"])}
        n = len(c["tracks"])
        freq = np.full((n, len(speeds)), np.nan)
        zeta = np.full((n, len(speeds)), np.nan)
        for i, t in enumerate(c["tracks"]):
            for p in t["points"]:
                j = index.get(p["speed"])
                if j is not None:
                    freq[i, j] = p["frequency"]
                    zeta[i, j] = p["damping_ratio"]
        return cls(
            speeds=speeds,
            tags=[t["tag"] for t in c["tracks"]],
            whirl=[t["whirl"] for t in c["tracks"]],
            frequency=freq,
            damping_ratio=zeta,
            operating_speeds=np.array(d["operating_speeds"], dtype=float),
            critical_speeds=d["critical_speeds"],
            json=d,
        )

    def plot(self, ax=None, title: Optional[str] = None, backend: str = "matplotlib"):
        """The Campbell diagram: tracks (forward solid, backward dashed), the 1x line and the
        operating speeds. Returns the matplotlib Figure (``backend="plotly"``: a plotly
        Figure)."""
        if backend == "plotly":
            go = _plotly()
            fig = go.Figure()
            for tag, whirl, f in zip(self.tags, self.whirl, self.frequency):
                fig.add_scatter(x=self.speeds, y=f, name=tag, line_dash="dash" if whirl == "backward" else "solid")
            fig.add_scatter(x=self.speeds, y=self.speeds, name="1x", line=dict(color="black", dash="dot"))
            fig.update_layout(title=title or "Campbell diagram", xaxis_title="speed Ω (rad/s)",
                              yaxis_title="whirl frequency (rad/s)")
            return fig
        fig, ax = _new_axes(ax)
        for tag, whirl, f in zip(self.tags, self.whirl, self.frequency):
            ax.plot(self.speeds, f, "-" if whirl != "backward" else "--", label=tag)
        ax.plot(self.speeds, self.speeds, "k:", lw=1, label="1x")
        for w in self.operating_speeds:
            ax.axvline(w, color="grey", lw=0.8)
        for c in self.critical_speeds:
            ax.plot([c["speed"]], [c["speed"]], "ko", ms=4)
        ax.set_xlabel("speed Ω (rad/s)")
        ax.set_ylabel("whirl frequency (rad/s)")
        ax.set_title(title or "Campbell diagram")
        ax.legend(fontsize="small", ncol=2)
        return fig


@dataclass(frozen=True)
class FloquetResult:
    """One Floquet point (`rotorshunt floquet --json`): max|μ|, growth rate, verdict and the
    multipliers μ as a complex array."""

    speed: float
    phi: float
    beta: float
    max_multiplier: float
    ln_max_multiplier: float
    growth_rate: float
    stable: bool
    status: str
    reason: Optional[str]
    multipliers: np.ndarray
    scaled_multipliers: np.ndarray = field(repr=False)
    multiplier_log_scale: float = 0.0
    basis: str = ""

    @classmethod
    def _of(cls, d: Dict[str, Any]) -> "FloquetResult":
        return cls(**d)


@dataclass(frozen=True)
class ChartResult:
    """A stability chart over a (φ, β) grid: 2-D arrays indexed [i_φ, i_β]."""

    speed: float
    phis: np.ndarray
    betas: np.ndarray
    max_multiplier: np.ndarray
    ln_max_multiplier: np.ndarray
    growth_rate: np.ndarray
    stable: np.ndarray
    status: np.ndarray
    status_names: List[str]
    threshold: str
    failed: int
    inaccurate: int
    unstable: int
    reduction: Dict[str, Any] = field(repr=False)

    @classmethod
    def _of(cls, d: Dict[str, Any]) -> "ChartResult":
        d = dict(d)
        d["reduction"] = json.loads(d["reduction"]) if d.get("reduction") else {}
        d["status_names"] = list(d["status_names"])
        return cls(**d)

    def plot(self, ax=None, regions: Optional["RegionsResult"] = None, title: Optional[str] = None):
        """The stability chart: unstable points in the (φ, β) plane and, given a catalogue,
        its regions' onsets and edges. Returns the matplotlib Figure."""
        fig, ax = _new_axes(ax)
        P, B = np.meshgrid(self.phis, self.betas, indexing="ij")
        bad = ~self.stable & (self.status != 2)
        ax.scatter(P[bad], B[bad], s=4, c="tab:blue", marker="s", label="unstable")
        if regions is not None:
            for r in regions:
                ax.plot([r.start], [r.onset_beta], "rv", ms=5)
                if r.left is not None and r.right is not None:
                    ax.plot([r.left, r.right], [regions.level] * 2, "r-", lw=2)
                ax.annotate(r.label, (r.start, r.onset_beta), fontsize=7, rotation=90, va="bottom")
        ax.set_xlim(self.phis.min(), self.phis.max())
        ax.set_ylim(self.betas.min(), self.betas.max())
        ax.set_xlabel("φ (rad/s)")
        ax.set_ylabel("β")
        ax.set_title(title or f"Stability chart at Ω = {self.speed:g} rad/s")
        return fig

    def plot_growth(self, ax=None, title: Optional[str] = None, backend: str = "matplotlib"):
        """The growth-rate map ln(max|μ|)/T (1/s) over the grid. Returns the matplotlib
        Figure (``backend="plotly"``: a plotly heat map)."""
        if backend == "plotly":
            go = _plotly()
            fig = go.Figure(go.Heatmap(x=self.phis, y=self.betas, z=self.growth_rate.T, colorbar_title="1/s"))
            fig.update_layout(title=title or f"Growth rate at Ω = {self.speed:g} rad/s", xaxis_title="φ (rad/s)",
                              yaxis_title="β")
            return fig
        fig, ax = _new_axes(ax)
        m = ax.pcolormesh(self.phis, self.betas, self.growth_rate.T, shading="nearest", cmap="viridis")
        fig.colorbar(m, ax=ax, label="growth rate (1/s)")
        ax.set_xlabel("φ (rad/s)")
        ax.set_ylabel("β")
        ax.set_title(title or f"Growth rate at Ω = {self.speed:g} rad/s")
        return fig


@dataclass(frozen=True)
class Region:
    """One instability region of a catalogue (`rotorshunt regions --json`)."""

    label: str
    kind: str
    order: int
    predicted: float
    start: float
    onset_beta: float
    left: Optional[float]
    right: Optional[float]
    width: Optional[float]
    counted: bool
    resolved: bool
    boundary: List[Any] = field(repr=False, default_factory=list)


class RegionsResult(list):
    """The catalogue of regions: a list of :class:`Region`, with the stable bands at the
    level (``stable_bands``, an (n, 2) array), their load margins and the JSON."""

    def __init__(self, text: str):
        d = json.loads(text)
        fields = Region.__dataclass_fields__
        super().__init__(Region(**{k: v for k, v in r.items() if k in fields}) for r in d["regions"])
        self.json = d
        self.speed = d["speed"]
        self.level = d["level"]
        self.beta_max = d["beta_max"]
        self.range = (d["range"]["lo"], d["range"]["hi"])
        self.stable_bands = np.array([[b["lo"], b["hi"]] for b in d["stable_bands"]], dtype=float).reshape(-1, 2)
        self.band_margins = d["band_margins"]
        self.unexplained = d["unexplained"]
        self.evaluations = d["evaluations"]

    def to_dataframe(self):
        """The regions as a pandas DataFrame (needs pandas)."""
        try:
            import pandas as pd
        except ImportError as e:  # pragma: no cover
            raise ImportError("to_dataframe needs pandas: pip install pandas") from e
        cols = [f for f in Region.__dataclass_fields__ if f != "boundary"]
        return pd.DataFrame([[getattr(r, c) for c in cols] for r in self], columns=cols)

    def plot(self, ax=None, chart: Optional[ChartResult] = None, title: Optional[str] = None):
        """The regions' onsets and edges at the level over the stable bands, on a chart if
        given. Returns the matplotlib Figure."""
        if chart is not None:
            return chart.plot(ax=ax, regions=self, title=title)
        fig, ax = _new_axes(ax)
        for lo, hi in self.stable_bands:
            ax.axvspan(lo, hi, ymax=0.02, color="tab:green")
        for r in self:
            ax.plot([r.start], [r.onset_beta], "rv", ms=5)
            if r.left is not None and r.right is not None:
                ax.plot([r.left, r.right], [self.level] * 2, "r-", lw=2)
            ax.annotate(r.label, (r.start, r.onset_beta), fontsize=7, rotation=90, va="bottom")
        ax.axhline(self.level, color="grey", lw=0.8)
        ax.set_xlim(*self.range)
        ax.set_ylim(0, self.beta_max)
        ax.set_xlabel("φ (rad/s)")
        ax.set_ylabel("onset β")
        ax.set_title(title or f"Instability regions at Ω = {self.speed:g} rad/s")
        return fig


@dataclass(frozen=True)
class BandResult:
    """The stable band around φ_op at a level (`rotorshunt band --json`), with margins."""

    phi_op: float
    level: float
    band: Optional[tuple]
    width: Optional[float]
    left: Optional[Dict[str, Any]]
    right: Optional[Dict[str, Any]]
    margins: Optional[Dict[str, Any]]
    json: Dict[str, Any] = field(repr=False)

    @classmethod
    def _of(cls, text: str) -> "BandResult":
        d = json.loads(text)
        b = d.get("band")
        return cls(
            phi_op=d["phi_op"],
            level=d["level"],
            band=(b["lo"], b["hi"]) if b else None,
            width=d.get("width"),
            left=d.get("left"),
            right=d.get("right"),
            margins=d.get("margins"),
            json=d,
        )


@dataclass(frozen=True)
class Probe:
    """The response at one probe: amplitude and phase over speed; in real coordinates
    also the x/y motions and the orbit's axes (``orbit`` holds arrays, else None)."""

    name: str
    kind: str
    node: Optional[int]
    amplitude: np.ndarray
    phase: np.ndarray
    peaks: List[Dict[str, Any]]
    orbit: Optional[Dict[str, np.ndarray]]


@dataclass(frozen=True)
class UnbalanceResult:
    """The synchronous unbalance response (`rotorshunt unbalance`'s unbalance.json)."""

    speeds: np.ndarray
    probes: List[Probe]
    json: Dict[str, Any] = field(repr=False)

    @classmethod
    def _of(cls, text: str) -> "UnbalanceResult":
        d = json.loads(text)
        u = d["unbalance"]
        probes = []
        for p in u["probes"]:
            orbit = p.get("orbit")
            if orbit is not None:
                orbit = {k: np.array(v, dtype=float) for k, v in orbit.items() if isinstance(v, list)}
            probes.append(
                Probe(
                    name=p["name"],
                    kind=p["kind"],
                    node=p.get("node"),
                    amplitude=np.array([np.inf if a is None else a for a in p["amplitude"]], dtype=float),
                    phase=np.array([np.nan if a is None else a for a in p["phase"]], dtype=float),
                    peaks=p.get("peaks", []),
                    orbit=orbit,
                )
            )
        return cls(speeds=np.array(u["speeds"], dtype=float), probes=probes, json=d)

    def plot(self, title: Optional[str] = None, backend: str = "matplotlib"):
        """Bode plot: amplitude (log) and phase over speed, a line per probe (and x/y per
        direction in real coordinates). Returns the matplotlib Figure (``backend="plotly"``:
        the amplitudes in a plotly Figure)."""
        if backend == "plotly":
            go = _plotly()
            fig = go.Figure()
            for pr in self.probes:
                fig.add_scatter(x=self.speeds, y=pr.amplitude, name=pr.name)
            fig.update_layout(title=title or "Unbalance response", xaxis_title="speed Ω (rad/s)",
                              yaxis_title="amplitude (m)", yaxis_type="log")
            return fig
        plt = _pyplot()
        fig, (a, p) = plt.subplots(2, 1, sharex=True, figsize=(8, 6))
        for pr in self.probes:
            a.semilogy(self.speeds, pr.amplitude, label=pr.name)
            p.plot(self.speeds, np.degrees(pr.phase), label=pr.name)
            if pr.orbit is not None and "x_amplitude" in pr.orbit:
                a.semilogy(self.speeds, pr.orbit["x_amplitude"], ":", label=f"{pr.name} x")
                a.semilogy(self.speeds, pr.orbit["y_amplitude"], "--", label=f"{pr.name} y")
        a.set_ylabel("amplitude (m)")
        p.set_ylabel("phase (deg)")
        p.set_xlabel("speed Ω (rad/s)")
        a.legend(fontsize="small")
        a.set_title(title or "Unbalance response")
        return fig


@dataclass(frozen=True)
class DesignResult:
    """A design run (`rotorshunt design`): status, verification, the variables before and
    after, the tuned file's text (``tuned_toml``, what `design` writes as tuned.toml or
    best-effort.toml) and the outcome as the report's JSON (``outcome``)."""

    status: str
    verified: bool
    file_name: str
    tuned_toml: str
    before: np.ndarray
    after: np.ndarray
    variables: List[str]
    outcome: Dict[str, Any] = field(repr=False)
    summary: Optional[str] = None

    @classmethod
    def _of(cls, d: Dict[str, Any]) -> "DesignResult":
        outcome = json.loads(d["outcome"])
        variables = []
        for v in outcome.get("spec", {}).get("variables", []):
            if "branch" in v:
                variables.append(f"branch {v['branch'] + 1} {v.get('parameter')}")
            else:
                variables.append(str(v.get("parameter")))
        return cls(
            status=d["status"],
            verified=d["verified"],
            file_name=d["file_name"],
            tuned_toml=d["tuned_toml"],
            before=np.array(outcome["before"], dtype=float),
            after=np.array(outcome["after"], dtype=float),
            variables=variables,
            outcome=outcome,
            summary=d.get("summary"),
        )

    def bands(self, which: str = "after") -> List[Optional[tuple]]:
        """The stable bands (lo, hi) at each design speed, before or after (rad/s)."""
        out = []
        for s in self.outcome[f"{which}_speeds"]:
            found = s.get("band") or {}
            band = found.get("band") if isinstance(found, dict) else None
            out.append((band["lo"], band["hi"]) if band else None)
        return out

    def plot(self, title: Optional[str] = None):
        """Before and after: the variables (relative change) and the bands. Returns the Figure."""
        plt = _pyplot()
        fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4))
        # Each variable as its place in its bounds (0 = min, 1 = max), values annotated.
        spec = self.outcome.get("spec", {}).get("variables", [])
        lo = np.array([v.get("min", 0.0) for v in spec] or np.zeros(len(self.before)), dtype=float)
        hi = np.array([v.get("max", 1.0) for v in spec] or np.ones(len(self.before)), dtype=float)
        span = np.where(hi > lo, hi - lo, 1.0)
        x = np.arange(len(self.before))
        for k, (values, off, name) in enumerate(((self.before, -0.2, "before"), (self.after, 0.2, "after"))):
            frac = (values - lo) / span
            a.bar(x + off, frac, 0.4, label=name)
            for xi, f, v in zip(x, frac, values):
                a.annotate(f"{v:.4g}", (xi + off, f), ha="center", va="bottom", fontsize=7)
        a.set_xticks(x, self.variables or [str(i) for i in x], fontsize=7)
        a.set_ylim(0, 1.15)
        a.set_ylabel("place in its bounds")
        a.set_title("design variables")
        a.legend()
        for k, (which, colour) in enumerate((("before", "tab:grey"), ("after", "tab:green"))):
            for band in self.bands(which):
                if band:
                    b.plot(band, [k, k], color=colour, lw=8)
        b.set_yticks([0, 1], ["before", "after"])
        b.set_xlabel("φ (rad/s)")
        b.set_title("stable band at the level")
        fig.suptitle(title or f"design: {self.status}{' (verified)' if self.verified else ''}")
        fig.tight_layout()
        return fig
