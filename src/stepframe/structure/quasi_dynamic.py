"""Quasi-dynamic design displacement of a stepping (rocking) pier: the paper's Part 1.

The AASHTO/Priestley procedure (paper eqs. 1.1-1.3) iterates, from a trial displacement δ_i,

    F_i = K_i δ_i = F_0 (1 - w δ_i),        F_0 = W_T (L_F - a) / (2 H_r),  w = W_s / (H_r F_0)
    T_i = 2π √(m_eff / K_i),                m_eff = (W_s + 0.5 W_col) / g
    δ_{i+1} = (T_i / 2π)² β S_a(T_i).

With u = δ/(1 - wδ) and c = m_eff/F_0 [s²/m] this is the one-dimensional map

    T(δ) = 2π √(c u),    f(δ) = c u β S_a(T(δ)),

defined for 0 ≤ δ < 1/w. On the branches of a two-period spectrum it becomes

    short (T ≤ T_s, S_a = S_DS):      f_1 = λ_1 u,      λ_1 = c β S_DS          (eqs. 2.1-2.2)
    long (T_s < T ≤ T_L, S_D1/T):     f_2 = λ_2 √u,     λ_2 = β S_D1 √c / 2π    (eqs. 2.4-2.5)
    very long (T > T_L, S_D1 T_L/T²): f_3 = λ_3,        λ_3 = β S_D1 T_L / 4π²

with fixed points δ_1* = 0, δ_2* = (1 - λ_1)/w (eq. 2.9), δ_3,4* = (1 ∓ √(1 - 4wλ_2²))/2w
(eq. 2.14) and δ_5* = λ_3 (constant spectral displacement; not in the paper). Their multipliers
are f_1' = λ_1/(1 - wδ)² (eq. 2.11), and, at a fixed point of f_2, f_2' = δ*/(2λ_2²): 1/(1 + s)
for δ_3* and 1/(1 - s) for δ_4*, s = √(1 - 4wλ_2²). (Eq. 2.16 as printed pairs the signs the other
way round; see docs/paper-notes.md.) A closed-form fixed point is only a design answer if its
period lies on the branch its formula assumed: :func:`closed_form_fixed_points` checks that, and
:func:`search_fixed_points` finds the fixed points of the full map numerically for any spectrum.

Fidelity ladder (:func:`design_displacement`, ``method=``): ``"closed-form"`` (microseconds, two-
period spectra only) → ``"iteration"`` (the AASHTO/Priestley procedure itself, traced) →
``"search"`` (bracketing of every fixed point of the full map, any spectrum).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any, Literal

from stepframe.core import validation
from stepframe.core.io import read_toml
from stepframe.core.jsonable import without_none
from stepframe.core.results import Status
from stepframe.errors import InputError
from stepframe.structure.damping import (
    DAMPING_METHODS,
    DampingMethod,
    damping_reduction,
    equivalent_damping_from_cr,
)
from stepframe.structure.design_spectrum import (
    Branch,
    Spectrum,
    TabulatedSpectrum,
    TwoPeriodSpectrum,
    spectrum_from_dict,
)

Method = Literal["closed-form", "iteration", "search"]
BranchChoice = Literal["auto", "short", "long", "very-long"]

#: A displacement δ with w·δ below this is the trivial fixed point δ_1* = 0.
_ZERO_W_DELTA = 1e-13


@dataclass(frozen=True)
class PierInputs:
    """Physical inputs of the rocking pier of paper Fig. 1 (SI: N, m).

    Attributes
    ----------
    weight_super_n
        Seismic weight of the superstructure W_s [N].
    weight_col_n
        Weight of the column(s) W_col [N], entering the effective mass as
        ``col_weight_factor · W_col`` (the paper's 0.5 W_col). The paper's Example 1 states
        W_col = 424 kN but substitutes 212 kN: pass the value you mean.
    weight_total_n
        Gross weight on the footing W_T [N] (≥ W_s).
    footing_length_m
        Footing length L_F in the direction of rocking [m].
    height_m
        Height of the centroid of the rocking mass H_r [m].
    block_width_m
        Width a of the compression stress block under the footing [m]; None to compute it as
        a = W_T / (B_F q_n) from ``footing_width_m`` and ``bearing_capacity_pa``.
    footing_width_m
        Footing width B_F [m] (only used to compute a).
    bearing_capacity_pa
        Soil bearing capacity q_n [Pa] (only used to compute a).
    col_weight_factor
        Fraction of W_col counted in the effective mass [-] (default 0.5, eq. 1.2).
    g_m_s2
        Acceleration of gravity [m/s²] (default 9.81, as in the paper's examples).
    """

    weight_super_n: float
    weight_col_n: float
    weight_total_n: float
    footing_length_m: float
    height_m: float
    block_width_m: float | None = None
    footing_width_m: float | None = None
    bearing_capacity_pa: float | None = None
    col_weight_factor: float = 0.5
    g_m_s2: float = 9.81

    def __post_init__(self) -> None:
        for name in ("weight_super_n", "weight_total_n", "footing_length_m", "height_m", "g_m_s2"):
            validation.positive(name, getattr(self, name))
        validation.finite("weight_col_n", self.weight_col_n)
        if self.weight_col_n < 0:
            raise InputError(f"weight_col_n = {self.weight_col_n}, expected ≥ 0")
        factor = validation.finite("col_weight_factor", self.col_weight_factor)
        if not 0 <= factor <= 1:
            raise InputError(f"col_weight_factor = {factor}, expected 0 ≤ col_weight_factor ≤ 1")
        if self.weight_total_n < self.weight_super_n:
            raise InputError(
                f"weight_total_n = {self.weight_total_n} N < weight_super_n = "
                f"{self.weight_super_n} N, expected W_T ≥ W_s"
            )
        given_a = self.block_width_m is not None
        given_soil = self.footing_width_m is not None or self.bearing_capacity_pa is not None
        if given_a == given_soil:
            raise InputError(
                "expected either block_width_m (a) or both footing_width_m and "
                "bearing_capacity_pa (a = W_T / (B_F q_n)), not both and not neither"
            )
        if given_a:
            validation.positive("block_width_m", self.block_width_m)
        else:
            validation.positive("footing_width_m", self.footing_width_m)
            validation.positive("bearing_capacity_pa", self.bearing_capacity_pa)
        if not self.block_width_m_value < self.footing_length_m:
            raise InputError(
                f"compression block a = {self.block_width_m_value:.6g} m ≥ footing_length_m = "
                f"{self.footing_length_m} m, expected a < L_F (the soil cannot carry W_T)"
            )

    @property
    def block_width_m_value(self) -> float:
        """Compression block width a [m], given or W_T / (B_F q_n)."""
        if self.block_width_m is not None:
            return self.block_width_m
        assert self.footing_width_m is not None and self.bearing_capacity_pa is not None
        return self.weight_total_n / (self.footing_width_m * self.bearing_capacity_pa)

    @property
    def lift_off_force_n(self) -> float:
        """F_0 = W_T (L_F - a) / (2 H_r) [N]: lateral force at incipient rocking (δ = 0)."""
        return (
            self.weight_total_n
            * (self.footing_length_m - self.block_width_m_value)
            / (2.0 * self.height_m)
        )

    @property
    def effective_mass_kg(self) -> float:
        """m_eff = (W_s + col_weight_factor · W_col) / g [kg]."""
        return (self.weight_super_n + self.col_weight_factor * self.weight_col_n) / self.g_m_s2

    def to_dict(self) -> dict[str, Any]:
        """The fields, omitting those left as None (the TOML ``[pier]`` table)."""
        return {k: v for k, v in asdict(self).items() if v is not None}

    @classmethod
    def from_dict(cls, data: Mapping[str, Any], where: str = "[pier]") -> PierInputs:
        """Build from a TOML-like table; unknown keys are an error naming the key."""
        known = set(cls.__dataclass_fields__)
        unknown = set(data) - known
        if unknown:
            raise InputError(f"{where}: unknown key(s) {sorted(unknown)}, expected {sorted(known)}")
        missing = {
            "weight_super_n",
            "weight_col_n",
            "weight_total_n",
            "footing_length_m",
            "height_m",
        } - set(data)
        if missing:
            raise InputError(f"{where}: missing key(s) {sorted(missing)}")
        return cls(**dict(data))


@dataclass(frozen=True)
class SteppingMap:
    """The design map f(δ) = c u β S_a(2π√(c u)), u = δ/(1 - wδ), for 0 ≤ δ < 1/w.

    Attributes
    ----------
    w_per_m
        w = 2 W_s / (W_T (L_F - a)) [1/m] (eq. 2.3); 1/w is the displacement at which the
        lateral capacity F_i vanishes.
    c_s2_per_m
        c = m_eff / F_0 [s²/m]; T(δ) = 2π √(c δ / (1 - wδ)).
    beta
        Damping reduction factor β on the 5 %-damped spectrum [-].
    lift_off_force_n
        F_0 [N], only needed to report the secant stiffness K_i = F_0 (1 - wδ_i)/δ_i.
    """

    w_per_m: float
    c_s2_per_m: float
    beta: float
    lift_off_force_n: float | None = None

    def __post_init__(self) -> None:
        validation.positive("w_per_m", self.w_per_m)
        validation.positive("c_s2_per_m", self.c_s2_per_m)
        validation.positive("beta", self.beta)
        if self.lift_off_force_n is not None:
            validation.positive("lift_off_force_n", self.lift_off_force_n)

    @classmethod
    def from_pier(cls, pier: PierInputs, beta: float) -> SteppingMap:
        """The map of a physical pier (eqs. 1.1-1.3, 2.3)."""
        f_0 = pier.lift_off_force_n
        return cls(
            w_per_m=pier.weight_super_n / (pier.height_m * f_0),
            c_s2_per_m=pier.effective_mass_kg / f_0,
            beta=beta,
            lift_off_force_n=f_0,
        )

    @classmethod
    def from_lambda_2(
        cls, w_per_m: float, lambda_2_sqrt_m: float, beta: float, s_d1_m_s: float
    ) -> SteppingMap:
        """The map with given w and λ_2 (as the paper's Example 2 table states them).

        c follows from λ_2 = β S_D1 √c / 2π; F_0 is unknown, so stiffnesses are not reported.
        """
        lam = validation.positive("lambda_2_sqrt_m", lambda_2_sqrt_m)
        c = (
            2.0
            * math.pi
            * lam
            / (validation.positive("beta", beta) * validation.positive("s_d1_m_s", s_d1_m_s))
        ) ** 2
        return cls(w_per_m=w_per_m, c_s2_per_m=c, beta=beta)

    @property
    def delta_limit_m(self) -> float:
        """1/w [m]: the map is defined for δ < 1/w only."""
        return 1.0 / self.w_per_m

    def period_s(self, delta_m: float) -> float:
        """Equivalent linear period T(δ) = 2π √(c δ / (1 - wδ)) [s] (eqs. 1.1-1.2)."""
        return 2.0 * math.pi * math.sqrt(self.c_s2_per_m * delta_m / (1.0 - self.w_per_m * delta_m))

    def stiffness_n_m(self, delta_m: float) -> float | None:
        """Secant stiffness K = F_0 (1 - wδ)/δ [N/m] (eq. 1.1); None when F_0 is not known."""
        if self.lift_off_force_n is None or delta_m <= 0:
            return None
        return self.lift_off_force_n * (1.0 - self.w_per_m * delta_m) / delta_m

    def lambda_1(self, spectrum: TwoPeriodSpectrum) -> float:
        """λ_1 = c β S_DS [-] (eq. 2.2)."""
        return self.c_s2_per_m * self.beta * spectrum.s_ds_m_s2

    def lambda_2_sqrt_m(self, spectrum: TwoPeriodSpectrum) -> float:
        """λ_2 = β S_D1 √c / 2π [m^½] (eq. 2.5)."""
        return self.beta * spectrum.s_d1_m_s * math.sqrt(self.c_s2_per_m) / (2.0 * math.pi)

    def lambda_3_m(self, spectrum: TwoPeriodSpectrum) -> float | None:
        """λ_3 = β S_D1 T_L / 4π² [m] (the constant-displacement branch), None without T_L."""
        if spectrum.t_l_s is None:
            return None
        return self.beta * spectrum.s_d1_m_s * spectrum.t_l_s / (4.0 * math.pi**2)

    def __call__(self, delta_m: float, spectrum: Spectrum) -> float:
        """f(δ): the next iterate of the AASHTO/Priestley procedure (eq. 1.3)."""
        period = self.period_s(delta_m)
        u = delta_m / (1.0 - self.w_per_m * delta_m)
        return self.c_s2_per_m * u * self.beta * spectrum.sa_m_s2(period)

    def branch_formula(
        self, spectrum: TwoPeriodSpectrum, branch: Literal["short", "long", "very-long"]
    ) -> Callable[[float], float]:
        """The single-branch map f_1, f_2 or f_3, applied whatever the period (as in eq. 2.1)."""
        w = self.w_per_m
        if branch == "short":
            lam1 = self.lambda_1(spectrum)
            return lambda d: lam1 * d / (1.0 - w * d)
        if branch == "long":
            lam2 = self.lambda_2_sqrt_m(spectrum)
            return lambda d: lam2 * math.sqrt(d / (1.0 - w * d))
        lam3 = self.lambda_3_m(spectrum)
        if lam3 is None:
            raise InputError("branch 'very-long' needs a spectrum with t_l_s")
        return lambda d: lam3

    def to_dict(self) -> dict[str, Any]:
        """The fields as a dictionary."""
        return asdict(self)

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> SteppingMap:
        """Inverse of :meth:`to_dict`; unknown keys are an error naming the key."""
        known = set(cls.__dataclass_fields__)
        unknown = set(data) - known
        if unknown:
            raise InputError(f"unknown key(s) {sorted(unknown)}, expected {sorted(known)}")
        return cls(**dict(data))


@dataclass(frozen=True)
class FixedPoint:
    """A fixed point δ* = f(δ*) of the design map, with its linear stability.

    Attributes
    ----------
    name
        ``"delta_1"`` ... ``"delta_5"`` for the closed forms, ``"search_k"`` for numerical ones.
    formula
        Where it comes from (``"eq. 2.14"``, ``"numerical search"``).
    branch
        Spectrum branch the formula assumed (closed forms) or found at T* (search).
    delta_m
        δ* [m], or None when the formula has no real root in [0, 1/w).
    period_s
        T* = T(δ*) [s] (None when δ* is None).
    multiplier
        f'(δ*) [-]; ``inf`` for the long branch at δ = 0 (√δ has an infinite slope there).
    stable
        |f'(δ*)| < 1: the iteration converges to δ* from nearby starts.
    on_branch
        The period T* lies on the branch the formula assumed (False: not a fixed point of the
        real procedure, whatever the formula says).
    """

    name: str
    formula: str
    branch: Branch
    delta_m: float | None
    period_s: float | None
    multiplier: float | None
    stable: bool
    on_branch: bool

    def to_dict(self) -> dict[str, Any]:
        """The fields as a dictionary; δ*, T* and f'(δ*) absent when the formula has no root."""
        return asdict(self, dict_factory=without_none)


def closed_form_fixed_points(
    stepping_map: SteppingMap, spectrum: TwoPeriodSpectrum
) -> tuple[FixedPoint, ...]:
    """δ_1* ... δ_4* (eqs. 2.9, 2.14), δ_5* (T_L branch), multipliers and branch checks.

    A fixed point whose formula has no root in [0, 1/w) is returned with ``delta_m=None``.
    The roots are computed in forms free of cancellation: δ_3* = 2λ_2²/(1 + s), so that
    w λ_2² → 0 keeps full relative accuracy.
    """
    w = stepping_map.w_per_m
    lam1 = stepping_map.lambda_1(spectrum)
    lam2 = stepping_map.lambda_2_sqrt_m(spectrum)
    out: list[FixedPoint] = []

    def make(
        name: str,
        formula: str,
        branch: Literal["short", "long", "very-long"],
        delta: float | None,
        multiplier: float | None,
    ) -> FixedPoint:
        if delta is None or not 0 <= delta < 1.0 / w:
            return FixedPoint(name, formula, branch, None, None, None, False, False)
        period = stepping_map.period_s(delta)
        stable = multiplier is not None and abs(multiplier) < 1
        return FixedPoint(
            name,
            formula,
            branch,
            delta,
            period,
            multiplier,
            stable,
            spectrum.branch(period) == branch,
        )

    # δ_1* = 0 sits at T = 0, on the plateau, where the map is f_1 with slope λ_1 (eq. 2.11).
    out.append(make("delta_1", "eq. 2.9", "short", 0.0, lam1))
    delta_2 = (1.0 - lam1) / w
    out.append(make("delta_2", "eq. 2.9", "short", delta_2 if lam1 <= 1 else None, 1.0 / lam1))
    disc = 1.0 - 4.0 * w * lam2**2
    if disc >= 0:
        s = math.sqrt(disc)
        delta_3 = 2.0 * lam2**2 / (1.0 + s)
        delta_4 = (1.0 + s) / (2.0 * w)
        # f_2'(δ*) = δ*/(2λ_2²) at any fixed point of f_2 (use 1 - wδ* = λ_2²/δ*).
        out.append(make("delta_3", "eq. 2.14", "long", delta_3, 1.0 / (1.0 + s)))
        out.append(make("delta_4", "eq. 2.14", "long", delta_4, delta_4 / (2.0 * lam2**2)))
    else:
        out.append(make("delta_3", "eq. 2.14", "long", None, None))
        out.append(make("delta_4", "eq. 2.14", "long", None, None))
    lam3 = stepping_map.lambda_3_m(spectrum)
    if lam3 is not None:
        out.append(make("delta_5", "constant-displacement branch", "very-long", lam3, 0.0))
    return tuple(out)


@dataclass(frozen=True)
class IterateRow:
    """One iterate of the AASHTO/Priestley procedure.

    Attributes
    ----------
    i
        Iteration index (0: the starting value δ_0).
    delta_m
        δ_i [m].
    stiffness_n_m
        Secant stiffness K_i [N/m] (None when F_0 is not known or δ_i = 0).
    period_s
        T_i [s].
    branch
        The spectrum branch used to compute δ_{i+1} from this row.
    """

    i: int
    delta_m: float
    stiffness_n_m: float | None
    period_s: float
    branch: Branch


@dataclass(frozen=True)
class Iteration:
    """Trace and outcome of the AASHTO/Priestley iteration from one start.

    Attributes
    ----------
    rows
        δ_0, δ_1, ... with K_i, T_i and the branch used at each step.
    status
        From :data:`stepframe.core.results.STATUSES`: ``"ok"`` (converged, possibly to
        δ_1* = 0: see ``to_zero``), ``"failed"`` (an iterate reached δ ≥ 1/w: no lateral
        capacity left, the procedure has no answer) or ``"not_converged"`` (``max_iterations``
        reached).
    delta_m, period_s
        The last iterate and its period (δ* and T* when converged).
    branch_choice
        The branch option the iteration ran with.
    notes
        Remarks (a forced branch used off its range).
    message
        What happened, one line.
    to_zero
        Whether it converged to δ_1* = 0 (the procedure predicts no rocking).
    """

    rows: tuple[IterateRow, ...]
    status: Status
    delta_m: float
    period_s: float
    branch_choice: BranchChoice = "auto"
    notes: tuple[str, ...] = field(default=())
    message: str = ""
    to_zero: bool = False

    def to_dict(self) -> dict[str, Any]:
        """Trace and outcome as a dictionary (a row's K_i absent where it is not known)."""
        return asdict(self, dict_factory=without_none)


def iterate(
    stepping_map: SteppingMap,
    spectrum: Spectrum,
    delta0_m: float,
    *,
    branch: BranchChoice = "auto",
    max_iterations: int = 200,
    rtol: float = 1e-12,
) -> Iteration:
    """Run the AASHTO/Priestley iteration δ_{i+1} = f(δ_i) from ``delta0_m``, keeping every iterate.

    Parameters
    ----------
    stepping_map, spectrum
        The design map and the spectrum.
    delta0_m
        Starting displacement δ_0 [m], 0 ≤ δ_0 < 1/w.
    branch
        ``"auto"`` (default): S_a at each T_i, as the procedure prescribes. ``"short"``,
        ``"long"`` or ``"very-long"``: apply that branch's formula whatever T_i is (what the
        paper's Example 2 table does); needs a :class:`TwoPeriodSpectrum`.
    max_iterations
        Largest number of steps.
    rtol
        Converged when |δ_{i+1} - δ_i| ≤ rtol · δ_{i+1}.

    Returns
    -------
    Iteration
        The trace; failure to converge is a status, not an exception.
    """
    w = stepping_map.w_per_m
    start = validation.finite("delta0_m", delta0_m)
    if not 0 <= start < 1.0 / w:
        raise InputError(f"delta0_m = {start} m, expected 0 ≤ delta0_m < 1/w = {1.0 / w:.6g} m")
    if max_iterations < 1:
        raise InputError(f"max_iterations = {max_iterations}, expected ≥ 1")
    step: Callable[[float], float]
    if branch == "auto":

        def step(d: float) -> float:
            return stepping_map(d, spectrum)

        def branch_at(period: float) -> Branch:
            return spectrum.branch(period)
    else:
        if not isinstance(spectrum, TwoPeriodSpectrum):
            raise InputError(f"branch = {branch!r} needs a two-period spectrum, expected 'auto'")
        step = stepping_map.branch_formula(spectrum, branch)
        forced: Branch = branch

        def branch_at(period: float) -> Branch:
            return forced

    rows: list[IterateRow] = []
    notes: list[str] = []
    delta = start
    status: Status = "not_converged"
    message = f"no convergence in {max_iterations} iterations"
    to_zero = False
    for i in range(max_iterations + 1):
        period = stepping_map.period_s(delta)
        used = branch_at(period)
        rows.append(IterateRow(i, delta, stepping_map.stiffness_n_m(delta), period, used))
        if branch != "auto" and isinstance(spectrum, TwoPeriodSpectrum):
            actual = spectrum.branch(period)
            if actual != branch and not any(n.startswith("forced") for n in notes):
                notes.append(
                    f"forced branch {branch!r} used at T_{i} = {period:.4g} s, which lies on the "
                    f"{actual!r} branch"
                )
        if i == max_iterations:
            break
        nxt = step(delta)
        if not (math.isfinite(nxt) and 0 <= nxt < 1.0 / w):
            status = "failed"
            message = f"iterate {i + 1} left the domain 0 ≤ δ < 1/w: no lateral capacity left"
            break
        if w * nxt < _ZERO_W_DELTA:
            rows.append(IterateRow(i + 1, nxt, None, stepping_map.period_s(nxt), used))
            status, message, to_zero = "ok", "converged to δ_1* = 0 (no rocking)", True
            break
        if abs(nxt - delta) <= rtol * nxt:
            period = stepping_map.period_s(nxt)
            rows.append(
                IterateRow(i + 1, nxt, stepping_map.stiffness_n_m(nxt), period, branch_at(period))
            )
            status, message = "ok", "converged"
            break
        delta = nxt
    last = rows[-1]
    return Iteration(
        tuple(rows), status, last.delta_m, last.period_s, branch, tuple(notes), message, to_zero
    )


def map_derivative(
    stepping_map: SteppingMap, spectrum: Spectrum, delta_m: float, rel_step: float = 1e-6
) -> float:
    """Central-difference f'(δ) (one-sided at δ = 0); used by the numerical search.

    Near the domain's end 1/w, where f grows like (1 - wδ)^(-1/2), the step is at most a quarter
    of the distance to it: a weak spectrum puts the unstable root some 10⁻¹⁰/w from the end,
    where a step of ``rel_step``·δ left the domain (a math domain error). The slope there is
    good to a few per cent (the step's truncation and the rounding of 1 - wδ), enough for its
    verdict: it is in the hundreds of thousands."""
    h = rel_step * max(delta_m, 1e-9 * stepping_map.delta_limit_m)
    h = min(h, 0.25 * (stepping_map.delta_limit_m - delta_m))
    if delta_m - h <= 0:
        return (stepping_map(delta_m + h, spectrum) - stepping_map(delta_m, spectrum)) / h
    up = stepping_map(delta_m + h, spectrum)
    down = stepping_map(delta_m - h, spectrum)
    return (up - down) / (2.0 * h)


def search_fixed_points(
    stepping_map: SteppingMap, spectrum: Spectrum, *, n_grid: int = 2000
) -> tuple[FixedPoint, ...]:
    """Every fixed point of the full map (all branches at once), for any spectrum.

    f(δ) - δ is sampled on a geometric grid of ``n_grid`` points in [10⁻¹⁰/w, (1 - 10⁻¹⁰)/w],
    each sign change is refined by Brent's method, and the multiplier is a central difference.
    δ_1* = 0 is always a fixed point and is listed first, with the one-sided slope at 0.
    Roots closer together than the grid spacing can be missed; raise ``n_grid`` for such spectra.
    """
    from scipy.optimize import brentq

    if n_grid < 10:
        raise InputError(f"n_grid = {n_grid}, expected ≥ 10")
    limit = stepping_map.delta_limit_m

    def excess(d: float) -> float:
        return stepping_map(d, spectrum) - d

    lo_d, hi_d = 1e-10 * limit, (1.0 - 1e-10) * limit
    ratio = (hi_d / lo_d) ** (1.0 / (n_grid - 1))
    grid = [lo_d * ratio**k for k in range(n_grid)]
    values = [excess(d) for d in grid]
    found: list[FixedPoint] = []
    slope_0 = stepping_map(lo_d, spectrum) / lo_d
    found.append(
        FixedPoint("search_0", "numerical search", spectrum.branch(0.0), 0.0, 0.0, slope_0,
                   abs(slope_0) < 1, True)
    )  # fmt: skip
    for k in range(n_grid - 1):
        a, b = values[k], values[k + 1]
        if a == 0 or a * b < 0:
            root = grid[k] if a == 0 else float(brentq(excess, grid[k], grid[k + 1], xtol=1e-15,
                                                       rtol=8.9e-16))  # fmt: skip
            period = stepping_map.period_s(root)
            slope = map_derivative(stepping_map, spectrum, root)
            found.append(
                FixedPoint(f"search_{len(found)}", "numerical search", spectrum.branch(period),
                           root, period, slope, abs(slope) < 1, True)
            )  # fmt: skip
    return tuple(found)


@dataclass(frozen=True)
class DesignResult:
    """The design displacement chosen by :func:`design_displacement`.

    Attributes
    ----------
    method
        How it was found.
    status
        ``"ok"`` (δ* may be 0 when the only stable answer is δ_1* = 0: the procedure predicts no
        rocking; ``message`` says so), or ``"failed"`` when no stable fixed point lies on its
        branch (δ is then None).
    delta_m, period_s, multiplier, branch
        δ*, T*, f'(δ*) and the spectrum branch at T*.
    stepping_effectiveness
        SE = 1 - F(δ*)/F_0 with F_0 = F(0) (see :func:`stepping_effectiveness`).
    iteration
        The trace, for ``method="iteration"``.
    """

    method: Method
    status: Status
    delta_m: float | None
    period_s: float | None
    multiplier: float | None
    branch: Branch | None
    stepping_effectiveness: float | None
    iteration: Iteration | None = None
    message: str = ""

    def to_dict(self) -> dict[str, Any]:
        """The fields as a dictionary; δ*, T*, f'(δ*), the branch, SE and the iteration absent
        where there are none (a failed design)."""
        return asdict(self, dict_factory=without_none)


def stepping_effectiveness(
    stepping_map: SteppingMap, delta_m: float, delta0_m: float = 0.0
) -> float:
    """Stepping effectiveness SE = 1 - F(δ*)/F(δ_0) = 1 - (1 - wδ*)/(1 - wδ_0) (eq. 2.21, exact).

    The force at displacement δ is F = F_0 (1 - wδ) (eq. 1.1), so the product in eq. 2.21
    telescopes to this ratio. The default δ_0 = 0 takes F_0, the force at incipient rocking, as
    the reference, giving SE = wδ*. (The paper's last step, SE = 1 - T_0/T_n, does not follow:
    see docs/paper-notes.md.)
    """
    w = stepping_map.w_per_m
    return 1.0 - (1.0 - w * delta_m) / (1.0 - w * delta0_m)


def design_displacement(
    stepping_map: SteppingMap,
    spectrum: Spectrum,
    method: Method = "closed-form",
    *,
    delta0_m: float | None = None,
    max_iterations: int = 200,
) -> DesignResult:
    """Design displacement δ* by one rung of the fidelity ladder.

    Parameters
    ----------
    stepping_map
        The map f(δ) of eq. 1.3 (:class:`SteppingMap`).
    spectrum
        The design spectrum (two-period or tabulated).
    method
        ``"closed-form"``: the stable fixed point among eqs. 2.9/2.14 (and δ_5*) whose period lies
        on its branch (two-period spectra only; microseconds). ``"iteration"``: the
        AASHTO/Priestley procedure from ``delta0_m``. ``"search"``: the smallest stable non-zero
        fixed point of the full map found by :func:`search_fixed_points` (any spectrum).
    delta0_m
        Start of the iteration [m] (default 5 % of 1/w).
    max_iterations
        Iteration limit of ``"iteration"``.

    Returns
    -------
    DesignResult
        ``status`` says whether a stable answer exists; a missing answer is not an exception.
    """
    if method == "closed-form":
        if not isinstance(spectrum, TwoPeriodSpectrum):
            raise InputError(
                "method 'closed-form' needs a two-period spectrum, expected 'search' or "
                "'iteration' for a tabulated spectrum"
            )
        points = closed_form_fixed_points(stepping_map, spectrum)
    elif method == "search":
        points = search_fixed_points(stepping_map, spectrum)
    elif method == "iteration":
        start = 0.05 * stepping_map.delta_limit_m if delta0_m is None else delta0_m
        trace = iterate(stepping_map, spectrum, start, max_iterations=max_iterations)
        if trace.status == "ok":
            delta = 0.0 if trace.to_zero else trace.delta_m
            return DesignResult(
                method,
                "ok",
                delta,
                stepping_map.period_s(delta),
                map_derivative(stepping_map, spectrum, delta),
                spectrum.branch(stepping_map.period_s(delta)),
                stepping_effectiveness(stepping_map, delta),
                trace,
                _NO_ROCKING if trace.to_zero else "",
            )
        return DesignResult(method, "failed", None, None, None, None, None, trace, trace.message)
    else:
        raise InputError(f"method {method!r}, expected 'closed-form', 'iteration' or 'search'")
    usable = [p for p in points if p.stable and p.on_branch and p.delta_m is not None]
    nonzero = [p for p in usable if p.delta_m]
    chosen = nonzero[0] if nonzero else (usable[0] if usable else None)
    if chosen is None or chosen.delta_m is None:
        return DesignResult(method, "failed", None, None, None, None, None, None, _NO_ANSWER)
    return DesignResult(
        method,
        "ok",
        chosen.delta_m,
        chosen.period_s,
        chosen.multiplier,
        chosen.branch,
        stepping_effectiveness(stepping_map, chosen.delta_m),
        None,
        "" if chosen.delta_m > 0 else _NO_ROCKING,
    )


_NO_ROCKING = "the only stable answer is δ_1* = 0: the procedure predicts no rocking"
_NO_ANSWER = "no stable fixed point lies on its branch"


# ----------------------------------------------------------------------------------------------
# Design input file (TOML): [pier] or [map], [spectrum], [damping], [iteration]


@dataclass(frozen=True)
class DesignCase:
    """Everything a design run needs: the map, the spectrum, and how to iterate.

    Attributes
    ----------
    stepping_map
        The design map (from a pier, or from w and λ_2).
    spectrum
        Two-period or tabulated spectrum.
    pier
        The physical inputs, when the map was built from them.
    xi
        Equivalent viscous damping used for β (None when β was given).
    damping_method
        The damping-reduction formula used (None when β was given).
    delta0_m
        Starting values of the iteration [m].
    """

    stepping_map: SteppingMap
    spectrum: TwoPeriodSpectrum | TabulatedSpectrum
    pier: PierInputs | None = None
    xi: float | None = None
    damping_method: DampingMethod | None = None
    delta0_m: tuple[float, ...] = ()

    def to_dict(self) -> dict[str, Any]:
        """The case as nested dictionaries."""
        return {
            "map": self.stepping_map.to_dict(),
            "spectrum": self.spectrum.to_dict(),
            "pier": None if self.pier is None else self.pier.to_dict(),
            "xi": self.xi,
            "damping_method": self.damping_method,
            "delta0_m": list(self.delta0_m),
        }


def resolve_beta(
    damping: Mapping[str, Any], where: str = "[damping]"
) -> tuple[float, float | None, DampingMethod | None]:
    """β from a ``[damping]`` table: ``beta``, or ``xi`` or ``c_r`` with optional ``method``.

    Returns (β, ξ or None, method or None).
    """
    known = {"beta", "xi", "c_r", "method"}
    unknown = set(damping) - known
    if unknown:
        raise InputError(f"{where}: unknown key(s) {sorted(unknown)}, expected {sorted(known)}")
    given = [k for k in ("beta", "xi", "c_r") if k in damping]
    if len(given) != 1:
        raise InputError(f"{where}: expected exactly one of beta, xi or c_r, found {given}")
    if "beta" in damping:
        if "method" in damping:
            raise InputError(f"{where}: method given with beta, expected method only with xi/c_r")
        beta = validation.positive("beta", damping["beta"])
        if beta > 2:
            raise InputError(f"beta = {beta}, expected a reduction factor in (0, 2]")
        return beta, None, None
    method = damping.get("method", "ec8")
    if method not in DAMPING_METHODS:
        raise InputError(
            f"{where}: method = {method!r}, expected one of {', '.join(DAMPING_METHODS)}"
        )
    if "xi" in damping:
        xi = validation.finite("xi", damping["xi"])
    else:
        xi = equivalent_damping_from_cr(damping["c_r"])
    return damping_reduction(xi, method), xi, method


def case_from_dict(data: Mapping[str, Any], where: str = "design input") -> DesignCase:
    """Build a :class:`DesignCase` from nested tables (a parsed TOML file).

    Tables: ``[pier]`` (see :class:`PierInputs`) or ``[map]`` (``w_per_m``, ``lambda_2_sqrt_m``),
    ``[spectrum]`` (see :func:`spectrum_from_dict`), ``[damping]`` (see :func:`resolve_beta`),
    optional ``[iteration]`` (``delta0_m``: a list of starts).
    """
    known = {"pier", "map", "spectrum", "damping", "iteration"}
    unknown = set(data) - known
    if unknown:
        raise InputError(f"{where}: unknown table(s) {sorted(unknown)}, expected {sorted(known)}")
    if ("pier" in data) == ("map" in data):
        raise InputError(f"{where}: expected exactly one of the tables [pier] or [map]")
    for name in ("spectrum", "damping"):
        if name not in data:
            raise InputError(f"{where}: missing table [{name}]")
    pier = PierInputs.from_dict(data["pier"], f"{where} [pier]") if "pier" in data else None
    g = (
        pier.g_m_s2
        if pier is not None
        else validation.positive("g_m_s2", data["map"].get("g_m_s2", 9.81))
    )
    spectrum = spectrum_from_dict(data["spectrum"], g_m_s2=g, where=f"{where} [spectrum]")
    beta, xi, method = resolve_beta(data["damping"], f"{where} [damping]")
    if pier is not None:
        stepping_map = SteppingMap.from_pier(pier, beta)
    else:
        table = data["map"]
        known_map = {"w_per_m", "lambda_2_sqrt_m", "g_m_s2"}
        if set(table) - known_map or not {"w_per_m", "lambda_2_sqrt_m"} <= set(table):
            raise InputError(f"{where} [map]: expected keys w_per_m and lambda_2_sqrt_m only")
        if not isinstance(spectrum, TwoPeriodSpectrum):
            raise InputError(f"{where} [map]: λ_2 needs a two-period spectrum (S_D1)")
        stepping_map = SteppingMap.from_lambda_2(
            table["w_per_m"], table["lambda_2_sqrt_m"], beta, spectrum.s_d1_m_s
        )
    iteration = data.get("iteration", {})
    if set(iteration) - {"delta0_m"}:
        raise InputError(f"{where} [iteration]: unknown key(s), expected delta0_m")
    starts = iteration.get("delta0_m", [])
    if isinstance(starts, int | float):
        starts = [starts]
    if "delta0_m" in iteration and not starts:  # it fell back to the default starts, unsaid
        raise InputError(
            "delta0_m = [], expected at least one start [m] (or no delta0_m: the default starts)"
        )
    delta0 = tuple(validation.finite("delta0_m", s) for s in starts)
    return DesignCase(stepping_map, spectrum, pier, xi, method, delta0)


def read_case(path: str | Path) -> DesignCase:
    """Read a design input TOML file; errors name the file (and the line of a TOML error)."""
    data, _ = read_toml(path, "a design input TOML file")
    return case_from_dict(data, where=str(path))
