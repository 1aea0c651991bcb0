"""``stepframe structure design``: quasi-dynamic design displacement of a stepping pier (Part 1).

Inputs come from a TOML file (``--input``, see ``--template``) or from options; options given on
the command line override the file's values. The command prints the map constants (w, λ_1, λ_2),
the closed-form fixed points δ_1*..δ_4* (eqs. 2.9, 2.14) with their multipliers, stability and
branch check, the fixed points of the full map found numerically, the traced AASHTO/Priestley
iteration from each start, and the design answer δ*, T* and stepping effectiveness SE.
"""

from __future__ import annotations

import argparse
from typing import Any, Literal

from stepframe.commands import CommandResult, add_command, float_list, positive_float

EXAMPLES = """\
  # Example 2 of the paper (two-column steel frame), β = 0.8, W_col = 0 (the paper leaves it out):
  stepframe structure design --weight-super-n 1.472e6 --weight-col-n 0 \\
      --weight-total-n 2.807e6 --footing-length-m 8.839 --block-width-m 1.166 \\
      --height-m 29.944 --sds-g 1.038 --sd1-g 0.456 --beta 0.8 --delta0-m 0.00254,0.3048
  # The paper's Table 1 (Example 2, caption constants, long-branch formula forced), full trace:
  stepframe structure design --w-per-m 0.136737 --lambda-2-sqrt-m 0.381964 --sds-g 1.038 \
      --sd1-g 0.456 --beta 0.8 --delta0-m 0.00254,0.3048 --branch long --max-iterations 19 --trace
  # From a file, β from the velocity ratio at impact (eq. 4.17, Eurocode 8 reduction):
  stepframe structure design --template > pier.toml
  stepframe structure design --input pier.toml --c-r 0.9 --plot cobweb.png --json
"""

TEMPLATE = """\
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

_PIER_OPTIONS = {
    "weight_super_n": "W_s, seismic weight of the superstructure [N]",
    "weight_col_n": "W_col, weight of the column(s) [N]",
    "weight_total_n": "W_T, gross weight on the footing [N]",
    "footing_length_m": "L_F, footing length in the rocking direction [m]",
    "height_m": "H_r, height of the centroid of the rocking mass [m]",
    "block_width_m": "a, width of the compression block under the footing [m]",
    "footing_width_m": "B_F, footing width [m] (a = W_T/(B_F q_n))",
    "bearing_capacity_pa": "q_n, soil bearing capacity [Pa]",
    "col_weight_factor": "share of W_col in the effective mass (default 0.5)",
    "g_m_s2": "gravity [m/s²] (default 9.81, as in the paper)",
}
_SPECTRUM_OPTIONS = {
    "s_ds_g": ("--sds-g", "S_DS [g]"),
    "s_ds_m_s2": ("--sds-m-s2", "S_DS [m/s²]"),
    "s_d1_g": ("--sd1-g", "S_D1 [g]"),
    "s_d1_m_s": ("--sd1-m-s", "S_D1 [m/s]"),
    "t_l_s": ("--tl-s", "long-period transition T_L [s]"),
}
_TWINS = {
    "s_ds_g": ("s_ds_m_s2",),
    "s_ds_m_s2": ("s_ds_g",),
    "s_d1_g": ("s_d1_m_s",),
    "s_d1_m_s": ("s_d1_g",),
}


def register(subparsers: Any) -> None:
    """Add ``design`` to the ``structure`` group."""
    parser = add_command(
        subparsers,
        "design",
        help="quasi-dynamic design displacement: fixed points, stability, iteration, SE",
        description=__doc__.split("\n\n", 1)[1].strip() if __doc__ else None,
        examples=EXAMPLES,
        run=run,
    )
    parser.add_argument("--input", metavar="TOML", help="design input file (see --template)")
    parser.add_argument(
        "--template", action="store_true", help="print a commented input file and exit"
    )
    pier = parser.add_argument_group("pier (override [pier] of --input)")
    for key, text in _PIER_OPTIONS.items():
        pier.add_argument("--" + key.replace("_", "-"), dest=key, type=float, help=text)
    spectrum = parser.add_argument_group("two-period spectrum (override [spectrum])")
    for key, (flag, text) in _SPECTRUM_OPTIONS.items():
        spectrum.add_argument(flag, dest=key, type=positive_float, help=text)
    damping = parser.add_argument_group("damping (override [damping]; one of --beta/--xi/--c-r)")
    damping.add_argument("--beta", type=positive_float, help="spectral reduction factor β")
    damping.add_argument("--xi", type=float, help="equivalent viscous damping ratio (fraction)")
    damping.add_argument(
        "--c-r", dest="c_r", type=float, help="velocity ratio at impact; ξ = 0.48(1 - C_r²)"
    )
    damping.add_argument(
        "--damping-method",
        choices=("ec8", "ec8-1998", "aashto-isolation"),
        help="damping-reduction formula with --xi/--c-r (default ec8)",
    )
    given_map = parser.add_argument_group("map constants instead of a pier (override [map])")
    given_map.add_argument("--w-per-m", type=positive_float, help="w of eq. 2.3 [1/m]")
    given_map.add_argument(
        "--lambda-2-sqrt-m", type=positive_float, help="λ_2 of eq. 2.5 [m^½] (needs S_D1)"
    )
    parser.add_argument(
        "--branch",
        choices=("auto", "short", "long", "very-long"),
        default="auto",
        help="spectrum branch used by the iteration: auto (S_a at each T_i, the procedure) or "
        "one branch's formula whatever T_i is (as the paper's Table 1 does)",
    )
    parser.add_argument("--trace", action="store_true", help="print every iterate (i, δ, K, T)")
    parser.add_argument(
        "--delta0-m", type=float_list, metavar="D,...", help="starts of the iteration [m]"
    )
    parser.add_argument(
        "--method",
        choices=("closed-form", "search"),
        default=None,
        help="how the design answer is chosen (default: closed-form for a two-period "
        "spectrum, search for a tabulated one)",
    )
    parser.add_argument(
        "--max-iterations", type=int, default=200, help="iteration limit (default 200)"
    )
    parser.add_argument("--plot", metavar="OUT.png", help="draw the cobweb of the iteration")


def _merged_input(args: argparse.Namespace) -> dict[str, Any]:
    """The TOML tables of --input with command-line options laid over them."""
    import tomllib
    from pathlib import Path

    from stepframe.errors import InputError

    data: dict[str, Any] = {}
    if args.input:
        path = Path(args.input)
        try:
            with path.open("rb") as handle:
                data = tomllib.load(handle)
        except FileNotFoundError:
            raise InputError("no such file, expected a design input TOML file", path) from None
        except tomllib.TOMLDecodeError as exc:
            raise InputError(f"not valid TOML ({exc})", path) from None
    pier = {k: getattr(args, k) for k in _PIER_OPTIONS if getattr(args, k) is not None}
    if pier:
        data.pop("map", None)
        data["pier"] = dict(data.get("pier", {})) | pier
    given_map = {
        k: getattr(args, k) for k in ("w_per_m", "lambda_2_sqrt_m") if getattr(args, k) is not None
    }
    if given_map:
        if pier:
            raise InputError("pier options and --w-per-m/--lambda-2-sqrt-m given, expected one")
        data.pop("pier", None)
        data["map"] = dict(data.get("map", {})) | given_map
    spectrum = {k: getattr(args, k) for k in _SPECTRUM_OPTIONS if getattr(args, k) is not None}
    if spectrum:
        base = dict(data.get("spectrum", {}))
        if "periods_s" in base:  # options describe a two-period spectrum: drop the table
            base = {}
        for key in spectrum:  # an option in g replaces the file's value in SI, and vice versa
            for twin in _TWINS.get(key, ()):
                base.pop(twin, None)
        data["spectrum"] = base | spectrum
    damping = {k: getattr(args, k) for k in ("beta", "xi", "c_r") if getattr(args, k) is not None}
    if damping:
        data["damping"] = damping
    if args.damping_method is not None:
        data["damping"] = dict(data.get("damping", {})) | {"method": args.damping_method}
    if args.delta0_m is not None:
        data["iteration"] = {"delta0_m": args.delta0_m}
    if not data:
        raise InputError("no inputs, expected --input FILE.toml or the pier/spectrum options")
    return data


def run(args: argparse.Namespace) -> CommandResult:
    """Compute and report the design displacement."""
    if args.template:
        return CommandResult({"template": TEMPLATE}, TEMPLATE.rstrip("\n"))

    from stepframe.errors import InputError
    from stepframe.structure.design_spectrum import TwoPeriodSpectrum
    from stepframe.structure.quasi_dynamic import (
        case_from_dict,
        closed_form_fixed_points,
        design_displacement,
        iterate,
        search_fixed_points,
    )

    if args.max_iterations < 1:
        raise InputError(f"--max-iterations {args.max_iterations}, expected ≥ 1")
    case = case_from_dict(_merged_input(args), where=args.input or "options")
    smap, spectrum = case.stepping_map, case.spectrum
    two_period = isinstance(spectrum, TwoPeriodSpectrum)
    method: Literal["closed-form", "search"] = args.method or (
        "closed-form" if two_period else "search"
    )
    if method == "closed-form" and not two_period:
        raise InputError("--method closed-form needs a two-period spectrum, expected search")
    starts = case.delta0_m or (0.05 * smap.delta_limit_m,)
    closed = (
        closed_form_fixed_points(smap, spectrum) if isinstance(spectrum, TwoPeriodSpectrum) else ()
    )
    found = search_fixed_points(smap, spectrum)
    traces = [
        iterate(smap, spectrum, d0, branch=args.branch, max_iterations=args.max_iterations)
        for d0 in starts
    ]
    design = design_displacement(smap, spectrum, method)

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
    data = {
        "inputs": case.to_dict(),
        "constants": constants,
        "fixed_points": [p.to_dict() for p in closed],
        "search": [p.to_dict() for p in found],
        "iterations": [t.to_dict() for t in traces],
        "design": {k: v for k, v in design.to_dict().items() if k != "iteration"},
    }
    if args.plot:
        _plot_cobweb(args.plot, smap, spectrum, traces, [*closed, *found])
        data["plot"] = args.plot
    text = _text(constants, closed, found, traces, design, args.plot, trace_rows=args.trace)
    return CommandResult(data, text)


def _fmt(value: Any, spec: str = ".6g") -> str:
    return "-" if value is None else format(value, spec)


def _text(
    constants: dict[str, Any],
    closed: Any,
    found: Any,
    traces: Any,
    design: Any,
    plot: str | None,
    *,
    trace_rows: bool = False,
) -> str:
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
        lines.append(
            f"iteration from delta0 = {first.delta_m:.6g} m: {trace.status} after "
            f"{len(trace.rows) - 1} steps, delta = {trace.delta_m:.6g} m, "
            f"T = {trace.period_s:.6g} s"
        )
    if design.delta_m is None:
        lines.append(f"design ({design.method}): no stable fixed point lies on its branch")
    else:
        lines.append(
            f"design ({design.method}): delta* = {design.delta_m:.6g} m, T* = "
            f"{_fmt(design.period_s)} s, multiplier {_fmt(design.multiplier)}, "
            f"branch {design.branch}, SE = {_fmt(design.stepping_effectiveness, '.4f')}"
        )
    if plot:
        lines.append(f"cobweb written to {plot}")
    return "\n".join(lines)


def _plot_cobweb(path: str, smap: Any, spectrum: Any, traces: Any, points: Any) -> None:
    """The map f(δ), the diagonal, the iterates as a cobweb and the fixed points; atomic write."""
    import os
    from pathlib import Path

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    from stepframe.errors import InputError

    out = Path(path)
    if out.suffix.lower() not in (".png", ".pdf", ".svg"):
        raise InputError(f"--plot {path}: suffix {out.suffix!r}, expected .png, .pdf or .svg")
    # Frame the iterates and the stable fixed points; an unstable δ_4* near 1/w would squash them.
    finite = [p.delta_m for p in points if p.delta_m is not None and p.stable]
    finite += [r.delta_m for t in traces for r in t.rows]
    top = min(0.999 * smap.delta_limit_m, 1.5 * max([*finite, 1e-3 * smap.delta_limit_m]))
    grid = np.linspace(0.0, top, 600)
    values = np.array([smap(float(d), spectrum) for d in grid])
    fig, ax = plt.subplots(figsize=(6.4, 5.2))
    ax.plot(grid, np.where(values <= 1.2 * top, values, np.nan), color="k", label="f(δ)")
    ax.plot([0, top], [0, top], color="0.6", lw=0.8, label="δ = f(δ)")
    for trace in traces:
        xs, ys = [trace.rows[0].delta_m], [0.0]
        for a, b in zip(trace.rows[:-1], trace.rows[1:], strict=True):
            xs += [a.delta_m, b.delta_m]
            ys += [b.delta_m, b.delta_m]
        ax.plot(xs, ys, lw=0.8, label=f"iteration from {trace.rows[0].delta_m:.3g} m")
    for p in points:
        if p.delta_m is not None and p.on_branch and p.delta_m <= top:
            ax.plot(p.delta_m, p.delta_m, "o", mfc="k" if p.stable else "w", mec="k")
    ax.set_xlim(0, top)
    ax.set_ylim(0, 1.2 * top)
    ax.set_xlabel(r"$\delta_i$ [m]")
    ax.set_ylabel(r"$\delta_{i+1}$ [m]")
    ax.set_title("Design iteration (filled: stable fixed point, open: unstable)")
    ax.legend(loc="upper left", fontsize=8)
    fig.tight_layout()
    tmp = out.with_name(f".{out.name}.tmp{out.suffix}")
    try:
        fig.savefig(tmp, dpi=120)
        os.replace(tmp, out)  # nothing half-written: temporary name, then rename
    finally:
        plt.close(fig)
        tmp.unlink(missing_ok=True)
