"""``stepframe stochastic amplify``: moving-resonance amplification for a site and an oscillator.

The site is given by its Beck-Papadimitriou parameters or estimated from a record; the oscillator
by its small-amplitude frequency (tracking ω(t) = ω_0·ω_g(t)/ω_p) or by a frame file (ω(t) =
2π/T(A) from the frame's period-amplitude law, A = √2·σ_x). Prints the paper's spectral ratio
(eq. 6.18) and its two approximations (eq. 6.19) next to the response amplification computed by
the exact covariance method (optionally confirmed by Monte Carlo). The work is done by
:mod:`stepframe.pipeline.amplification`; heavy imports happen in :func:`run_amplify`.
"""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from stepframe.commands import (
    CommandResult,
    add_command,
    add_record_options,
    add_t0_option,
    positive_float,
    record_options,
)
from stepframe.errors import InputError

if TYPE_CHECKING:
    from stepframe.commands import Subparsers

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


def register(subparsers: Subparsers) -> None:
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
    add_t0_option(site, "with --record: time origin, record start (default) or picked P onset")
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
            curve, f0_hz=result.f0_hz, at_f0=result.response_amplification_vs_fixed
        )
        save_figure(figure, args.plot, dpi=110)
        data["plot"] = args.plot
    return CommandResult(data=data, text=result.describe())
