"""The stated ranking intensity: the scale at which every candidate is simulated and compared.

Two kinds (docs/selection.md, "The ranking intensity"):

- ``as-used`` (the default): each record at the scale it will be used at, its scale factor by
  the scaling policy (``scale = "none"``: as recorded);
- ``equal-psa-t1``: every record scaled to a common PSA at T_1, given either as an onset ratio
  r (``rank_onset_ratio``: P_1·SD(T_1, ξ_1)·s = r·x_c, the linear frame's peak at r times the
  onset of stepping; PSA(T_1, ξ_1) = r·ω_1²x_c/P_1) or in g (``rank_psa_t1_g``: PSA(T_1) at 5 %
  damping, the engineer's convention).

The ranking then simulates every candidate at a short ladder of factors around that scale
(:data:`stepframe.pipeline.selection.exact.LADDER`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from stepframe.errors import InputError
from stepframe.pipeline.selection.names import SIMULATED_RESPONSE
from stepframe.records.units import STANDARD_GRAVITY_M_S2

Floats = NDArray[np.float64]


@dataclass(frozen=True)
class RankingIntensity:
    """The intensity a selection ranks at (written as ``ranking_intensity`` in selection.json).

    Attributes
    ----------
    kind
        ``"as-used"`` or ``"equal-psa-t1"``.
    scale
        The scaling policy (``as-used``: the records at its scale factors).
    onset_ratio
        ``equal-psa-t1`` given as an onset ratio (else None).
    psa_t1_g
        ``equal-psa-t1`` given as PSA(T_1) at 5 % damping [g] (else None).
    onset_psa_t1_g
        The frame's onset of stepping as PSA(T_1, ξ_1) = ω_1²x_c/P_1 [g].
    ladder
        Factors on each record's scale at which it is simulated (empty when the ranking is a
        tier: it simulates nothing, it reads each record at its scale).
    """

    kind: str
    scale: str
    onset_ratio: float | None
    psa_t1_g: float | None
    onset_psa_t1_g: float
    ladder: tuple[float, ...]

    def describe(self) -> str:
        """One line for people (the summary, the report): the level, then the ladder after
        "; " when the ranking simulates (:func:`intensity_level` reads the level back)."""
        if self.kind == "as-used":
            how = "as recorded" if self.scale == "none" else f"at their {self.scale} scale factors"
            level = f"the records as they will be used ({how})"
        elif self.onset_ratio is not None:
            level = (
                f"every record at equal {equal_psa_level(self.onset_ratio, self.onset_psa_t1_g)}"
            )
        else:
            assert self.psa_t1_g is not None
            level = (
                f"every record at equal PSA(T_1) = {self.psa_t1_g:.3g} g (5 % damping), "
                f"{self.psa_t1_g / self.onset_psa_t1_g:.3g} × the onset of stepping"
            )
        if not self.ladder:
            return level
        first, last = self.ladder[0], self.ladder[-1]
        return f"{level}; ladder ×{first:g} to ×{last:g} ({len(self.ladder)} levels)"

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready, with ``text`` (:meth:`describe`)."""
        return {
            "kind": self.kind,
            "scale": self.scale,
            "onset_ratio": self.onset_ratio,
            "psa_t1_g": self.psa_t1_g,
            "onset_psa_t1_g": self.onset_psa_t1_g,
            "ladder": list(self.ladder),
            "text": self.describe(),
        }

    def base_scales(
        self, frame: Any, sd_t1_xi1_m: Floats, psa_t1_g: Floats, scale_factor: Floats
    ) -> Floats:
        """Each record's scale at this intensity.

        Parameters
        ----------
        frame
            The frame (ω_1, P_1, x_c).
        sd_t1_xi1_m
            SD(T_1, ξ_1) of each record, unscaled [m].
        psa_t1_g
            PSA(T_1) at 5 % damping, unscaled [g].
        scale_factor
            The scaling policy's factors.
        """
        with np.errstate(divide="ignore", invalid="ignore"):
            if self.kind == "as-used":
                return np.asarray(scale_factor, dtype=np.float64)
            if self.onset_ratio is not None:
                return equal_intensity_scales(sd_t1_xi1_m, frame, self.onset_ratio)
            assert self.psa_t1_g is not None
            return np.asarray(self.psa_t1_g / np.asarray(psa_t1_g), dtype=np.float64)


def equal_intensity_scales(sd_t1_m: Floats, frame: Any, onset_ratio: float) -> Floats:
    """Scale factors s giving P_1·SD(T_1, ξ_1)·s = ``onset_ratio``·x_c for each record: the
    linear frame's peak at ``onset_ratio`` times the onset of stepping (the ranking's and the
    confirmation's equal intensity; a record with SD = 0 gets an infinite scale).

    Parameters
    ----------
    sd_t1_m
        SD(T_1, ξ_1) of each record, unscaled [m].
    frame
        The frame (P_1, x_c).
    onset_ratio
        The multiple of the onset of stepping [-].
    """
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.asarray(
            onset_ratio * frame.x_c_m / (frame.p_1 * np.asarray(sd_t1_m, dtype=np.float64)),
            dtype=np.float64,
        )


def equal_psa_level(onset_ratio: float, onset_psa_t1_g: float) -> str:
    """An equal intensity given as a multiple of the onset of stepping, for people: "PSA(T_1) =
    0.681 g, 1 × the onset of stepping" (the ranking's, :meth:`RankingIntensity.describe`, and
    the confirmation's).

    Parameters
    ----------
    onset_ratio
        The linear frame's peak P_1·SD(T_1, ξ_1) over x_c [-].
    onset_psa_t1_g
        PSA(T_1, ξ_1) at the onset (:func:`onset_psa_t1_g`) [g].
    """
    return (
        f"PSA(T_1) = {onset_ratio * onset_psa_t1_g:.3g} g, {onset_ratio:g} × the onset of stepping"
    )


def intensity_level(text: str) -> str:
    """The level of :meth:`RankingIntensity.describe`'s text without its ladder (a selection
    folder keeps the intensity's text; the summary's response line names its intensity by it)."""
    return text.split("; ladder")[0]


def onset_psa_t1_g(frame: Any) -> float:
    """PSA(T_1, ξ_1) at which the linear frame's peak P_1·SD reaches x_c [g]: the frame's static
    uplift acceleration ω_1²x_c/P_1 (:attr:`~stepframe.structure.frame.PortalFrame.
    uplift_acceleration_m_s2`) in g."""
    return float(frame.uplift_acceleration_m_s2 / STANDARD_GRAVITY_M_S2)


def ranking_intensity(options: Any, frame: Any, ladder: tuple[float, ...]) -> RankingIntensity:
    """The intensity the options state (module docstring), with the simulation's ``ladder``
    when the ranking is the simulated response (a tier reads each record once, at its scale)."""
    equal = options.rank_onset_ratio is not None or options.rank_psa_t1_g is not None
    kind = "equal-psa-t1" if equal else "as-used"
    return RankingIntensity(
        kind,
        options.scale,
        options.rank_onset_ratio,
        options.rank_psa_t1_g,
        onset_psa_t1_g(frame),
        ladder if options.rank_by == SIMULATED_RESPONSE else (),
    )


def check_target_covers(target: Any, period_1_s: float) -> None:
    """A tabulated target must cover T_1, where the ranking and the scaling read it (below its
    first period it is held, beyond its last it falls as 1/T²: neither is a given value)."""
    periods = getattr(target, "periods_s", None)
    if periods is None:
        return
    low, high = float(periods[0]), float(periods[-1])
    if not low <= period_1_s <= high:
        raise InputError(
            f"the target spectrum covers {low:g}-{high:g} s, expected it to cover T_1 = "
            f"{period_1_s:.4g} s (the frame's period, where the selection reads it)"
        )


def checked_target(options: Any, frame: Any) -> Any:
    """The options' target spectrum (:func:`stepframe.pipeline.selection.spectral.target_spectrum`,
    None without one), refused when it does not cover the frame's T_1 (:func:`check_target_covers`):
    read before any work."""
    import math

    from stepframe.pipeline.selection.spectral import target_spectrum

    target = target_spectrum(options)
    if target is not None:
        check_target_covers(target, 2.0 * math.pi / frame.omega_1_rad_s)
    return target
