r"""Classical reference RTD models with analytic E(t) and analytic moments.

Three families are provided, both as pure vectorised functions (broadcast over all
array arguments) and as small frozen model objects used by the fitting code:

* **Tanks in series** (TiS), integer or extended (gamma) N, Lee (2008) Eq. 2.11
  (Martin's extended form):

    $$
    E(t) = \frac{N^N t^{N-1}}{\Gamma(N)\,\tau^N} e^{-N t/\tau}
    $$

  mean $\tau$, variance $\tau^2/N$, skewness $2/\sqrt N$.
  Identical to the integer TiS model for integer N. N is restricted to
  $N \ge 1$ so that E(0) stays finite (N < 1 would be an integrable
  singularity at t = 0, which least-squares fitting cannot handle).

* **Axial dispersion model** (ADM), Péclet number $Pe = uL/D$,
  space time $\tau = L/u$, two boundary-condition choices (Levenspiel,
  *Chemical Reaction Engineering*, 3rd ed. 1999, ch. 13; Wehner & Wilhelm 1956):

  - ``"open"`` (open-open, flux-averaged outlet), closed form
    $E(\theta) = \sqrt{Pe/(4\pi\theta)}\,\exp[-Pe(1-\theta)^2/(4\theta)]$,
    $\theta = t/\tau$; mean $\tau(1 + 2/Pe)$, variance
    $\tau^2 (2/Pe + 8/Pe^2)$. It is the size-biased inverse-Gaussian
    distribution (mean 1, shape Pe/2), which also gives the skewness used here.
  - ``"closed"`` (closed-closed, Danckwerts conditions), mean $\tau$,
    variance $\tau^2 [2/Pe - 2/Pe^2 (1 - e^{-Pe})]$. E(t) has no closed
    form; it is the inverse of the Wehner–Wilhelm transfer function

    $$
    G(s) = \frac{4q\,e^{Pe/2}}{(1+q)^2 e^{qPe/2} - (1-q)^2 e^{-qPe/2}},
    \quad q = \sqrt{1 + 4 s\tau / Pe}.
    $$

    For Pe < 100 it is inverted numerically with the fixed Talbot method
    (Abate & Valkó 2004, 24 nodes, contour shifted by -Pe/4 so that all poles
    lie on the non-positive real axis, contour radius raised to the saddle
    point Pe/(4θ²)). For Pe >= 100 the first term of the reflection (image)
    expansion of G is inverted in closed form with erfcx (the reflected terms
    arrive after θ ≈ 3 with weight below exp(-Pe/3)); both branches agree to
    better than 1e-10 relative to the peak at Pe = 100–1000 and integrate to 1
    within 1e-12 (see tests/test_rtd_models.py).

* **Interactive mixers with dead zones (Song (2003) Section 2.7, Eq. 2.10-2.16)**:

  Duchesne, Thibault & Bazin (1996), as printed by Song (2003): N cells ("interactive
  mixers") in series; the solids flow from cell i-1 to cell i is k (m_{a,i-1} - m_{a,i})
  (conductance k, 1/s), so at steady state every difference is F/k and, with the discharge
  k m_{a,N} of the last cell, m_{a,j} = (N - j + 1) F/k (Song Eq. 2.10 with
  m_{a,N+1} = 0; the boundary conditions are not printed, notes song.md Section 2.7). In the
  modified Cholette-Cloutier model (Eq. 2.10-2.16) each cell also has a dead zone of mass
  m_{d,i} = m_{a,i} (1 - alpha)/alpha (Eq. 2.16, alpha the active fraction) that exchanges
  only with its own active zone, beta F each way at steady state (Eq. 2.14-2.15 give
  beta_a = beta_d = beta when m_a/(m_a + m_d) = alpha). The tracer obeys the water balances
  Eq. 2.11 and 2.13 with w the tracer fraction; with tau_a = m_a/F and tau_d = m_d/F the
  transfer function of one cell is

      G_i(s) = 1 / (1 + s tau_a + beta s tau_d / (beta + s tau_d)),

  and the vessel's G = prod_i G_i, tau_a = m/k and tau_d = c m/k for m = 1..N,
  c = (1 - alpha)/alpha. With sigma = s/k the product is in closed form,

      prod_m [1 + sigma m + beta sigma c m/(beta + sigma c m)]
          = sigma^N prod_{r in roots} Gamma(N + 1 - r)/Gamma(1 - r)
            / [Gamma(N + 1 + q)/Gamma(1 + q)],   q = beta/(sigma c),

  with r the roots in m of sigma^2 c m^2 + sigma (c + beta + beta c) m + beta (and
  prod_m (1 + sigma m) = sigma^N Gamma(N + 1 + 1/sigma)/Gamma(1 + 1/sigma) when alpha = 1),
  so one evaluation costs the same for any N. E(t) = k g(k t) is inverted with the fixed
  Talbot method (Abate & Valko 2004; all poles lie on the negative real axis) for N <= 20
  and by the damped Fourier series (Dubner & Abate 1968) for narrower curves. Moments from
  the cumulants of ln G, summed over the cells (S_1 = N(N+1)/2, S_2 = N(N+1)(2N+1)/6,
  S_3 = S_1^2):

      mean = (1 + c) S_1/k = N(N+1)/(2 k alpha)      (Song's tau, notes song.md 2.7)
      var  = S_2/k^2 [(1 + c)^2 + 2 c^2/beta]
      mu_3 = S_3/k^3 [2 (1 + c)^3 + 6 (1 + c) c^2/beta + 6 c^3/beta^2]

  (each cell's dead zone is a first-order exchange: mean stay tau_d/beta, the mobile-immobile
  moments of rotarydryer.transport.core_variants.stagnant_core_moments).

These are *reference* models, not Lee's or Ajayi's dryer models (those live in
``rotarydryer.transport``); Lee (2008) l.1351 notes that the closed dispersion
model is close to TiS for N > 15, the classical large-Pe limit being N ≈ Pe/2.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np
from scipy.special import erfcx, gammaln

from .._validation import check_choice, check_finite, check_range

__all__ = [
    "AnalyticMoments",
    "tanks_in_series_e",
    "tanks_in_series_f",
    "tanks_in_series_moments",
    "axial_dispersion_e",
    "axial_dispersion_moments",
    "TanksInSeries",
    "AxialDispersion",
    "DISPERSION_BOUNDARIES",
    "cholette_cloutier_e",
    "cholette_cloutier_moments",
    "CholetteCloutier",
]

DISPERSION_BOUNDARIES = ("closed", "open")
_MAX_TANKS = 1e7
_MAX_PECLET = 1e9


@dataclass(frozen=True)
class AnalyticMoments:
    """Analytic moments of a reference RTD model.

    Fields may be floats or arrays (when the model parameters are arrays).

    Attributes
    ----------
    mean_s : mean residence time (s)
    variance_s2 : variance (s²)
    skewness : standardised skewness μ3/σ³ (dimensionless); ``None`` where no
        closed form is available.
    """

    mean_s: Any
    variance_s2: Any
    skewness: Any = None

    @property
    def std_s(self):
        """Standard deviation (s)."""
        return np.sqrt(self.variance_s2)

    def to_dict(self) -> dict:
        """Plain-dict view (floats/lists), including ``std_s``."""
        d = asdict(self)
        d["std_s"] = self.std_s
        return {k: (np.asarray(v).tolist() if v is not None else None) for k, v in d.items()}


# --------------------------------------------------------------------------- TiS
def _check_tis(tau_s, n_tanks):
    tau = check_range("mean_residence_time_s", tau_s, 0.0, np.inf, unit="s")
    n = check_range("n_tanks", n_tanks, 1.0, _MAX_TANKS, low_inclusive=True, high_inclusive=True)
    return tau, n


def tanks_in_series_e(time_s, mean_residence_time_s, n_tanks):
    r"""Exit-age distribution E(t) (1/s) of N tanks in series.

    Lee (2008) Eq. 2.11 (extended TiS, Martin 2000):
    $E(t) = N^N t^{N-1} e^{-Nt/\tau} / (\Gamma(N)\tau^N)$; E = 0 for t < 0.

    Parameters
    ----------
    time_s : array_like, time since the Dirac injection (s), any real value.
    mean_residence_time_s : array_like, τ (s) > 0.
    n_tanks : array_like, N (-) in [1, 1e7]; need not be an integer.

    Returns
    -------
    ndarray, E(t) in 1/s, broadcast over the arguments.
    """
    t = check_finite("time_s", time_s)
    tau, n = _check_tis(mean_residence_time_s, n_tanks)
    t, tau, n = np.broadcast_arrays(t, tau, n)
    x = np.where(t > 0, t / tau, 1.0)  # dimensionless time θ (dummy 1 where t <= 0)
    with np.errstate(divide="ignore"):
        log_e = n * np.log(n) + (n - 1.0) * np.log(x) - n * x - gammaln(n) - np.log(tau)
    e = np.exp(log_e)
    # t = 0: E = 1/τ for N = 1, 0 for N > 1; t < 0: 0.
    e = np.where(t > 0, e, np.where((t == 0) & (n == 1.0), 1.0 / tau, 0.0))
    return e if e.ndim else float(e)


def tanks_in_series_f(time_s, mean_residence_time_s, n_tanks):
    r"""Cumulative distribution F(t) (-) of N tanks in series.

    Integral of Lee (2008) Eq. 2.11: $F(t) = P(N, N t/\tau)$, the regularised
    lower incomplete gamma function. F = 0 for t <= 0.
    Units and ranges as [`tanks_in_series_e`][rotarydryer.rtd.models.tanks_in_series_e].
    """
    from scipy.special import gammainc

    t = check_finite("time_s", time_s)
    tau, n = _check_tis(mean_residence_time_s, n_tanks)
    f = gammainc(n, np.maximum(t, 0.0) * n / tau)
    return f if np.ndim(f) else float(f)


def tanks_in_series_moments(mean_residence_time_s, n_tanks) -> AnalyticMoments:
    """Analytic moments of N tanks in series (gamma distribution).

    mean = τ, variance = τ²/N, skewness = 2/√N (Lee (2008) Eq. 2.11 is a gamma
    density with shape N and scale τ/N). τ in s, N in [1, 1e7].
    """
    tau, n = _check_tis(mean_residence_time_s, n_tanks)
    tau, n = np.broadcast_arrays(tau, n)
    return AnalyticMoments(
        mean_s=_scalar(tau * 1.0), variance_s2=_scalar(tau**2 / n), skewness=_scalar(2.0 / np.sqrt(n))
    )


# --------------------------------------------------------------------------- ADM
def _check_adm(tau_s, peclet, boundary):
    tau = check_range("space_time_s", tau_s, 0.0, np.inf, unit="s")
    pe = check_range("peclet", peclet, 0.0, _MAX_PECLET, high_inclusive=True)
    check_choice("boundary", boundary, DISPERSION_BOUNDARIES)
    return tau, pe


def _adm_open_theta(theta, pe):
    """Open-open E(θ) (dimensionless), θ > 0 assumed where used."""
    th = np.where(theta > 0, theta, 1.0)
    e = np.sqrt(pe / (4.0 * np.pi * th)) * np.exp(-pe * (1.0 - th) ** 2 / (4.0 * th))
    return np.where(theta > 0, e, 0.0)


def _adm_closed_image(theta, pe):
    """Closed-closed E(θ), first image term inverted in closed form (Pe >= 100)."""
    th = np.where(theta > 0, theta, 1.0)
    c = np.sqrt(pe)
    b = 0.5 * c
    z = b * np.sqrt(th) + c / (2.0 * np.sqrt(th))
    x = erfcx(z)
    f1 = 1.0 / np.sqrt(np.pi * th) - b * x
    f2 = (1.0 + b * c + 2.0 * b * b * th) * x - 2.0 * b * np.sqrt(th / np.pi)
    e = 2.0 * c * (f1 - b * f2) * np.exp(-pe * (1.0 - th) ** 2 / (4.0 * th))
    return np.where(theta > 0, np.maximum(e, 0.0), 0.0)


def _log_shifted_transfer(sig, pe):
    """log of G(σ - Pe/4) * exp(-Pe/2) for the closed-closed ADM (θ units)."""
    a = 0.5 * pe
    q = 2.0 * np.sqrt(sig / pe)
    return np.log(4.0 * q) - a * q - np.log((1.0 + q) ** 2 - (1.0 - q) ** 2 * np.exp(-2.0 * q * a))


def _adm_closed_talbot(theta, pe, nodes: int = 24):
    """Closed-closed E(θ) by the fixed Talbot method on the shifted transform."""
    th = np.where(theta > 0, theta, 1.0)[..., None]
    pe_ = np.asarray(pe, dtype=float)[..., None]
    k = np.arange(1, nodes)
    phi = k * np.pi / nodes
    cot = 1.0 / np.tan(phi)
    r = np.maximum(2.0 * nodes / (5.0 * th), pe_ / (4.0 * th**2))
    s = r * phi * (cot + 1j)
    dsig = phi + (phi * cot - 1.0) * cot
    shift = 0.5 * pe_ - 0.25 * pe_ * th  # exp(Pe/2) factor and the -Pe/4 contour shift
    with np.errstate(over="ignore", invalid="ignore"):
        first = 0.5 * np.exp(r * th + _log_shifted_transfer(r + 0j, pe_) + shift)
        rest = np.sum(
            np.real(np.exp(th * s + _log_shifted_transfer(s, pe_) + shift) * (1.0 + 1j * dsig)),
            axis=-1,
            keepdims=True,
        )
    e = np.real(r / nodes * (first + rest))[..., 0]
    e = np.where(np.isfinite(e), e, 0.0)
    return np.where(theta > 0, np.maximum(e, 0.0), 0.0)


def axial_dispersion_e(time_s, space_time_s, peclet, boundary: str = "closed"):
    r"""Exit-age distribution E(t) (1/s) of the axial dispersion model.

    Parameters
    ----------
    time_s : array_like, time since the Dirac injection (s).
    space_time_s : array_like, τ = L/u (s) > 0. For ``"closed"`` this is the
        mean residence time; for ``"open"`` the mean is τ(1 + 2/Pe).
    peclet : array_like, Pe = uL/D (-), in (0, 1e9].
    boundary : ``"closed"`` (Danckwerts closed-closed, default) or ``"open"``
        (open-open). See the module docstring for the equations and the
        numerical inversion used for ``"closed"`` (Levenspiel 1999 ch. 13).

    Returns
    -------
    ndarray, E(t) in 1/s (0 for t <= 0), broadcast over the arguments.
    """
    t = check_finite("time_s", time_s)
    tau, pe = _check_adm(space_time_s, peclet, boundary)
    t, tau, pe = np.broadcast_arrays(t, tau, pe)
    theta = t / tau
    if boundary == "open":
        e = _adm_open_theta(theta, pe)
    else:
        e = np.zeros(theta.shape)
        hi = pe >= 100.0
        if np.any(hi):
            e[hi] = _adm_closed_image(theta[hi], pe[hi])
        if np.any(~hi):
            e[~hi] = _adm_closed_talbot(theta[~hi], pe[~hi])
    e = e / tau
    return e if e.ndim else float(e)


def axial_dispersion_moments(space_time_s, peclet, boundary: str = "closed") -> AnalyticMoments:
    r"""Analytic moments of the axial dispersion model (Levenspiel 1999 ch. 13).

    * closed-closed: mean τ, variance $\tau^2[2/Pe - 2/Pe^2(1-e^{-Pe})]$
      (van der Laan 1958); third central moment
      $\mu_3/\tau^3 = 12/Pe^2 + 12e^{-Pe}/Pe^2 - 24(1-e^{-Pe})/Pe^3$, the
      third cumulant $-d^3 \ln G/ds^3|_0$ of the Wehner–Wilhelm transfer
      function (derived for this package, not taken from a printed source;
      checked against a Cauchy-integral differentiation of ln G and against
      quadrature of E in tests/test_rtd_models.py).
    * open-open: mean $\tau(1+2/Pe)$, variance $\tau^2(2/Pe + 8/Pe^2)$;
      skewness from the raw moments of the size-biased inverse Gaussian
      (shape λ = Pe/2): $m_k = E[X^{k+1}]$ with
      $E[X^2]=1+1/λ$, $E[X^3]=1+3/λ+3/λ^2$,
      $E[X^4]=1+6/λ+15/λ^2+15/λ^3$.

    τ in s (> 0), Pe dimensionless in (0, 1e9].
    """
    tau, pe = _check_adm(space_time_s, peclet, boundary)
    tau, pe = np.broadcast_arrays(tau, pe)
    if boundary == "closed":
        one_minus_exp = -np.expm1(-pe)
        var_rel = 2.0 / pe - 2.0 / pe**2 * one_minus_exp
        mu3_rel = 12.0 / pe**2 + 12.0 * np.exp(-pe) / pe**2 - 24.0 * one_minus_exp / pe**3
        return AnalyticMoments(
            mean_s=_scalar(tau * 1.0), variance_s2=_scalar(tau**2 * var_rel), skewness=_scalar(mu3_rel / var_rel**1.5)
        )
    il = 2.0 / pe  # 1/λ
    m1 = 1.0 + il
    m2 = 1.0 + 3.0 * il + 3.0 * il**2
    m3 = 1.0 + 6.0 * il + 15.0 * il**2 + 15.0 * il**3
    var = m2 - m1**2  # = 2/Pe + 8/Pe²
    mu3 = m3 - 3.0 * m1 * m2 + 2.0 * m1**3
    return AnalyticMoments(
        mean_s=_scalar(tau * m1), variance_s2=_scalar(tau**2 * var), skewness=_scalar(mu3 / var**1.5)
    )


def _scalar(x):
    x = np.asarray(x, dtype=float)
    return float(x) if x.ndim == 0 else x


# ------------------------------------------------------------------ model objects
@dataclass(frozen=True)
class TanksInSeries:
    """Tanks-in-series model (Lee (2008) Eq. 2.11), τ (s) and N (-) >= 1."""

    mean_residence_time_s: float
    n_tanks: float

    name = "tanks_in_series"
    parameter_names = ("mean_residence_time_s", "n_tanks")

    def __post_init__(self):
        _check_tis(self.mean_residence_time_s, self.n_tanks)

    def e(self, time_s):
        """E(t) in 1/s at ``time_s`` (s)."""
        return tanks_in_series_e(time_s, self.mean_residence_time_s, self.n_tanks)

    def f(self, time_s):
        """F(t) (-) at ``time_s`` (s)."""
        return tanks_in_series_f(time_s, self.mean_residence_time_s, self.n_tanks)

    def moments(self) -> AnalyticMoments:
        return tanks_in_series_moments(self.mean_residence_time_s, self.n_tanks)


@dataclass(frozen=True)
class AxialDispersion:
    """Axial dispersion model, τ = L/u (s), Pe (-), boundary ``closed``/``open``."""

    space_time_s: float
    peclet: float
    boundary: str = "closed"

    name = "axial_dispersion"
    parameter_names = ("space_time_s", "peclet")

    def __post_init__(self):
        _check_adm(self.space_time_s, self.peclet, self.boundary)

    def e(self, time_s):
        """E(t) in 1/s at ``time_s`` (s)."""
        return axial_dispersion_e(time_s, self.space_time_s, self.peclet, self.boundary)

    def moments(self) -> AnalyticMoments:
        return axial_dispersion_moments(self.space_time_s, self.peclet, self.boundary)


# ------------------------------------------------------- Cholette-Cloutier cells

_MAX_CELLS = 100_000
_MAX_EXCHANGE = 1e6
_TALBOT_NODES = 24


def _check_cells(n_cells, conductance_per_s, active_fraction, exchange_ratio):
    n = check_range("n_cells", n_cells, 1.0, _MAX_CELLS, low_inclusive=True, high_inclusive=True)
    if np.any(n != np.round(n)):
        raise ValueError(f"n_cells = {n_cells!r} must be an integer in [1, {_MAX_CELLS}] "
                         "(Song (2003) Section 2.7: N takes integer values)")
    k = check_range("conductance_per_s", conductance_per_s, 0.0, np.inf, unit="1/s")
    a = check_range("active_fraction", active_fraction, 0.0, 1.0, high_inclusive=True)
    b = check_range("exchange_ratio", exchange_ratio, 0.0, _MAX_EXCHANGE, high_inclusive=True)
    return n, k, a, b


def _stable_roots(A, B, C):
    """Both roots of A x^2 + B x + C (complex arrays, A != 0), without cancellation."""
    d = np.sqrt(B * B - 4.0 * A * C)
    d = np.where(np.real(np.conj(B) * d) >= 0.0, d, -d)
    q = -0.5 * (B + d)
    return q / A, C / q


def _cells_log_product(sig, n, c, beta):
    """log prod_{m=1}^{n} [1 + sig m + beta sig c m/(beta + sig c m)] (mod 2 pi i), vectorised."""
    from scipy.special import loggamma

    base = n * np.log(sig)
    plain = base + loggamma(n + 1.0 + 1.0 / sig) - loggamma(1.0 + 1.0 / sig)   # alpha = 1: prod (1 + sig m)
    dead = c > 0.0
    if not np.any(dead):
        return plain
    cc = np.where(dead, c, 1.0)
    A = sig * sig * cc
    B = sig * (cc + beta + beta * cc)
    r1, r2 = _stable_roots(A, B, beta + 0j)
    q = beta / (sig * cc)
    with_dead = (base + loggamma(n + 1.0 - r1) - loggamma(1.0 - r1) + loggamma(n + 1.0 - r2)
                 - loggamma(1.0 - r2) - loggamma(n + 1.0 + q) + loggamma(1.0 + q))
    return np.where(dead, with_dead, plain)


def _talbot(log_transfer, theta, nodes: int = _TALBOT_NODES):
    """f(theta) for theta > 0 from log F(sigma) by the fixed Talbot method (Abate & Valko 2004)."""
    th = theta[..., None]
    j = np.arange(1, nodes)
    phi = j * np.pi / nodes
    cot = 1.0 / np.tan(phi)
    r = 2.0 * nodes / (5.0 * th)
    s = r * phi * (cot + 1j)
    dsig = phi + (phi * cot - 1.0) * cot
    with np.errstate(over="ignore", invalid="ignore"):
        first = 0.5 * np.exp(r * th + log_transfer(r + 0j))
        rest = np.sum(np.real(np.exp(th * s + log_transfer(s)) * (1.0 + 1j * dsig)), axis=-1, keepdims=True)
    f = np.real(r / nodes * (first + rest))[..., 0]
    return np.where(np.isfinite(f), f, 0.0)


#: largest N inverted by the fixed Talbot method; more cells (a narrow curve far from t = 0, where
#: the Talbot contour passes close to the dense poles -1/m: it fails beyond N ~ 60) by the Fourier
#: series
_TALBOT_MAX_CELLS = 20
#: damping a P of the Fourier-series inversion (aliasing e^{-aP}; the rounding error of F grows by
#: e^{a theta} <= e^{aP/4} at the latest time, P = 4 max(theta))
_FOURIER_DAMPING = 24.0
#: the Fourier series stops where |G(i omega)| of the cells without dead zones < exp(-this)
_FOURIER_CUTOFF = 40.0


def _fourier_inverse(log_transfer, theta, n):
    """f(theta) for theta > 0 (1-D) from log F(sigma) by the damped Fourier series (Dubner &
    Abate 1968): f = e^{a theta}/P [F(a) + 2 Re sum_j F(a + i w_j) e^{i w_j theta}],
    w_j = 2 pi j/P, P = 4 max(theta), a = _FOURIER_DAMPING/P; the series runs to the
    frequency where prod_m |1 + i w m|^-1 (a bound of |F|, dead zones only lower it) falls
    below exp(-_FOURIER_CUTOFF)."""
    P = 4.0 * float(np.max(theta))
    a = _FOURIER_DAMPING / P
    lo, hi = 0.0, 1.0
    while 0.5 * np.real(_cells_log_product(np.array([1j * hi]), n, 0.0, 1.0))[0] * 2.0 < _FOURIER_CUTOFF:
        lo, hi = hi, 2.0 * hi
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        if np.real(_cells_log_product(np.array([1j * mid]), n, 0.0, 1.0))[0] < _FOURIER_CUTOFF:
            lo = mid
        else:
            hi = mid
    J = int(math.ceil(hi * P / (2.0 * np.pi))) + 1
    w = 2.0 * np.pi * np.arange(1, J + 1) / P
    g0 = float(np.real(np.exp(log_transfer(np.array([a + 0j])))[0]))
    gj = np.exp(log_transfer(a + 1j * w))
    out = np.empty(theta.shape)
    for i in range(0, theta.size, 2048):          # bounded memory: (2048, J) at a time
        th = theta[i:i + 2048]
        ph = th[:, None] * w[None, :]
        series = np.cos(ph) @ gj.real - np.sin(ph) @ gj.imag
        out[i:i + 2048] = np.exp(a * th) / P * (g0 + 2.0 * series)
    return out


def _cells_curve(t, n, k, a, b, log_input=None, cumulative=False):
    """E(t) (or the outlet response to an input with log transfer ``log_input(s)``, or with
    ``cumulative`` the distribution F(t), transform G(s)/s) of the cell model for flat float
    arrays of equal length; 0 for t <= 0 (except E(0) = k for N = 1)."""
    out = np.where((t == 0) & (n == 1) & (log_input is None) & (not cumulative), k, 0.0)
    pos = t > 0
    if not np.any(pos):
        return out
    keys = np.stack([n[pos], k[pos], a[pos], b[pos]], axis=1)
    uniq, inv = np.unique(keys, axis=0, return_inverse=True)
    inv = np.ravel(inv)
    vals = np.empty(int(pos.sum()))
    theta = t[pos] * k[pos]
    for j, (nj, kj, aj, bj) in enumerate(uniq):
        sel = inv == j
        cj = (1.0 - aj) / aj

        def log_g(sig, nj=nj, cj=cj, bj=bj, kj=kj):
            lg = -_cells_log_product(sig, nj, cj, bj)
            if cumulative:
                lg = lg - np.log(sig)
            return lg if log_input is None else lg + log_input(sig * kj)

        th = theta[sel]
        g = _talbot(log_g, th) if nj <= _TALBOT_MAX_CELLS else _fourier_inverse(log_g, th, nj)
        vals[sel] = np.clip(g, 0.0, 1.0) if cumulative else np.maximum(g, 0.0) * kj
    out[pos] = vals
    return out


def cholette_cloutier_e(time_s, n_cells, conductance_per_s, active_fraction=1.0, exchange_ratio=1.0):
    r"""Exit-age distribution E(t) (1/s) of N interactive mixers with dead zones.

    Song (2003) Eq. 2.10-2.16 (modified Cholette-Cloutier model of Duchesne et al. 1996) at
    steady state: active masses m_{a,j} = (N - j + 1) F/k (Eq. 2.10), dead zones
    m_d = m_a (1 - alpha)/alpha (Eq. 2.16) exchanging beta F each way (Eq. 2.12-2.15),
    tracer by Eq. 2.11 and 2.13; E(t) by inversion of the closed-form transfer function
    (see the module notes): the fixed Talbot method (Abate & Valko 2004) for N <= 20, the
    damped Fourier series (Dubner & Abate 1968) for more cells (narrow curves), both within
    1e-8 of the peak of the exact (matrix-exponential) solution (tests/test_rtd_cells.py).
    ``active_fraction = 1`` is Song's first model (interactive mixers without dead zones,
    2 parameters N and k).

    Parameters
    ----------
    time_s : array_like, time since the Dirac injection (s).
    n_cells : array_like of integers, N (-) in [1, 1e5].
    conductance_per_s : array_like, k (1/s) > 0.
    active_fraction : array_like, alpha (-) in (0, 1].
    exchange_ratio : array_like, beta (-) in (0, 1e6]: steady exchange flow / cell feed
        (ignored when alpha = 1).

    Returns
    -------
    ndarray, E(t) in 1/s (0 for t < 0; E(0) = k for N = 1, else 0), broadcast over the
    arguments.
    """
    t = check_finite("time_s", time_s)
    n, k, a, b = _check_cells(n_cells, conductance_per_s, active_fraction, exchange_ratio)
    t, n, k, a, b = np.broadcast_arrays(t, n, k, a, b)
    shape = t.shape
    e = _cells_curve(*(np.ravel(x).astype(float) for x in (t, n, k, a, b))).reshape(shape)
    return e if e.ndim else float(e)


def cholette_cloutier_moments(n_cells, conductance_per_s, active_fraction=1.0, exchange_ratio=1.0) -> AnalyticMoments:
    r"""Analytic moments of [`cholette_cloutier_e`][rotarydryer.rtd.models.cholette_cloutier_e] (Song (2003) Eq. 2.10-2.16).

    mean = N(N+1)/(2 k alpha), variance = S_2/k^2 [(1+c)^2 + 2c^2/beta], third central
    moment S_3/k^3 [2(1+c)^3 + 6(1+c)c^2/beta + 6c^3/beta^2] with c = (1 - alpha)/alpha,
    S_2 = N(N+1)(2N+1)/6, S_3 = [N(N+1)/2]^2 (cumulants of the cell transfer functions,
    derived for this package). Arguments broadcast; units as [`cholette_cloutier_e`][rotarydryer.rtd.models.cholette_cloutier_e].
    """
    n, k, a, b = _check_cells(n_cells, conductance_per_s, active_fraction, exchange_ratio)
    n, k, a, b = np.broadcast_arrays(n, k, a, b)
    c = (1.0 - a) / a
    s1 = n * (n + 1.0) / 2.0
    s2 = n * (n + 1.0) * (2.0 * n + 1.0) / 6.0
    s3 = s1 * s1
    mean = (1.0 + c) * s1 / k
    var = s2 / k**2 * ((1.0 + c) ** 2 + 2.0 * c * c / b)
    mu3 = s3 / k**3 * (2.0 * (1.0 + c) ** 3 + 6.0 * (1.0 + c) * c * c / b + 6.0 * c**3 / b**2)
    return AnalyticMoments(mean_s=_scalar(mean), variance_s2=_scalar(var), skewness=_scalar(mu3 / var**1.5))


@dataclass(frozen=True)
class CholetteCloutier:
    """N interactive mixers with dead zones (Song (2003) Eq. 2.10-2.16): N (-, integer),
    k (1/s), alpha (-) in (0, 1], beta (-) > 0. ``active_fraction = 1``: Song's first
    model (interactive mixers, no dead zone)."""

    n_cells: int
    conductance_per_s: float
    active_fraction: float = 1.0
    exchange_ratio: float = 1.0

    name = "cholette_cloutier"
    parameter_names = ("conductance_per_s", "active_fraction", "exchange_ratio")

    def __post_init__(self):
        _check_cells(self.n_cells, self.conductance_per_s, self.active_fraction, self.exchange_ratio)

    def e(self, time_s):
        """E(t) in 1/s at ``time_s`` (s)."""
        return cholette_cloutier_e(time_s, self.n_cells, self.conductance_per_s, self.active_fraction,
                                   self.exchange_ratio)

    def moments(self) -> AnalyticMoments:
        return cholette_cloutier_moments(self.n_cells, self.conductance_per_s, self.active_fraction,
                                         self.exchange_ratio)

    def cdf(self, time_s):
        """F(t) (-), the fraction of a Dirac injection out by ``time_s`` (s): inverse of G(s)/s."""
        return self._curve(check_finite("time_s", time_s), cumulative=True)

    def _curve(self, t, **kw):
        """`_cells_curve` of this model's parameters at the times ``t`` (same shape; a float for
        a scalar)."""
        flat = np.ravel(t).astype(float)
        par = [np.full(flat.shape, float(v)) for v in (self.n_cells, self.conductance_per_s,
                                                       self.active_fraction, self.exchange_ratio)]
        y = _cells_curve(flat, *par, **kw).reshape(np.shape(t))
        return y if y.ndim else float(y)

    def outlet(self, time_s, pulse):
        """Outlet response (1/s) at ``time_s`` (s after the input start) to a normalised input
        ``pulse`` ([`rotarydryer.rtd.pulse_input`][rotarydryer.rtd.pulse_input]), an exact convolution for a Dirac or
        rectangular input of duration d: [F(t) - F(t - d)]/d ([`cdf`][rotarydryer.rtd.models.CholetteCloutier.cdf]) for N <= 20, the
        inverse of G(s) (1 - e^{-sd})/(sd) for more cells; other inputs (or d below 1e-3 of
        the SD) by quadrature ([`rotarydryer.rtd.convolve_rtd`][rotarydryer.rtd.convolve_rtd])."""
        from .pulses import convolve_rtd

        t = check_finite("time_s", time_s)
        if pulse.kind == "dirac":
            return self.e(t)
        d = float(pulse.duration_s)
        if pulse.kind != "rectangular" or not d > 1e-3 * float(self.moments().std_s):
            return convolve_rtd(self.e, t, pulse)
        if self.n_cells <= _TALBOT_MAX_CELLS:
            return (self.cdf(t) - self.cdf(t - d)) / d

        def log_input(s):
            z = s * d
            return np.log(-np.expm1(-z) / z)

        return self._curve(t, log_input=log_input)
