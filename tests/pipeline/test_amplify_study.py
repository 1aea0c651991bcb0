"""pipeline.amplify_study: the routes of `stochastic amplify` (parameters, envelope-free)."""

from __future__ import annotations

import pytest

from stepframe.errors import InputError
from stepframe.pipeline.amplification.amplify import AmplificationResult, SpectralRatios
from stepframe.pipeline.amplification.study import AmplifyOptions, amplify_study

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
