"""pipeline.amplify_study: the routes of `stochastic amplify` (parameters, envelope-free)."""

from __future__ import annotations

from pathlib import Path

import pytest

from stepframe.errors import InputError
from stepframe.pipeline.amplification.amplify import AmplificationResult, SpectralRatios
from stepframe.pipeline.amplification.study import AmplifyOptions, amplify_study

DATA = Path(__file__).parents[1] / "data"
PAPER_SITE = {"fp_hz": 7.43, "fs_hz": 3.12, "fr_hz": 1.11, "xi_p": 0.096, "xi_r": 0.655}
TIMES = {"t_max_s": 5.0, "t_dur_s": 20.0}


def test_envelope_free_route_gives_the_full_routes_spectral_ratios() -> None:
    free = amplify_study(AmplifyOptions(**PAPER_SITE, f0_hz=3.12, alpha_reading="paper"))
    full = amplify_study(
        AmplifyOptions(**PAPER_SITE, **TIMES, f0_hz=3.12, alpha_reading="paper", n_steps=400)
    )
    assert isinstance(free.result, SpectralRatios) and free.site is None
    assert isinstance(full.result, AmplificationResult) and full.site is not None
    # eq. 6.19's last approximation is (ω_p/ω_s)² = (7.43/3.12)² whatever the route.
    assert free.result.approx_eq_6_19_last == pytest.approx((7.43 / 3.12) ** 2, rel=1e-12)
    for name in ("spectral_ratio_eq_6_18", "approx_eq_6_19_first", "approx_eq_6_19_last"):
        assert getattr(free.result, name) == pytest.approx(getattr(full.result, name), rel=1e-12)
    assert "response_amplification_vs_fixed" not in free.to_dict()
    assert full.to_dict()["response_amplification_vs_fixed"] > 1.0


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"f0_hz": 2.0, "frame": "f.toml"}, "expected exactly one of --f0-hz F and --frame"),
        ({"f0_hz": 2.0}, "no --t-max-s and --t-dur-s with --alpha-at-tmax eq-6-11"),
        ({"f0_hz": 2.0, "alpha_reading": "paper", "monte_carlo": 5}, "--monte-carlo without"),
        ({"f0_hz": 2.0, "record": "r.AT2"}, "--record with --fp-hz"),
    ],
)
def test_mixed_or_incomplete_inputs_are_one_error(kwargs: dict[str, object], message: str) -> None:
    with pytest.raises(InputError, match=message.replace("(", r"\(")):
        amplify_study(AmplifyOptions(**PAPER_SITE, **kwargs))  # type: ignore[arg-type]
    with pytest.raises(InputError, match="--plot without --t-max-s"):
        amplify_study(AmplifyOptions(**PAPER_SITE, f0_hz=2.0, alpha_reading="paper"), figure=True)


def test_a_frame_says_whether_it_stepped_and_from_which_intensity(tmp_path: Path) -> None:
    """The frame-driven run's amplitude √2·σ_x against x_c decides whether ω(t) moved at all:
    below the stated onset intensity the frame stays linear (amplification 1 by construction),
    just above it the run steps (its amplification differs from 1)."""
    from stepframe.structure.frame_file import frame_template

    frame_file = tmp_path / "f.toml"
    frame_file.write_text(frame_template())

    def run(intensity: float) -> AmplificationResult:
        options = AmplifyOptions(
            **PAPER_SITE, **TIMES, frame=str(frame_file), peak_intensity_m_s2=intensity,
            n_steps=400,
        )  # fmt: skip
        result = amplify_study(options).result
        assert isinstance(result, AmplificationResult) and result.frame_stepping is not None
        return result

    quiet = run(1.0)
    stepping = quiet.frame_stepping
    assert stepping is not None and not stepping.stepped
    assert quiet.response_amplification_vs_fixed == 1.0
    # The linear response is proportional to the intensity: √2·σ_x reaches x_c at the onset.
    assert stepping.peak_amplitude_m == pytest.approx(2**0.5 * quiet.peak_rms_fixed_m, rel=1e-12)
    onset = stepping.onset_intensity_m_s2
    assert onset == pytest.approx(stepping.x_c_m / stepping.peak_amplitude_m, rel=1e-12)
    assert "did not step" in quiet.describe() and f"{onset:.3g} m/s²" in quiet.describe()
    below, above = run(0.99 * onset), run(1.01 * onset)
    assert below.frame_stepping is not None and not below.frame_stepping.stepped
    assert above.frame_stepping is not None and above.frame_stepping.stepped
    assert above.response_amplification_vs_fixed != 1.0
    assert above.to_dict()["frame_stepping"]["stepped"] is True
    # The figure's curves are tracking oscillators; its point is the frame's own run, so named.
    options = AmplifyOptions(
        **PAPER_SITE, **TIMES, frame=str(frame_file), n_steps=400, n_frequencies=5
    )  # fmt: skip
    legend = amplify_study(options, figure=True).figure().axes[0].get_legend()
    labels = [text.get_text() for text in legend.get_texts()]
    assert any(label.startswith("frame-driven ω(t) = 2π/T(A), f_1 = ") for label in labels)


def test_an_implausible_fit_is_degraded_and_says_why() -> None:
    """The ESM record's fit stops at its bounds (ω_p = ω_r: ω_g(t) does not fall), so eq. 6.19's
    (ω_p/ω_s)² is 1 by construction: the result is not the site's and must not read "ok"."""
    from stepframe.stochastic.flags import implausible

    record = DATA / "formats" / "esm" / "HI.ARS1..HNE.D.20190728.160908.C.ACC.ASC.gz"
    study = amplify_study(AmplifyOptions(record=str(record), f0_hz=2.0, n_steps=400))
    result = study.result
    assert isinstance(result, AmplificationResult)
    flags = implausible(result.inputs["flags"])
    assert "omega_not_decreasing" in flags
    model = result.inputs["ground_motion_model"]
    assert model["omega_p_rad_s"] == pytest.approx(model["omega_r_rad_s"], rel=1e-3)
    assert result.status == "degraded" and not result.lower_bound
    assert all(flag in result.message for flag in flags)
    assert "status: degraded" in result.describe() and "not plausible" in result.describe()
    # A plausible fit (RSN 8883) stays "ok".
    good = DATA / "peer_nga_west2" / "RSN8883_14383980_13849090.AT2"
    plain = amplify_study(AmplifyOptions(record=str(good), f0_hz=2.0, n_steps=400)).result
    assert isinstance(plain, AmplificationResult)
    assert implausible(plain.inputs["flags"]) == [] and plain.status == "ok"


def test_an_implausible_fit_is_explained_by_its_own_flags() -> None:
    # A clipped record's fit said its parameters were "where the search stopped", which is the
    # reason of a bound, not of clipping: each flag's meaning is given instead.
    from types import SimpleNamespace

    from stepframe.pipeline.amplification.amplify import _implausible_fit
    from stepframe.stochastic.flags import meaning

    site = SimpleNamespace(source={"flags": ["record_clipped"], "record": "a.AT2"})
    message = _implausible_fit(site)  # type: ignore[arg-type]
    assert message.startswith("the fit to a.AT2 is not plausible (record_clipped: ")
    assert meaning("record_clipped") in message and "search stopped" not in message


def test_the_monte_carlo_check_is_drawn_where_it_is_printed() -> None:
    # --monte-carlo N --plot printed the check and drew nothing of it: it is now a point with
    # its 95 % interval at f0, the numbers of the result's monte_carlo.
    options = AmplifyOptions(
        **PAPER_SITE, **TIMES, f0_hz=3.12, alpha_reading="paper", n_steps=400,
        n_frequencies=5, monte_carlo=20, seed=3,
    )  # fmt: skip
    study = amplify_study(options, figure=True)
    check = study.result.monte_carlo  # type: ignore[union-attr]
    assert check is not None
    axes = study.figure().axes[0]
    labels = [text.get_text() for text in axes.get_legend().get_texts()]
    drawn = [label for label in labels if label.startswith("Monte Carlo check, N = 20 motions")]
    assert drawn == [
        f"Monte Carlo check, N = 20 motions: {check.response_amplification_vs_fixed:.3g} "
        "(95 % interval)"
    ]
    (bars,) = axes.containers
    low, high = check.response_amplification_vs_fixed_band
    segment = bars.lines[2][0].get_segments()[0]
    assert segment[0][0] == pytest.approx(3.12) and (segment[0][1], segment[1][1]) == (
        pytest.approx(low),
        pytest.approx(high),
    )
