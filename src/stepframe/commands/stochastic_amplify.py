"""``stepframe stochastic amplify``: moving-resonance amplification for a site and an oscillator.

The site is given by its Beck-Papadimitriou parameters or estimated from a record; the oscillator
by its small-amplitude frequency (tracking ω(t) = ω_0·ω_g(t)/ω_p) or by a frame file (ω(t) =
2π/T(A) from the frame's period-amplitude law, A = √2·σ_x). Prints the paper's spectral ratio
(eq. 6.18) and its two approximations (eq. 6.19) next to the response amplification computed by
the exact covariance method (optionally confirmed by Monte Carlo). Without ``--t-max-s`` and
``--t-dur-s`` under ``--alpha-at-tmax paper`` only eqs. 6.18-6.19 are computed (they do not
depend on the envelope's times; the response amplification does). The work is done by
:mod:`stepframe.pipeline.amplification`; heavy imports happen in :func:`run_amplify`.
"""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from stepframe.commands import (
    CommandResult,
    Once,
    add_command,
    add_record_options,
    add_t0_option,
    positive_float,
    read_record_file,
    record_options,
)
from stepframe.errors import InputError

if TYPE_CHECKING:
    from stepframe.commands import Subparsers

EXAMPLES = """\
  # the paper's site (eq. 6.19: 5.67) and an oscillator at 3.12 Hz
  stepframe stochastic amplify --fp-hz 7.43 --fs-hz 3.12 --fr-hz 1.11 --xi-p 0.096 \\
      --xi-r 0.655 --t-max-s 5 --t-dur-s 20 --f0-hz 3.12 --alpha-at-tmax paper
  # eqs. 6.18-6.19 alone: with the paper's α_g(t_max) = ω_r ξ_r they need no envelope times
  stepframe stochastic amplify --fp-hz 7.43 --fs-hz 3.12 --fr-hz 1.11 --xi-p 0.096 \\
      --xi-r 0.655 --f0-hz 3.12 --alpha-at-tmax paper
  # with the envelope, confirmed by 500 Monte Carlo motions, the figure over 0.1-10 Hz
  stepframe stochastic amplify --fp-hz 7.43 --fs-hz 3.12 --fr-hz 1.11 --xi-p 0.096 \\
      --xi-r 0.655 --t-max-s 5 --t-dur-s 20 --f0-hz 2 --monte-carlo 500 --seed 1 --plot a.png
  # parameters estimated from a record, a frame file for ω(t) = 2π/T(A), JSON output
  stepframe stochastic amplify --record RSN8883_14383980_13849360.AT2 --frame frame.toml --json
  # the site from a component of the embedded example catalogue
  stepframe stochastic amplify --example fema-p695 --component MUL009 --f0-hz 2
"""


def register(subparsers: Subparsers) -> None:
    """Add ``amplify`` to the ``stochastic`` group."""
    parser = add_command(
        subparsers,
        "amplify",
        help="moving-resonance amplification: eqs. 6.18-6.19 and the response amplification",
        description=(
            "Spectral ratio of eq. 6.18 at f0, eq. 6.19's first and last approximations, and the "
            "response amplification (peak RMS with the moving frequency over the fixed "
            "oscillator and over the stationary RMS) by the exact covariance method. With "
            "--alpha-at-tmax paper, eqs. 6.18-6.19 need no envelope times: without --t-max-s "
            "and --t-dur-s only they are computed (the response amplification is then null)."
        ),
        examples=EXAMPLES,
        run=run_amplify,
    )
    site = parser.add_argument_group("site (either the parameters or --record)")
    site.add_argument(
        "--fp-hz",
        type=positive_float,
        metavar="F",
        help="P-wave dominant f_p [Hz] (omega_p_rad_s/2π; `stochastic fit` prints both)",
    )
    site.add_argument("--fs-hz", type=positive_float, metavar="F", help="S-wave dominant f_s [Hz]")
    site.add_argument("--fr-hz", type=positive_float, metavar="F", help="surface-wave f_r [Hz]")
    site.add_argument("--xi-p", type=positive_float, metavar="X", help="bandwidth ratio ξ_p")
    site.add_argument("--xi-r", type=positive_float, metavar="X", help="bandwidth ratio ξ_r")
    site.add_argument(
        "--t-max-s",
        type=positive_float,
        metavar="T",
        help="time of peak I_g [s] (`stochastic fit` prints t_max_s; the paper's site: 5); "
        "not needed for eqs. 6.18-6.19 alone with --alpha-at-tmax paper",
    )
    site.add_argument(
        "--t-dur-s",
        type=positive_float,
        metavar="T",
        help="strong duration [s] (`stochastic fit` prints t_dur_s; the paper's site: 20)",
    )
    site.add_argument(
        "--record", action=Once, metavar="FILE", help="estimate the site from this record (one)"
    )
    add_t0_option(
        site,
        "with --record: time origin, auto (default: reliable P pick, else record start), "
        "start or p-pick",
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


def run_amplify(args: argparse.Namespace) -> CommandResult:
    """Compute the amplifications and optionally draw them."""
    from stepframe.pipeline import amplification as stage
    from stepframe.pipeline.site import SITE_PARAMETERS, site_from_options

    if (args.f0_hz is None) == (args.frame is None):
        raise InputError("expected exactly one of --f0-hz F and --frame FRAME.toml")
    if args.plot:
        from stepframe.pipeline.figures import check_figure_path

        check_figure_path(args.plot)
    if args.example is not None:
        # The example catalogue as the site's record: one component, as with --record.
        from stepframe.pipeline.site import site_from_record

        given = [name for name in SITE_PARAMETERS if getattr(args, name) is not None]
        if given or args.record is not None:
            raise InputError(
                f"--example with {'--record' if args.record else '--' + given[0].replace('_', '-')}"
                ", expected the site from one of the parameters, --record or --example"
            )
        stream = read_record_file(None, args)
        if len(stream) != 1:
            raise InputError(
                f"--example {args.example}: {len(stream)} components, expected one "
                "(pick it with --component, such as MUL009)"
            )
        site = site_from_record(
            stream[0], t0=args.t0, alpha_reading=args.alpha_at_tmax,
            name=f"example {args.example} {args.component}",
        )  # fmt: skip
    elif _envelope_free(args):
        return _run_envelope_free(args)
    else:
        site = site_from_options(
            {name: getattr(args, name) for name in SITE_PARAMETERS},
            record=args.record,
            record_options=record_options(args),
            t0=args.t0,
            alpha_reading=args.alpha_at_tmax,
        )
    if args.frame is not None:
        from stepframe.structure.frame_file import read_frame_file

        oscillator = stage.frame_oscillator(read_frame_file(args.frame), args.xi0, args.frame)
    else:
        oscillator = stage.tracking_oscillator(args.f0_hz, args.xi0)
    result = stage.amplify(
        site,
        oscillator,
        peak_intensity_m_s2=args.peak_intensity_m_s2,
        n_steps=args.n_steps,
        monte_carlo=args.monte_carlo,
        seed=args.seed,
    )
    data = result.to_dict()
    if args.plot:
        import numpy as np

        from stepframe.pipeline.figures import save_figure
        from stepframe.stochastic.plots import amplification_figure

        curve = stage.amplification_curve(
            site, np.geomspace(0.1, 10.0, 60), oscillator.xi0, n_steps=args.n_steps
        )
        figure = amplification_figure(
            curve,
            f0_hz=result.f0_hz,
            at_f0=result.response_amplification_vs_fixed,
            lower_bound=result.lower_bound,
            site=str(site.source.get("record") or "site from parameters"),
        )
        save_figure(figure, args.plot, dpi=110)
        data["plot"] = args.plot
    return CommandResult(data=data, text=result.describe())


#: The site parameters that are the envelope's times.
_TIMES = ("t_max_s", "t_dur_s")


def _envelope_free(args: argparse.Namespace) -> bool:
    """Whether the site is given by its parameters without both envelope times (none given).

    Under the paper's reading that is the envelope-free route; under eq. 6.11's it is an
    error saying why (α_g(t_max) then depends on t_max/t_dur) and what to give.
    """
    from stepframe.pipeline.site import SITE_PARAMETERS

    if args.record is not None or any(getattr(args, name) is not None for name in _TIMES):
        return False
    if not all(getattr(args, name) is not None for name in SITE_PARAMETERS if name not in _TIMES):
        return False  # site_from_options names the first one missing
    if args.alpha_at_tmax != "paper":
        raise InputError(
            f"no --t-max-s and --t-dur-s with --alpha-at-tmax {args.alpha_at_tmax}, expected "
            "both (eq. 6.18's α_g(t_max) then depends on t_max/t_dur; `stepframe stochastic "
            "fit` prints t_max_s and t_dur_s of a record of the site, the paper's site has 5 "
            "and 20 s), or --alpha-at-tmax paper for eqs. 6.18-6.19 alone"
        )
    for option, given in (("--monte-carlo", args.monte_carlo), ("--plot", args.plot)):
        if given:
            raise InputError(
                f"{option} without --t-max-s and --t-dur-s, expected both times (the response "
                "amplification needs the envelope; `stepframe stochastic fit` prints t_max_s and "
                "t_dur_s of a record of the site, the paper's site has 5 and 20 s)"
            )
    return True


def _run_envelope_free(args: argparse.Namespace) -> CommandResult:
    """Eqs. 6.18-6.19 without the envelope: the response amplification keys are null."""
    from stepframe.pipeline import amplification as stage

    if args.frame is not None:
        from stepframe.structure.frame_file import read_frame_file

        oscillator = stage.frame_oscillator(read_frame_file(args.frame), args.xi0, args.frame)
    else:
        oscillator = stage.tracking_oscillator(args.f0_hz, args.xi0)
    result = stage.spectral_ratios(
        args.fp_hz, args.fs_hz, args.fr_hz, args.xi_p, args.xi_r, oscillator,
        peak_intensity_m_s2=args.peak_intensity_m_s2,
    )  # fmt: skip
    return CommandResult(data=result.to_dict(), text=result.describe())
