"""The standard intensity measures an engineer would rank by instead: the selection's peers.

Each is computed per candidate from the record as recorded (unscaled) and compared with the
frame's simulated response on the same runs (docs/selection.md, "The peers"):

- ``sa_t1_g``: S_a(T_1), PSA at the frame's small-amplitude period, 5 % damping [g];
- ``sa_avg_g``: Sa_avg, the geometric mean of S_a at :data:`N_AVERAGE` periods equally spaced
  over [0.2 T_1, 3 T_1] (Eads, Miranda and Lignos 2015, "Average spectral acceleration as an
  intensity measure for collapse risk assessment", Earthquake Eng. Struct. Dyn.
  44(12):2057-2073) [g];
- ``sa_ratio``: SaRatio = S_a(T_1)/Sa_avg(0.2 T_1, 3 T_1) (Eads, Miranda and Lignos 2016,
  "Spectral shape metrics and structural collapse potential", Earthquake Eng. Struct. Dyn.
  45(10):1643-1659); a *lower* SaRatio means more of the spectrum away from T_1, the more
  damaging shape for a softening structure at equal S_a(T_1);
- ``n_p_2t1`` and ``n_p_band``: N_p = Sa_avg(T_1 … T_N)/S_a(T_1) with T_N = 2 T_1 and
  T_N = T(A_max), the frame's period at the band's bottom (at most :data:`LONGEST_PERIOD_S`)
  (Bojórquez and Iervolino 2011, "Spectral shape proxies and nonlinear structural response",
  Soil Dyn. Earthquake Eng. 31(7):996-1008);
- ``fiv3_m_s``: FIV3, the filtered incremental velocity (Dávalos and Miranda 2019, "Filtered
  incremental velocity: a novel approach in intensity measures for seismic collapse estimation",
  Earthquake Eng. Struct. Dyn. 48(12):1384-1405): the acceleration low-passed by a causal
  second-order Butterworth filter at f_c = β/T_1 (β = 0.85), integrated over sliding windows of
  length αT_1 (α = 0.7); FIV3 = max(V_p1 + V_p2 + V_p3, |V_s1 + V_s2 + V_s3|), the three largest
  local maxima and the three lowest local minima of that window integral [m/s];
- ``sa_1_5t1_ratio``: S_a(1.5 T_1)/S_a(T_1), a one-period spectral-shape measure;
- ``pgv_pga_s`` and ``pgv_sa_t1_s``: PGV/PGA and PGV/S_a(T_1), the rocking literature's
  measures of a record's long-period (pulse) content (e.g. Makris and Konstantinidis 2003,
  "The rocking spectrum and the limitations of practical design methodologies", Earthquake Eng.
  Struct. Dyn. 32(2):265-289) [s].

Every measure scales with the record as ``value · s^exponent`` (:data:`PEERS`: 1 for S_a, Sa_avg
and FIV3, 0 for the ratios), so the value at any intensity follows from the unscaled one; its
``direction`` says which way is more severe (+1: larger is more severe).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from stepframe.records.units import STANDARD_GRAVITY_M_S2

Floats = NDArray[np.float64]

#: Periods in each average (Sa_avg, N_p), equally spaced between the range's ends.
N_AVERAGE = 10
#: Longest period of N_p over the band [s]: recorded motions carry little beyond it.
LONGEST_PERIOD_S = 10.0
#: FIV3's window αT_1 and cut-off β/T_1 (Dávalos and Miranda 2019's recommended values).
FIV_ALPHA = 0.7
FIV_BETA = 0.85


@dataclass(frozen=True)
class Peer:
    """One standard intensity measure: unit, meaning, source, and how it ranks and scales."""

    unit: str
    meaning: str
    direction: int
    exponent: int


#: The peers by column name (candidates.csv), in the order the tables show them.
PEERS: dict[str, Peer] = {
    "sa_t1_g": Peer("g", "S_a(T_1), 5 % damping", 1, 1),
    "sa_avg_g": Peer(
        "g", "Sa_avg: geometric mean of S_a over [0.2 T_1, 3 T_1] (Eads et al. 2015)", 1, 1
    ),
    "sa_ratio": Peer(
        "",
        "SaRatio = S_a(T_1)/Sa_avg(0.2 T_1, 3 T_1) (Eads et al. 2016); lower is more severe",
        -1,
        0,
    ),
    "n_p_2t1": Peer("", "N_p = Sa_avg(T_1..2 T_1)/S_a(T_1) (Bojórquez and Iervolino 2011)", 1, 0),
    "n_p_band": Peer(
        "", "N_p over the band: Sa_avg(T_1..T(A_max))/S_a(T_1), T(A_max) ≤ 10 s", 1, 0
    ),
    "fiv3_m_s": Peer("m/s", "FIV3, filtered incremental velocity (Dávalos and Miranda 2019)", 1, 1),
    "sa_1_5t1_ratio": Peer("", "S_a(1.5 T_1)/S_a(T_1)", 1, 0),
    "pgv_pga_s": Peer("s", "PGV/PGA", 1, 0),
    "pgv_sa_t1_s": Peer("s", "PGV/S_a(T_1)", 1, 0),
}


@dataclass(frozen=True)
class PeerPeriods:
    """The periods [s] whose 5 %-damped S_a the peers read, one array for one spectrum call."""

    period_1_s: float
    band_end_s: float

    @property
    def average(self) -> Floats:
        """[0.2 T_1, 3 T_1], :data:`N_AVERAGE` periods."""
        return np.linspace(0.2 * self.period_1_s, 3.0 * self.period_1_s, N_AVERAGE)

    @property
    def twice(self) -> Floats:
        """[T_1, 2 T_1]."""
        return np.linspace(self.period_1_s, 2.0 * self.period_1_s, N_AVERAGE)

    @property
    def band(self) -> Floats:
        """[T_1, min(T(A_max), 10 s)] (at least 1.5 T_1)."""
        end = max(min(self.band_end_s, LONGEST_PERIOD_S), 1.5 * self.period_1_s)
        return np.linspace(self.period_1_s, end, N_AVERAGE)

    @property
    def all(self) -> Floats:
        """T_1, 1.5 T_1, then the three ranges (the order :func:`peer_values` reads)."""
        head = np.array([self.period_1_s, 1.5 * self.period_1_s])
        return np.concatenate([head, self.average, self.twice, self.band])


def fiv3_m_s(acc_m_s2: Floats, dt_s: float, period_s: float) -> float:
    """FIV3 of one record for a structure of period ``period_s`` [m/s] (module docstring).

    The window integral of the filtered acceleration is exact for a record linear between
    samples (a cumulative trapezoid, read at t + αT by linear interpolation); a record shorter
    than the window has no FIV3 (NaN).
    """
    from scipy.signal import find_peaks, lfilter

    from stepframe.records.integration import velocity_m_s

    acc = np.asarray(acc_m_s2, dtype=np.float64)
    time_s = np.arange(acc.size) * dt_s
    window_s = FIV_ALPHA * period_s
    starts = time_s[time_s + window_s <= time_s[-1]]
    if starts.size < 3:
        return math.nan
    nyquist_hz = 0.5 / dt_s
    cutoff_hz = min(FIV_BETA / period_s, 0.99 * nyquist_hz)
    b, a = _low_pass(cutoff_hz, 1.0 / dt_s)
    velocity = velocity_m_s(lfilter(b, a, acc), dt_s)
    fiv = np.interp(starts + window_s, time_s, velocity) - velocity[: starts.size]
    peaks = np.sort(fiv[find_peaks(fiv)[0]])[::-1][:3]
    troughs = np.sort(fiv[find_peaks(-fiv)[0]])[:3]
    return float(max(np.sum(peaks), abs(np.sum(troughs))))


@functools.lru_cache(maxsize=64)
def _low_pass(cutoff_hz: float, sampling_hz: float) -> tuple[Floats, Floats]:
    """FIV3's second-order Butterworth low-pass at ``cutoff_hz`` [Hz] for samples at
    ``sampling_hz`` [Hz]: its coefficients ``(b, a)``, read-only.

    Remembered: a catalogue's records share a few sampling intervals and the selection asks
    one period of each, and designing the filter was about a sixth of a record's spectra and
    peers (2.38 → 2.01 ms per component without it; docs/benchmarks.md, issue 29).
    """
    from scipy.signal import butter

    b, a = butter(2, cutoff_hz, fs=sampling_hz)
    for coefficients in (b, a):
        coefficients.flags.writeable = False  # shared by every later call
    return b, a


def peer_values(sa_m_s2: Floats, pga_m_s2: float, pgv_m_s: float, fiv3: float) -> dict[str, float]:
    """The peers of one record from its 5 %-damped S_a at :attr:`PeerPeriods.all` [m/s²], its
    PGA [m/s²], PGV [m/s] and FIV3 [m/s]."""
    sa_t1, sa_15 = float(sa_m_s2[0]), float(sa_m_s2[1])
    ranges = np.asarray(sa_m_s2[2:], dtype=np.float64).reshape(3, N_AVERAGE)
    with np.errstate(divide="ignore", invalid="ignore"):
        average, twice, band = np.exp(np.mean(np.log(ranges), axis=1))
        return {
            "sa_t1_g": sa_t1 / STANDARD_GRAVITY_M_S2,
            "sa_avg_g": float(average) / STANDARD_GRAVITY_M_S2,
            "sa_ratio": sa_t1 / float(average),
            "n_p_2t1": float(twice) / sa_t1,
            "n_p_band": float(band) / sa_t1,
            "fiv3_m_s": fiv3,
            "sa_1_5t1_ratio": sa_15 / sa_t1,
            "pgv_pga_s": pgv_m_s / pga_m_s2,
            "pgv_sa_t1_s": pgv_m_s / sa_t1,
        }


def record_peers(acc_m_s2: Floats, dt_s: float, periods: PeerPeriods) -> dict[str, float]:
    """Every peer of one record (one spectrum call at :attr:`PeerPeriods.all`, 5 % damping)."""
    from stepframe.records.integration import velocity_m_s
    from stepframe.records.spectra import peak_displacements_m, pseudo_acceleration_m_s2

    acc = np.asarray(acc_m_s2, dtype=np.float64)
    all_periods = periods.all
    sd = peak_displacements_m(acc, dt_s, all_periods, 0.05)
    sa = pseudo_acceleration_m_s2(all_periods, sd)
    pga = float(np.max(np.abs(acc)))
    pgv = float(np.max(np.abs(velocity_m_s(acc, dt_s))))
    return peer_values(sa, pga, pgv, fiv3_m_s(acc, dt_s, periods.period_1_s))


def at_intensity(name: str, values: Floats, scales: Floats) -> Floats:
    """The peer ``name``'s values for the records scaled by ``scales``, signed so that larger is
    more severe (the ranking it gives)."""
    peer = PEERS[name]
    with np.errstate(invalid="ignore"):
        out = np.asarray(peer.direction * values * scales**peer.exponent, dtype=np.float64)
    if np.isfinite(out).any():
        # S_a(T_1) of records scaled to equal S_a(T_1) differs only by rounding (the scale comes
        # from a separate spectrum call): equal values must rank as ties, not by that noise
        middle = float(np.nanmedian(out))
        out = np.where(np.abs(out - middle) <= 1e-9 * abs(middle), middle, out)
    return out


def spectra_and_peers(
    item: tuple[Floats, float, tuple[tuple[Floats, float], ...], PeerPeriods],
) -> tuple[list[Floats], dict[str, float]]:
    """One record's spectra pass (:func:`stepframe.pipeline.selection.spectral.record_spectra`
    on ``item[:3]``) and its peers at ``item[3]`` (a :func:`map_items` worker)."""
    from stepframe.pipeline.selection.spectral import record_spectra

    acc, dt, groups, periods = item
    return record_spectra((acc, dt, groups)), record_peers(acc, dt, periods)
