"""``stepframe stochastic amplify``: moving-resonance amplification for a site and an oscillator.

The site is given by its Beck-Papadimitriou parameters or estimated from a record; the oscillator
by its small-amplitude frequency (tracking ω(t) = ω_0·ω_g(t)/ω_p) or by a frame file (ω(t) =
2π/T(A) from the frame's period-amplitude law, A = √2·σ_x). Prints the paper's spectral ratio
(eq. 6.18) and its two approximations (eq. 6.19) next to the response amplification computed by
the exact covariance method (optionally confirmed by Monte Carlo). Heavy imports happen in
:func:`run_amplify`.
"""

from __future__ import annotations

import argparse
import math
import os
from pathlib import Path
from typing import Any

from stepframe.commands import (
    CommandResult,
    add_command,
    add_record_options,
    positive_float,
    read_record_file,
)
from stepframe.errors import InputError

EXAMPLES = """\
  # the paper's site (eq. 6.19: 5.67) and an oscillator at 3.12 Hz
  stepframe stochastic amplify --fp-hz 7.43 --fs-hz 3.12 --fr-hz 1.11 --xi-p 0.096 \\
      --xi-r 0.655 --t-max-s 5 --t-dur-s 20 --f0-hz 3.12 --alpha-at-tmax paper
  # the same, confirmed by 500 Monte Carlo motions, with the figure over 0.1-10 Hz
  stepframe stochastic amplify --fp-hz 7.43 --fs-hz 3.12 --fr-hz 1.11 --xi-p 0.096 \\
      --xi-r 0.655 --t-max-s 5 --t-dur-s 20 --f0-hz 2 --monte-carlo 500 --seed 1 --plot a.png
  # parameters estimated from a record, a frame file for ω(t) = 2π/T(A), JSON output
  stepframe stochastic amplify --record RSN8883.AT2 --frame frame.toml --json
"""

SITE_OPTIONS = ("fp_hz", "fs_hz", "fr_hz", "xi_p", "xi_r", "t_max_s", "t_dur_s")


def register(subparsers: Any) -> None:
    """Add ``amplify`` to the ``stochastic`` group."""
    parser = add_command(
        subparsers,
        "amplify",
        help="moving-resonance amplification: eqs. 6.18-6.19 and the response amplification",
        description=(
            "Spectral ratio of eq. 6.18 at f0, eq. 6.19's first and last approximations, and the "
            "response amplification (peak RMS with the moving frequency over the fixed "
            "oscillator and over the stationary RMS) by the exact covariance method."
        ),
        examples=EXAMPLES,
        run=run_amplify,
    )
    site = parser.add_argument_group("site (either the parameters or --record)")
    site.add_argument("--fp-hz", type=positive_float, metavar="F", help="P-wave dominant f_p [Hz]")
    site.add_argument("--fs-hz", type=positive_float, metavar="F", help="S-wave dominant f_s [Hz]")
    site.add_argument("--fr-hz", type=positive_float, metavar="F", help="surface-wave f_r [Hz]")
    site.add_argument("--xi-p", type=positive_float, metavar="X", help="bandwidth ratio ξ_p")
    site.add_argument("--xi-r", type=positive_float, metavar="X", help="bandwidth ratio ξ_r")
    site.add_argument("--t-max-s", type=positive_float, metavar="T", help="time of peak I_g [s]")
    site.add_argument("--t-dur-s", type=positive_float, metavar="T", help="strong duration [s]")
    site.add_argument("--record", metavar="FILE", help="estimate the site from this record")
    site.add_argument(
        "--t0",
        choices=("start", "p-pick"),
        default="start",
        help="with --record: time origin, record start (default) or picked P onset",
    )
    osc = parser.add_argument_group("oscillator (either --f0-hz or --frame)")
    osc.add_argument("--f0-hz", type=positive_float, metavar="F", help="small-amplitude f0 [Hz]")
    osc.add_argument("--frame", metavar="FRAME.toml", help="frame file: ω(t) = 2π/T(A)")
    osc.add_argument(
        "--xi0",
        type=float,
        default=None,
        metavar="X",
        help="damping ratio at f0 (fraction; default 0.05, or the frame's xi_1 with --frame)",
    )
    parser.add_argument(
        "--alpha-at-tmax",
        choices=("eq-6-11", "paper"),
        default="eq-6-11",
        help="α_g ramp ends at t_dur (eq. 6.11 as printed, default) or at t_max (the paper)",
    )
    parser.add_argument(
        "--peak-intensity-m-s2",
        type=positive_float,
        default=None,
        metavar="I",
        help="max I_g [m/s²] (default 1, or the record's); matters only with --frame",
    )
    parser.add_argument(
        "--monte-carlo", type=int, default=0, metavar="N", help="confirm with N synthetic motions"
    )
    parser.add_argument("--seed", type=int, default=None, help="seed of the Monte Carlo motions")
    parser.add_argument(
        "--n-steps", type=int, default=4000, metavar="N", help="time steps (default 4000)"
    )
    parser.add_argument("--plot", metavar="OUT.png", help="draw both amplifications, 0.1-10 Hz")
    add_record_options(parser)


def _site_model(args: argparse.Namespace) -> tuple[Any, float, dict[str, Any]]:
    """The ground-motion model, the peak intensity [m/s²] and a description of the source."""
    from stepframe.stochastic.model import GroundMotionModel

    given = [name for name in SITE_OPTIONS if getattr(args, name) is not None]
    if args.record is not None:
        if given:
            raise InputError(
                f"--record with --{given[0].replace('_', '-')}, expected either the site "
                "parameters or --record"
            )
        from stepframe.stochastic.features import record_features
        from stepframe.stochastic.fit import fit_model

        stream = read_record_file(args.record, args)
        if len(stream) != 1:
            raise InputError(
                f"{len(stream)} components in the file, expected one (choose it with --component)",
                args.record,
            )
        trace = stream[0]
        try:
            features = record_features(trace, t0=args.t0)
            fitted = fit_model(features, alpha_reading=args.alpha_at_tmax)
        except InputError as error:
            raise InputError(error.what, args.record) from None
        source = {"record": args.record, "component": trace.stats.channel}
        source["fit_quality"] = fitted.fit_quality
        source["flags"] = list(fitted.flags)
        return fitted.model, float(features.peak_intensity), source
    missing = [name for name in SITE_OPTIONS if getattr(args, name) is None]
    if missing:
        raise InputError(
            f"missing --{missing[0].replace('_', '-')}, expected all of "
            + ", ".join("--" + n.replace("_", "-") for n in SITE_OPTIONS)
            + " or --record FILE"
        )
    model = GroundMotionModel.from_hz(
        args.fp_hz,
        args.fs_hz,
        args.fr_hz,
        args.xi_p,
        args.xi_r,
        t_max_s=args.t_max_s,
        t_dur_s=args.t_dur_s,
        alpha_reading=args.alpha_at_tmax,
    )
    return model, 1.0, {"site": "parameters"}


def run_amplify(args: argparse.Namespace) -> CommandResult:
    """Compute the amplifications and optionally draw them."""
    import numpy as np

    from stepframe.stochastic.amplification import (
        approx_eq_6_19_first,
        approx_eq_6_19_last,
        response_amplification,
        spectral_ratio_eq_6_18,
    )
    from stepframe.stochastic.mean_square import FrameDriven, analysis_grid

    if (args.f0_hz is None) == (args.frame is None):
        raise InputError("expected exactly one of --f0-hz F and --frame FRAME.toml")
    if args.monte_carlo < 0 or args.monte_carlo == 1:
        raise InputError(f"--monte-carlo {args.monte_carlo}, expected 0 (none) or N ≥ 2")
    model, intensity, source = _site_model(args)
    if args.peak_intensity_m_s2 is not None:
        intensity = args.peak_intensity_m_s2
    grid = analysis_grid(model, n_steps=args.n_steps)
    frame_spec = None
    inputs: dict[str, Any] = {"ground_motion_model": model.to_dict(), **source}
    if args.frame is not None:
        from stepframe.structure.frame_file import read_frame_file
        from stepframe.structure.period_amplitude import period_amplitude

        frame = read_frame_file(args.frame)

        def period_s(amplitude_m: float) -> float:
            return float(period_amplitude(frame, amplitude_m, beyond_x_star="inf"))

        frame_spec = FrameDriven(period_s)
        xi0 = frame.xi_1 if args.xi0 is None else args.xi0
        # the frame's equation of motion takes -p_1 ẍ_g in its unstepped phase (eq. 4.11)
        intensity *= frame.p_1
        inputs |= {"frame": args.frame, "participation_p_1": frame.p_1}
        f0_hz = 1.0 / period_s(0.0)
    else:
        xi0 = 0.05 if args.xi0 is None else args.xi0
        f0_hz = args.f0_hz
    if not (math.isfinite(xi0) and xi0 > 0):
        raise InputError(f"--xi0 {xi0}, expected a damping fraction > 0 (e.g. 0.05)")
    omega_0 = 2 * math.pi * f0_hz
    covariance = response_amplification(
        model,
        None if frame_spec else [omega_0],
        xi0,
        frame=frame_spec,
        peak_intensity=intensity,
        time_s=grid,
    )
    data: dict[str, Any] = {
        "spectral_ratio_eq_6_18": float(spectral_ratio_eq_6_18(model, omega_0)),
        "approx_eq_6_19_first": approx_eq_6_19_first(model),
        "approx_eq_6_19_last": approx_eq_6_19_last(model),
        "response_amplification_vs_fixed": float(covariance.vs_fixed[0]),
        "response_amplification_vs_stationary": float(covariance.vs_stationary[0]),
        "peak_rms_moving_m": float(covariance.peak_rms_moving_m[0]),
        "peak_rms_fixed_m": float(covariance.peak_rms_fixed_m[0]),
        "stationary_rms_m": float(covariance.stationary_rms_m[0]),
        "omega_path": covariance.omega_path,
        "alpha_reading": model.alpha_reading,
        "method": "covariance",
        "status": covariance.moving.status,
        # a frame that overturns stops the run: its peak RMS so far is only a lower bound
        "lower_bound": covariance.moving.status != "ok",
        "f0_hz": f0_hz,
        "xi0": xi0,
        "peak_intensity_m_s2": intensity,
        "duration_s": float(grid[-1]),
        "n_steps": int(grid.size - 1),
        "inputs": inputs,
    }
    if args.monte_carlo:
        mc = response_amplification(
            model,
            None if frame_spec else [omega_0],
            xi0,
            frame=frame_spec,
            method="monte-carlo",
            peak_intensity=intensity,
            time_s=grid,
            n_realisations=args.monte_carlo,
            seed=args.seed,
        )
        assert mc.vs_fixed_band is not None and mc.vs_stationary_band is not None
        data["monte_carlo"] = {
            "n_realisations": args.monte_carlo,
            "seed": args.seed,
            "confidence": 0.95,
            "response_amplification_vs_fixed": float(mc.vs_fixed[0]),
            "response_amplification_vs_fixed_band": mc.vs_fixed_band[0].tolist(),
            "response_amplification_vs_stationary": float(mc.vs_stationary[0]),
            "response_amplification_vs_stationary_band": mc.vs_stationary_band[0].tolist(),
            "status": mc.moving.status,
        }
    if args.plot:
        frequencies = np.geomspace(0.1, 10.0, 60)
        curve = response_amplification(model, 2 * np.pi * frequencies, xi0, time_s=grid)
        _plot(Path(args.plot), model, frequencies, curve, data)
        data["plot"] = args.plot
    return CommandResult(data=data, text=_describe(data))


def _describe(data: dict[str, Any]) -> str:
    lines = [
        f"oscillator f0 = {data['f0_hz']:.4g} Hz, xi0 = {data['xi0']:.3g}, "
        f"omega path: {data['omega_path']}, alpha reading: {data['alpha_reading']}",
        f"  spectral ratio eq. 6.18 at f0          {data['spectral_ratio_eq_6_18']:.4g}",
        f"  eq. 6.19 first approximation           {data['approx_eq_6_19_first']:.4g}",
        f"  eq. 6.19 last approximation (ωp/ωs)²   {data['approx_eq_6_19_last']:.4g}",
        f"  response amplification vs fixed       {data['response_amplification_vs_fixed']:.4g}",
        "  response amplification vs stationary  "
        f"{data['response_amplification_vs_stationary']:.4g}",
    ]
    mc = data.get("monte_carlo")
    if mc:
        lo, hi = mc["response_amplification_vs_fixed_band"]
        lines.append(
            f"  Monte Carlo (N = {mc['n_realisations']}): vs fixed "
            f"{mc['response_amplification_vs_fixed']:.4g} [{lo:.4g}, {hi:.4g}] (95 %)"
        )
    if data["status"] != "ok":
        lines.append(f"  status: {data['status']}")
    return "\n".join(lines)


def _plot(target: Path, model: Any, frequencies: Any, curve: Any, data: dict[str, Any]) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    from stepframe.stochastic.amplification import spectral_ratio_eq_6_18

    ratio = spectral_ratio_eq_6_18(model, 2 * np.pi * frequencies)
    fig, ax = plt.subplots(figsize=(7, 4.5), constrained_layout=True)
    ax.loglog(frequencies, ratio, color="C0", label="spectral ratio, eq. 6.18")
    ax.loglog(frequencies, curve.vs_fixed, color="C3", label="response amplification vs fixed")
    ax.loglog(
        frequencies,
        curve.vs_stationary,
        color="C3",
        ls="--",
        label="response amplification vs stationary",
    )
    ax.axhline(data["approx_eq_6_19_last"], color="0.5", ls=":", label="(ω_p/ω_s)², eq. 6.19")
    ax.plot(
        [data["f0_hz"]],
        [data["response_amplification_vs_fixed"]],
        "o",
        color="k",
        label=f"f0 = {data['f0_hz']:.3g} Hz ({data['omega_path']})",
    )
    ax.set_xlabel("small-amplitude oscillator frequency f0 [Hz]")
    ax.set_ylabel("amplification [-]")
    ax.set_title(
        f"tracking ω(t) = ω0·ω_g(t)/ω_p, ξ0 = {data['xi0']:.3g}, α reading {data['alpha_reading']}"
    )
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=8)
    tmp = target.with_name(f".{target.stem}.{os.getpid()}.tmp{target.suffix}")
    try:
        fig.savefig(tmp, dpi=110, format=target.suffix.lstrip(".") or "png")
        os.replace(tmp, target)
    finally:
        plt.close(fig)
        tmp.unlink(missing_ok=True)
