"""Result objects of the Python API: frozen dataclasses of the fields the native module
builds from the Rust library's typed results (numpy arrays, numbers, and the command's
JSON document as dicts and lists, ``json``), their conveniences and their plots."""

from __future__ import annotations

import importlib
from dataclasses import field, fields, make_dataclass
from typing import Any, List, Optional

import numpy as np

from . import _rotorshunt as _native

# Fields left out of a result's repr: the JSON document and other bulky ones.
_BULKY = {"json", "outcome", "reduction", "scaled_multipliers", "boundary"}


def _result(names: str):
    """Class decorator: the class, its methods kept, as a frozen dataclass of the fields
    ``names`` (the keys of the native module's dict, in order)."""

    def make(cls):
        spec = [(n, Any, field(repr=n not in _BULKY)) for n in names.split()]
        body = {k: v for k, v in vars(cls).items() if k not in ("__dict__", "__weakref__")}
        return make_dataclass(cls.__name__, spec, namespace=body, frozen=True)

    return make


def _refuse(argument: str, expected: str, value: Any):
    """Raise the ArgumentError of ``argument``, which expected ``expected`` and was given
    ``value`` (worded as the native calls word theirs: the value and its type)."""
    raise _native._argument_error(argument, expected, value)


def _backend(backend: Any) -> str:
    """A plot's ``backend``: "matplotlib" or "plotly"."""
    if not (isinstance(backend, str) and backend in ("matplotlib", "plotly")):
        _refuse("backend", '"matplotlib" or "plotly"', backend)
    return backend


def _need(module: str, what: str):
    """An optional module (matplotlib, plotly, pandas), or an ImportError saying what needs it."""
    try:
        return importlib.import_module(module)
    except ImportError as e:  # pragma: no cover - depends on the environment
        package = module.split(".")[0]
        raise ImportError(f"{what} needs {package}: pip install {package}") from e


def _new_axes(ax=None):
    """``ax``'s figure and ``ax``, or a new figure and its axes."""
    if ax is not None and not hasattr(ax, "figure"):
        _refuse("ax", "None or matplotlib Axes", ax)
    return (ax.figure, ax) if ax is not None else _need("matplotlib.pyplot", "plotting").subplots(figsize=(8, 5))


@_result("speed critical_load static_load frequency whirl damping_ratio label kind eigenvalue json")
class ModesResult:
    """The lowest forward and backward whirls at a speed (`rotorshunt modes --json`), as
    arrays in the order of the command's list: by frequency (rad/s)."""

    @property
    def labels(self) -> np.ndarray:
        """The modes' tags, e.g. ``f1``, ``b1``, ``fr1``."""
        return np.array([{"forward": "f", "backward": "b"}.get(w, "") + l for w, l in zip(self.whirl, self.label)])

    def forward(self) -> np.ndarray:
        """Frequencies of the forward whirls (rad/s)."""
        return self.frequency[self.whirl == "forward"]

    def backward(self) -> np.ndarray:
        """Frequencies of the backward whirls (rad/s)."""
        return self.frequency[self.whirl == "backward"]


@_result("speeds tags whirl frequency damping_ratio operating_speeds critical_speeds json")
class CampbellResult:
    """Whirl frequencies over speed (`rotorshunt campbell`'s campbell.json): ``frequency[i,
    j]`` is track i at ``speeds[j]`` (rad/s), NaN where the track has no point."""

    def plot(self, ax=None, title: Optional[str] = None, backend: str = "matplotlib"):
        """The Campbell diagram: tracks (forward solid, backward dashed), the 1x line and the
        operating speeds. Returns the matplotlib Figure (``backend="plotly"``: plotly's)."""
        title = title or "Campbell diagram"
        if _backend(backend) == "plotly":
            fig = _need("plotly.graph_objects", "backend='plotly'").Figure()
            for tag, whirl, f in zip(self.tags, self.whirl, self.frequency):
                fig.add_scatter(x=self.speeds, y=f, name=tag, line_dash="dash" if whirl == "backward" else "solid")
            fig.add_scatter(x=self.speeds, y=self.speeds, name="1x", line=dict(color="black", dash="dot"))
            fig.update_layout(title=title, xaxis_title="speed Ω (rad/s)", yaxis_title="whirl frequency (rad/s)")
            return fig
        fig, ax = _new_axes(ax)
        for tag, whirl, f in zip(self.tags, self.whirl, self.frequency):
            ax.plot(self.speeds, f, "-" if whirl != "backward" else "--", label=tag)
        ax.plot(self.speeds, self.speeds, "k:", lw=1, label="1x")
        for w in self.operating_speeds:
            ax.axvline(w, color="grey", lw=0.8)
        for c in self.critical_speeds:
            ax.plot([c["speed"]], [c["speed"]], "ko", ms=4)
        ax.set(xlabel="speed Ω (rad/s)", ylabel="whirl frequency (rad/s)", title=title)
        ax.legend(fontsize="small", ncol=2)
        return fig


@_result("speed phi beta max_multiplier ln_max_multiplier growth_rate stable status reason multipliers "
         "scaled_multipliers multiplier_log_scale basis")
class FloquetResult:
    """One Floquet point (`rotorshunt floquet --json`): max|μ|, growth rate, verdict and the
    multipliers μ as a complex array."""


def _draw_regions(ax, regions: "RegionsResult") -> None:
    """Each region's onset (a triangle), its edges at the level (a bar) and its label."""
    for r in regions:
        ax.plot([r.start], [r.onset_beta], "rv", ms=5)
        if r.left is not None and r.right is not None:
            ax.plot([r.left, r.right], [regions.level] * 2, "r-", lw=2)
        ax.annotate(r.label, (r.start, r.onset_beta), fontsize=7, rotation=90, va="bottom")


@_result("speed phis betas max_multiplier ln_max_multiplier growth_rate stable status status_names threshold "
         "failed inaccurate unstable reduction")
class ChartResult:
    """A stability chart over a (φ, β) grid: 2-D arrays indexed [i_φ, i_β]."""

    def plot(self, ax=None, regions: Optional["RegionsResult"] = None, title: Optional[str] = None):
        """The stability chart: unstable points in the (φ, β) plane and, given a catalogue,
        its regions' onsets and edges. Returns the matplotlib Figure."""
        if regions is not None and not isinstance(regions, RegionsResult):
            _refuse("regions", "None or a RegionsResult (Problem.regions)", regions)
        fig, ax = _new_axes(ax)
        P, B = np.meshgrid(self.phis, self.betas, indexing="ij")
        bad = ~self.stable & (self.status != 2)
        ax.scatter(P[bad], B[bad], s=4, c="tab:blue", marker="s", label="unstable")
        if regions is not None:
            _draw_regions(ax, regions)
        ax.set(xlim=(self.phis.min(), self.phis.max()), ylim=(self.betas.min(), self.betas.max()),
               xlabel="φ (rad/s)", ylabel="β", title=title or f"Stability chart at Ω = {self.speed:g} rad/s")
        return fig

    def plot_growth(self, ax=None, title: Optional[str] = None, backend: str = "matplotlib"):
        """The growth-rate map ln(max|μ|)/T (1/s) over the grid. Returns the matplotlib
        Figure (``backend="plotly"``: a plotly heat map)."""
        title = title or f"Growth rate at Ω = {self.speed:g} rad/s"
        if _backend(backend) == "plotly":
            go = _need("plotly.graph_objects", "backend='plotly'")
            fig = go.Figure(go.Heatmap(x=self.phis, y=self.betas, z=self.growth_rate.T, colorbar_title="1/s"))
            fig.update_layout(title=title, xaxis_title="φ (rad/s)", yaxis_title="β")
            return fig
        fig, ax = _new_axes(ax)
        m = ax.pcolormesh(self.phis, self.betas, self.growth_rate.T, shading="nearest", cmap="viridis")
        fig.colorbar(m, ax=ax, label="growth rate (1/s)")
        ax.set(xlabel="φ (rad/s)", ylabel="β", title=title)
        return fig


@_result("label kind order predicted start onset_beta left right width counted resolved boundary")
class Region:
    """One instability region of a catalogue (`rotorshunt regions --json`)."""


class RegionsResult(list):
    """The catalogue of regions: a list of :class:`Region`, with the stable bands at the
    level (``stable_bands``, an (n, 2) array), their load margins and the JSON."""

    def __init__(self, native: dict):
        super().__init__(Region(**{f.name: r[f.name] for f in fields(Region)}) for r in native["json"]["regions"])
        self.__dict__.update(native)

    def to_dataframe(self):
        """The regions as a pandas DataFrame (needs pandas)."""
        pd = _need("pandas", "to_dataframe")
        cols = [f.name for f in fields(Region) if f.name != "boundary"]
        return pd.DataFrame([[getattr(r, c) for c in cols] for r in self], columns=cols)

    def plot(self, ax=None, chart: Optional[ChartResult] = None, title: Optional[str] = None):
        """The regions' onsets and edges at the level over the stable bands, on a chart if
        given. Returns the matplotlib Figure."""
        if chart is not None:
            if not isinstance(chart, ChartResult):
                _refuse("chart", "None or a ChartResult (Problem.chart)", chart)
            return chart.plot(ax=ax, regions=self, title=title)
        fig, ax = _new_axes(ax)
        for lo, hi in self.stable_bands:
            ax.axvspan(lo, hi, ymax=0.02, color="tab:green")
        _draw_regions(ax, self)
        ax.axhline(self.level, color="grey", lw=0.8)
        ax.set(xlim=self.range, ylim=(0, self.beta_max), xlabel="φ (rad/s)", ylabel="onset β",
               title=title or f"Instability regions at Ω = {self.speed:g} rad/s")
        return fig


@_result("phi_op level band width left right margins json")
class BandResult:
    """The stable band around φ_op at a level (`rotorshunt band --json`), with margins."""


@_result("name kind node amplitude phase peaks orbit")
class Probe:
    """The response at one probe: amplitude and phase over speed; in real coordinates
    also the x/y motions and the orbit's axes (``orbit`` holds arrays, else None)."""


@_result("speeds probes json")
class UnbalanceResult:
    """The synchronous unbalance response (`rotorshunt unbalance`'s unbalance.json)."""

    def plot(self, title: Optional[str] = None, backend: str = "matplotlib"):
        """Bode plot: amplitude (log) and phase over speed, a line per probe (and x/y in real
        coordinates). Returns the matplotlib Figure (``backend="plotly"``: the amplitudes')."""
        title = title or "Unbalance response"
        if _backend(backend) == "plotly":
            fig = _need("plotly.graph_objects", "backend='plotly'").Figure()
            for pr in self.probes:
                fig.add_scatter(x=self.speeds, y=pr.amplitude, name=pr.name)
            fig.update_layout(title=title, xaxis_title="speed Ω (rad/s)", yaxis_title="amplitude (m)",
                              yaxis_type="log")
            return fig
        fig, (a, p) = _need("matplotlib.pyplot", "plotting").subplots(2, 1, sharex=True, figsize=(8, 6))
        for pr in self.probes:
            a.semilogy(self.speeds, pr.amplitude, label=pr.name)
            p.plot(self.speeds, np.degrees(pr.phase), label=pr.name)
            if pr.orbit is not None:
                a.semilogy(self.speeds, pr.orbit["x_amplitude"], ":", label=f"{pr.name} x")
                a.semilogy(self.speeds, pr.orbit["y_amplitude"], "--", label=f"{pr.name} y")
        a.set(ylabel="amplitude (m)", title=title)
        p.set(ylabel="phase (deg)", xlabel="speed Ω (rad/s)")
        a.legend(fontsize="small")
        return fig


@_result("status verified file_name tuned_toml before after variables outcome summary")
class DesignResult:
    """A design run (`rotorshunt design`): status, verification, the variables before and
    after, the tuned file's text (``tuned_toml``, what `design` writes as tuned.toml or
    best-effort.toml) and the outcome as the report's JSON (``outcome``)."""

    def bands(self, which: str = "after") -> List[Optional[tuple]]:
        """The stable bands (lo, hi) at each design speed, before or after (rad/s)."""
        if not (isinstance(which, str) and which in ("before", "after")):
            _refuse("which", '"before" or "after"', which)
        found = [(s.get("band") or {}).get("band") for s in self.outcome[f"{which}_speeds"]]
        return [(b["lo"], b["hi"]) if b else None for b in found]

    def plot(self, title: Optional[str] = None):
        """Before and after: the variables (relative change) and the bands. Returns the Figure."""
        fig, (a, b) = _need("matplotlib.pyplot", "plotting").subplots(1, 2, figsize=(10, 4))
        # Each variable as its place in its bounds (0 = min, 1 = max), values annotated.
        spec = self.outcome["spec"]["variables"]
        lo = np.array([v["min"] for v in spec], dtype=float)
        span = np.array([v["max"] for v in spec], dtype=float) - lo
        x = np.arange(len(self.before))
        for values, off, name in ((self.before, -0.2, "before"), (self.after, 0.2, "after")):
            frac = (values - lo) / np.where(span > 0, span, 1.0)
            a.bar(x + off, frac, 0.4, label=name)
            for xi, f, v in zip(x, frac, values):
                a.annotate(f"{v:.4g}", (xi + off, f), ha="center", va="bottom", fontsize=7)
        a.set_xticks(x, self.variables, fontsize=7)
        a.set(ylim=(0, 1.15), ylabel="place in its bounds", title="design variables")
        a.legend()
        for k, (which, colour) in enumerate((("before", "tab:grey"), ("after", "tab:green"))):
            for band in filter(None, self.bands(which)):
                b.plot(band, [k, k], color=colour, lw=8)
        b.set_yticks([0, 1], ["before", "after"])
        b.set(xlabel="φ (rad/s)", title="stable band at the level")
        fig.suptitle(title or f"design: {self.status}{' (verified)' if self.verified else ''}")
        fig.tight_layout()
        return fig
