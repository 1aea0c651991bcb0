"""``stepframe stochastic amplify``: moving-resonance amplification for a site and an oscillator.

The site is given by its Beck-Papadimitriou parameters or estimated from a record; the oscillator
by its small-amplitude frequency (tracking ω(t) = ω_0·ω_g(t)/ω_p) or by a frame file (ω(t) =
2π/T(A) from the frame's period-amplitude law, A = √2·σ_x). Prints the paper's spectral ratio
(eq. 6.18) and its two approximations (eq. 6.19) next to the response amplification computed by
the exact covariance method (optionally confirmed by Monte Carlo). Without ``--t-max-s`` and
``--t-dur-s`` under ``--alpha-at-tmax paper`` only eqs. 6.18-6.19 are computed (they do not
depend on the envelope's times; the response amplification does). The work is done by
:func:`stepframe.pipeline.amplify_study.amplify_study`; heavy imports happen in
:func:`run_amplify`.
"""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from stepframe.commands import (
    CommandResult,
    Once,
    add_command,
    add_record_options,
    check_plot,
    read_record_file,
    record_options,
    save_plot,
)
from stepframe.core.options import add_fields, add_options, fields_given
from stepframe.pipeline.amplify_study import AmplifyOptions
from stepframe.pipeline.site import SITE_PARAMETERS

#: The analysis options, after the site's and the oscillator's.
ANALYSIS = ("alpha_reading", "peak_intensity_m_s2", "monte_carlo", "seed", "n_steps")

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
    add_fields(site, AmplifyOptions, SITE_PARAMETERS)
    add_fields(site, AmplifyOptions, ["record"], action=Once)
    add_fields(site, AmplifyOptions, ["t0"])
    oscillator = parser.add_argument_group("oscillator (either --f0-hz or --frame)")
    add_fields(oscillator, AmplifyOptions, ["f0_hz", "frame", "xi0"])
    add_fields(parser, AmplifyOptions, ANALYSIS)
    add_options(parser, ("--plot", None, "OUT.png", "draw both amplifications, 0.1-10 Hz"))
    add_record_options(parser)


def run_amplify(args: argparse.Namespace) -> CommandResult:
    """Compute the amplifications and optionally draw them."""
    from stepframe.pipeline.amplify_study import amplify_study

    check_plot(args.plot)
    example = None
    if args.example is not None:  # the example catalogue as the site's record: one component
        example = (args.example, args.component, read_record_file(None, args))
    study = amplify_study(
        AmplifyOptions(**fields_given(args, AmplifyOptions)), record_options=record_options(args),
        example=example, figure=args.plot is not None,
    )  # fmt: skip
    result = CommandResult(study.to_dict(), study.describe())
    return save_plot(result, args.plot, study.figure, line=None)
