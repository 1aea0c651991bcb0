"""The quasi-dynamic design of a stepping pier (Part 1 of the paper).

:class:`DesignOptions` holds the inputs of a run (the ``stepframe structure design`` options, each
declared once on its field) and :func:`design_run` runs it. :func:`merged_design_input` lays
overrides over the tables of a design TOML file; :func:`design_case` turns them into a
:class:`~stepframe.structure.quasi_dynamic.DesignCase`; :func:`run_design` computes the map
constants, the closed-form and searched fixed points, the traced iterations and the design
answer, as a :class:`DesignRun` (``to_dict``; :func:`write_design_result` and
:func:`read_design_result` store it as JSON).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

from stepframe.core.jsonable import to_jsonable
from stepframe.core.options import Range, check_fields, option
from stepframe.errors import InputError

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from stepframe.structure.quasi_dynamic import (
        BranchChoice,
        DesignCase,
        DesignResult,
        FixedPoint,
        Iteration,
    )

#: A commented design input file (``stepframe structure design --template``).
DESIGN_TEMPLATE = """\
# Quasi-dynamic design input for `stepframe structure design --input THIS.toml`.
# SI units throughout (N, m, s). Values below: the paper's Example 1 (Priestley et al. Ex. 6.6).

[pier]                       # or [map] with w_per_m and lambda_2_sqrt_m (and optional g_m_s2)
weight_super_n = 8.0e6       # W_s, seismic weight of the superstructure [N]
weight_col_n = 2.12e5        # W_col [N]; the paper states 424 kN but substitutes 212 kN
weight_total_n = 9.6e6       # W_T, gross weight on the footing [N]
footing_length_m = 7.0       # L_F, footing length in the rocking direction [m]
height_m = 27.0              # H_r, height of the centroid of the rocking mass [m]
footing_width_m = 7.0        # B_F [m]  } a = W_T / (B_F q_n); or give block_width_m (a) instead
bearing_capacity_pa = 1.0e6  # q_n [Pa] }
col_weight_factor = 0.5      # share of W_col in the effective mass (eq. 1.2) [-]
g_m_s2 = 9.81                # gravity [m/s²]; also converts s_ds_g, s_d1_g, sa_g

[spectrum]                   # two-period: S_a = S_DS up to T_s = S_D1/S_DS, then S_D1/T
s_ds_m_s2 = 8.4665           # or s_ds_g [g]
s_d1_m_s = 5.2492            # or s_d1_g [g]; the paper gives the product β·S_D1 = 5.2492 m/s
# t_l_s = 8.0                # optional long-period transition T_L [s]: S_a = S_D1 T_L / T²
# Tabulated instead: periods_s = [0.0, 0.5, 1.0, 4.0] and sa_m_s2 = [...] (or sa_g = [...])

[damping]                    # exactly one of beta, xi, c_r
beta = 1.0                   # factor on the 5 %-damped spectrum [-]
# xi = 0.15                  # equivalent viscous damping ratio (fraction)
# c_r = 0.9                  # velocity ratio at impact: xi = 0.48 (1 - c_r²), eq. 4.17
# method = "ec8"             # with xi or c_r: "ec8" (default), "ec8-1998", "aashto-isolation"

[iteration]
delta0_m = [0.05, 2.0]       # starts of the AASHTO/Priestley iteration [m]
"""

#: Keys of ``[pier]`` an override may set (their meaning: the fields of :class:`DesignOptions`).
PIER_KEYS = (
    "weight_super_n",
    "weight_col_n",
    "weight_total_n",
    "footing_length_m",
    "height_m",
    "block_width_m",
    "footing_width_m",
    "bearing_capacity_pa",
    "col_weight_factor",
    "g_m_s2",
)
#: Keys of ``[spectrum]`` an override may set (a two-period spectrum).
SPECTRUM_KEYS = ("s_ds_g", "s_ds_m_s2", "s_d1_g", "s_d1_m_s", "t_l_s")
#: Keys of ``[map]`` an override may set.
MAP_KEYS = ("w_per_m", "lambda_2_sqrt_m")
#: Keys of ``[damping]`` an override may set (exactly one of them).
DAMPING_KEYS = ("beta", "xi", "c_r")
# The same quantity in g and in SI: an override in one unit replaces the file's value in the other.
_TWINS = {
    "s_ds_g": ("s_ds_m_s2",),
    "s_ds_m_s2": ("s_ds_g",),
    "s_d1_g": ("s_d1_m_s",),
    "s_d1_m_s": ("s_d1_g",),
}


# Plausible ranges of a pier's values: those of a frame file's (structure.frame_file.PLAUSIBLE)
# where the two name the same quantity.
_WEIGHT = Range(1e2, 1e10)
_LENGTH = Range(0, 300, low_open=True)
_SPECTRAL_G = Range(0, 10, low_open=True)
_SPECTRAL_SI = Range(0, 100, low_open=True)


@dataclass(frozen=True)
class DesignOptions:
    """The inputs of one design run (:func:`design_run`): a design file, values laid over its
    tables (None: not given), and how the iteration and the answer are computed.

    The fields carry the ``stepframe structure design`` options
    (:func:`stepframe.core.options.option`); their meaning and units are in their help. The
    choices are spelled out: ``BranchChoice`` is imported for type checking only.
    """

    input: str | None = option(None, "design input file (see --template)", metavar="TOML")
    weight_super_n: float | None = option(
        None, "W_s, seismic weight of the superstructure [N]", valid=_WEIGHT
    )
    weight_col_n: float | None = option(
        None, "W_col, weight of the column(s) [N]", valid=Range(0, _WEIGHT.high)
    )
    weight_total_n: float | None = option(
        None, "W_T, gross weight on the footing [N]", valid=_WEIGHT
    )
    footing_length_m: float | None = option(
        None, "L_F, footing length in the rocking direction [m]", valid=_LENGTH
    )
    height_m: float | None = option(
        None, "H_r, height of the centroid of the rocking mass [m]", valid=_LENGTH
    )
    block_width_m: float | None = option(
        None, "a, width of the compression block under the footing [m]", valid=_LENGTH
    )
    footing_width_m: float | None = option(
        None, "B_F, footing width [m] (a = W_T/(B_F q_n))", valid=_LENGTH
    )
    bearing_capacity_pa: float | None = option(
        None, "q_n, soil bearing capacity [Pa]", valid=Range(1e3, 1e9)
    )
    col_weight_factor: float | None = option(
        None, "share of W_col in the effective mass (default 0.5)", valid=Range(0, 1)
    )
    g_m_s2: float | None = option(
        None, "gravity [m/s²] (default 9.81, as in the paper)", valid=Range(9.7, 9.9)
    )
    s_ds_g: float | None = option(
        None, "S_DS [g]", kind="positive", flag="--sds-g", valid=_SPECTRAL_G
    )
    s_ds_m_s2: float | None = option(
        None, "S_DS [m/s²]", kind="positive", flag="--sds-m-s2", valid=_SPECTRAL_SI
    )
    s_d1_g: float | None = option(
        None, "S_D1 [g]", kind="positive", flag="--sd1-g", valid=_SPECTRAL_G
    )
    s_d1_m_s: float | None = option(
        None, "S_D1 [m/s]", kind="positive", flag="--sd1-m-s", valid=_SPECTRAL_SI
    )
    t_l_s: float | None = option(
        None,
        "long-period transition T_L [s]",
        kind="positive",
        flag="--tl-s",
        valid=Range(0, 100, low_open=True),
    )
    beta: float | None = option(
        None, "spectral reduction factor β", kind="positive", valid=Range(0, 10, low_open=True)
    )
    xi: float | None = option(
        None, "equivalent viscous damping ratio (fraction)", valid=Range(0, 1, high_open=True)
    )
    c_r: float | None = option(
        None, "velocity ratio at impact; ξ = 0.48(1 - C_r²)", valid=Range(0, 1)
    )
    damping_method: Literal["ec8", "ec8-1998", "aashto-isolation"] | None = option(
        None,
        "damping-reduction formula with --xi/--c-r (default ec8)",
        choices=("ec8", "ec8-1998", "aashto-isolation"),
    )
    w_per_m: float | None = option(
        None, "w of eq. 2.3 [1/m]", kind="positive", valid=Range(0, 1e4, low_open=True)
    )
    lambda_2_sqrt_m: float | None = option(
        None,
        "λ_2 of eq. 2.5 [m^½] (needs S_D1)",
        kind="positive",
        valid=Range(0, 1e4, low_open=True),
    )
    branch: BranchChoice = option(
        "auto",
        "spectrum branch used by the iteration: auto (S_a at each T_i, the procedure) or one "
        "branch's formula whatever T_i is (as the paper's Table 1 does)",
        choices=("auto", "short", "long", "very-long"),
    )
    delta0_m: list[float] | None = option(
        None,
        "starts of the iteration [m]",
        kind="floats",
        metavar="D,...",
        valid=Range(0, 100, low_open=True),
    )
    method: Literal["closed-form", "search"] | None = option(
        None,
        "how the design answer is chosen (default: closed-form for a two-period spectrum, "
        "search for a tabulated one)",
        choices=("closed-form", "search"),
    )
    max_iterations: int = option(
        200, "iteration limit (default 200)", kind="int", valid=Range(1, 100_000)
    )

    def __post_init__(self) -> None:
        check_fields(self)


def design_run(options: DesignOptions) -> DesignRun:
    """The design run of :class:`DesignOptions`: :func:`design_case` of the file and the values
    given, then :func:`run_design`."""
    overrides = {
        name: getattr(options, name)
        for name in (*PIER_KEYS, *MAP_KEYS, *SPECTRUM_KEYS, *DAMPING_KEYS)
    }
    case = design_case(
        options.input,
        overrides,
        damping_method=options.damping_method,
        delta0_m=options.delta0_m,
    )
    return run_design(
        case, method=options.method, branch=options.branch, max_iterations=options.max_iterations
    )


def merged_design_input(
    path: str | PathLike[str] | None,
    overrides: Mapping[str, Any],
    *,
    damping_method: str | None = None,
    delta0_m: list[float] | None = None,
) -> dict[str, Any]:
    """The TOML tables of ``path`` with ``overrides`` laid over them.

    Parameters
    ----------
    path
        A design input file (see ``stepframe structure design --template``), or None.
    overrides
        Keys of :data:`PIER_KEYS`, :data:`MAP_KEYS`, :data:`SPECTRUM_KEYS` and
        :data:`DAMPING_KEYS` → value (None: not given). Pier values replace a ``[map]`` and map
        values a ``[pier]``; spectrum values replace a tabulated spectrum; a damping value
        replaces the whole ``[damping]`` table.
    damping_method
        The damping-reduction formula to use with ``xi``/``c_r``.
    delta0_m
        Starts of the iteration [m] (replace ``[iteration]``).

    Raises
    ------
    InputError
        Both pier and map values, no input at all, or a bad file (with its line).
    """
    from stepframe.core.io import read_toml

    data: dict[str, Any] = {}
    if path:
        data, _ = read_toml(path, "a design input TOML file")
    given = {key: value for key, value in overrides.items() if value is not None}
    pier = {k: v for k, v in given.items() if k in PIER_KEYS}
    if pier:
        data.pop("map", None)
        data["pier"] = dict(data.get("pier", {})) | pier
    given_map = {k: v for k, v in given.items() if k in MAP_KEYS}
    if given_map:
        if pier:
            raise InputError("pier options and --w-per-m/--lambda-2-sqrt-m given, expected one")
        data.pop("pier", None)
        data["map"] = dict(data.get("map", {})) | given_map
    spectrum = {k: v for k, v in given.items() if k in SPECTRUM_KEYS}
    if spectrum:
        base = dict(data.get("spectrum", {}))
        if "periods_s" in base:  # options describe a two-period spectrum: drop the table
            base = {}
        for key in spectrum:
            for twin in _TWINS.get(key, ()):
                base.pop(twin, None)
        data["spectrum"] = base | spectrum
    damping = {k: v for k, v in given.items() if k in DAMPING_KEYS}
    if len(damping) > 1:  # named as given, not as a file's [damping] they never were in
        flags = ", ".join("--" + key.replace("_", "-") for key in damping)
        raise InputError(
            f"{flags} given, expected exactly one of --beta, --xi or --c-r (it replaces the "
            "whole [damping] of the input)"
        )
    if damping:
        data["damping"] = damping
    if damping_method is not None:
        data["damping"] = dict(data.get("damping", {})) | {"method": damping_method}
    if delta0_m is not None:
        data["iteration"] = {"delta0_m": delta0_m}
    if not data:
        raise InputError("no inputs, expected --input FILE.toml or the pier/spectrum options")
    return data


def design_case(
    path: str | PathLike[str] | None,
    overrides: Mapping[str, Any] | None = None,
    *,
    damping_method: str | None = None,
    delta0_m: list[float] | None = None,
) -> DesignCase:
    """The design case of a TOML file with overrides (see :func:`merged_design_input`)."""
    from stepframe.structure.quasi_dynamic import case_from_dict

    data = merged_design_input(
        path, overrides or {}, damping_method=damping_method, delta0_m=delta0_m
    )
    try:
        return case_from_dict(data, where=str(path) if path else "options")
    except InputError as error:
        raise _at_key_line(error, path, overrides or {}) from None


def _at_key_line(
    error: InputError, path: str | PathLike[str] | None, overrides: Mapping[str, Any]
) -> InputError:
    """``error`` at the line of the file's key it starts with (``beta = -1.0, expected > 0``
    named neither the file nor the line); as it is when the value came from an option, or when
    it names no key of the file."""
    from stepframe.core.io import read_toml
    from stepframe.pipeline.engine.workflow import Lines

    key = error.key or error.what.split(" ", 1)[0]
    if not path or error.path is not None or overrides.get(key) is not None:
        return error
    _, text = read_toml(path, "a design input TOML file")
    lines = Lines(Path(path), text)
    line = next((number for (_, name), number in lines.keys.items() if name == key), None)
    return error if line is None else InputError(error.what, path, line)


@dataclass(frozen=True)
class DesignRun:
    """Everything ``stepframe structure design`` reports for one case.

    Attributes
    ----------
    case
        The inputs.
    constants
        Map constants: w [1/m], c [s²/m], β, ξ, δ limit [m]; for a two-period spectrum also T_s
        [s], λ_1, λ_2 [m^½], wλ_2², λ_3 [m] and the stability tests of eqs. 2.12 and 2.17.
    closed, found
        Closed-form fixed points (eqs. 2.9, 2.14; two-period spectra only) and those of the
        full map found numerically.
    traces
        The iteration from each start.
    design
        The design answer (its ``status`` says whether one exists).
    """

    case: DesignCase
    constants: dict[str, Any]
    closed: tuple[FixedPoint, ...]
    found: tuple[FixedPoint, ...]
    traces: tuple[Iteration, ...]
    design: DesignResult

    @property
    def status(self) -> str:
        """The design answer's status (``ok`` or ``failed``)."""
        return self.design.status

    def describe(self, *, trace_rows: bool = False) -> str:
        """The run as text: constants, fixed points, iterations (every iterate with
        ``trace_rows``) and the design answer."""
        return _describe(self, trace_rows)

    def figure(self) -> Figure:
        """The cobweb of the iterations over the map, with the fixed points."""
        from stepframe.structure.plots import cobweb_figure

        points = [*self.closed, *self.found]
        return cobweb_figure(self.case.stepping_map, self.case.spectrum, self.traces, points)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready form (what ``stepframe structure design --json`` prints)."""
        return {
            "inputs": self.case.to_dict(),
            "constants": dict(self.constants),
            "fixed_points": [p.to_dict() for p in self.closed],
            "search": [p.to_dict() for p in self.found],
            "iterations": [t.to_dict() for t in self.traces],
            "design": {k: v for k, v in self.design.to_dict().items() if k != "iteration"},
        }


def run_design(
    case: DesignCase,
    *,
    method: Literal["closed-form", "search"] | None = None,
    branch: BranchChoice = "auto",
    max_iterations: int = 200,
) -> DesignRun:
    """Fixed points, iterations and the design answer of ``case``.

    Parameters
    ----------
    case
        The design case.
    method
        How the answer is chosen (default closed-form for a two-period spectrum, search for a
        tabulated one).
    branch
        Spectrum branch the iteration uses (``auto``: S_a at each T_i).
    max_iterations
        Iteration limit.
    """
    from stepframe.structure.design_spectrum import TwoPeriodSpectrum
    from stepframe.structure.quasi_dynamic import (
        closed_form_fixed_points,
        design_displacement,
        iterate,
        search_fixed_points,
    )

    if max_iterations < 1:
        raise InputError(f"--max-iterations {max_iterations}, expected ≥ 1")
    smap, spectrum = case.stepping_map, case.spectrum
    two_period = isinstance(spectrum, TwoPeriodSpectrum)
    chosen: Literal["closed-form", "search"] = method or ("closed-form" if two_period else "search")
    if chosen == "closed-form" and not two_period:
        raise InputError("--method closed-form needs a two-period spectrum, expected search")
    starts = case.delta0_m or (0.05 * smap.delta_limit_m,)
    closed = (
        closed_form_fixed_points(smap, spectrum) if isinstance(spectrum, TwoPeriodSpectrum) else ()
    )
    found = search_fixed_points(smap, spectrum)
    traces = tuple(
        iterate(smap, spectrum, d0, branch=branch, max_iterations=max_iterations) for d0 in starts
    )
    design = design_displacement(smap, spectrum, chosen)
    constants: dict[str, Any] = {
        "w_per_m": smap.w_per_m,
        "c_s2_per_m": smap.c_s2_per_m,
        "beta": smap.beta,
        "xi": case.xi,
        "damping_method": case.damping_method,
        "delta_limit_m": smap.delta_limit_m,
    }
    if isinstance(spectrum, TwoPeriodSpectrum):
        lam2 = smap.lambda_2_sqrt_m(spectrum)
        constants |= {
            "t_s_s": spectrum.t_s_s,
            "lambda_1": smap.lambda_1(spectrum),
            "lambda_2_sqrt_m": lam2,
            "w_lambda_2_sq": smap.w_per_m * lam2**2,
            "lambda_3_m": smap.lambda_3_m(spectrum),
            "stable_short_eq_2_12": smap.lambda_1(spectrum) < 1,
            "stable_long_eq_2_17": smap.w_per_m * lam2**2 < 0.25,
        }
    return DesignRun(case, constants, tuple(closed), tuple(found), traces, design)


def _fmt(value: Any, spec: str = ".6g") -> str:
    return "-" if value is None else format(value, spec)


def _describe(run: DesignRun, trace_rows: bool) -> str:
    constants, closed, found = run.constants, run.closed, run.found
    traces, design = run.traces, run.design
    lines = ["map constants:"]
    for key, value in constants.items():
        if value is not None:
            lines.append(f"  {key:22s} {value if isinstance(value, str | bool) else _fmt(value)}")
    header = f"  {'name':9s} {'formula':14s} {'branch':9s} {'delta_m':>12s} {'period_s':>10s} "
    header += f"{'multiplier':>11s}  stable  on branch"
    if closed:
        lines += ["closed-form fixed points (eqs. 2.9, 2.14):", header]
        for p in closed:
            lines.append(
                f"  {p.name:9s} {p.formula[:14]:14s} {p.branch:9s} {_fmt(p.delta_m):>12s} "
                f"{_fmt(p.period_s):>10s} {_fmt(p.multiplier):>11s}  "
                f"{'yes' if p.stable else 'no':6s}  {'yes' if p.on_branch else 'no'}"
            )
    lines += ["fixed points of the full map (numerical search):", header]
    for p in found:
        lines.append(
            f"  {p.name:9s} {'search':14s} {p.branch:9s} {_fmt(p.delta_m):>12s} "
            f"{_fmt(p.period_s):>10s} {_fmt(p.multiplier):>11s}  {'yes' if p.stable else 'no':6s}"
            "  yes"
        )
    for trace in traces:
        first = trace.rows[0]
        if trace_rows:
            lines.append(f"  {'i':>4s} {'delta_m':>15s} {'K_n_m':>13s} {'period_s':>10s}  branch")
            for row in trace.rows:
                lines.append(
                    f"  {row.i:4d} {row.delta_m:15.8e} {_fmt(row.stiffness_n_m, '13.6e'):>13s} "
                    f"{row.period_s:10.6f}  {row.branch}"
                )
        lines.extend(f"  note: {note}" for note in trace.notes)
        # "no convergence in 19 iterations" counts its steps already
        steps = "" if trace.status == "not_converged" else f" after {len(trace.rows) - 1} steps"
        lines.append(
            f"iteration from delta0 = {first.delta_m:.6g} m: {trace.message}{steps}, "
            f"delta = {trace.delta_m:.6g} m, T = {trace.period_s:.6g} s"
        )
    if design.delta_m is None:
        lines.append(f"design ({design.method}): {design.message}")
    else:
        lines.append(
            f"design ({design.method}): delta* = {design.delta_m:.6g} m, T* = "
            f"{_fmt(design.period_s)} s, multiplier {_fmt(design.multiplier)}, "
            f"branch {design.branch}, SE = {_fmt(design.stepping_effectiveness, '.4f')}"
        )
    return "\n".join(lines)


def design_displacement_m(path: str | Path) -> float:
    """δ* [m] of a quasi-dynamic design input file (closed form for a two-period spectrum,
    search for a tabulated one); an error when the design gives no positive δ*."""
    from stepframe.structure.design_spectrum import TwoPeriodSpectrum
    from stepframe.structure.quasi_dynamic import design_displacement, read_case

    case = read_case(path)
    closed = isinstance(case.spectrum, TwoPeriodSpectrum)
    result = design_displacement(
        case.stepping_map, case.spectrum, "closed-form" if closed else "search"
    )
    if result.delta_m is None or not result.delta_m > 0:
        raise InputError(
            f"the design gives no positive design displacement (status {result.status}), "
            "expected one to bound the band (or give --a-max-m)",
            path,
        )
    return float(result.delta_m)


def write_design_result(run: DesignRun, path: str | PathLike[str]) -> Path:
    """Write ``run.to_dict()`` as JSON (atomically); :func:`read_design_result` reads it back."""
    import json

    from stepframe.core.io import atomic_write

    with atomic_write(path) as out:
        json.dump(to_jsonable(run.to_dict()), out, indent=2, allow_nan=False)
        out.write("\n")
    return Path(path)


def read_design_result(path: str | PathLike[str]) -> dict[str, Any]:
    """The dictionary written by :func:`write_design_result` (tuples come back as lists)."""
    import json

    target = Path(path)
    try:
        data: dict[str, Any] = json.loads(target.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise InputError("no such file, expected a design result (JSON)", target) from None
    except ValueError as error:
        raise InputError(f"not JSON ({error}), expected a design result", target) from None
    return data


__all__ = [
    "DAMPING_KEYS",
    "DESIGN_TEMPLATE",
    "MAP_KEYS",
    "PIER_KEYS",
    "SPECTRUM_KEYS",
    "DesignOptions",
    "DesignRun",
    "design_case",
    "design_displacement_m",
    "design_run",
    "merged_design_input",
    "read_design_result",
    "run_design",
    "write_design_result",
]
