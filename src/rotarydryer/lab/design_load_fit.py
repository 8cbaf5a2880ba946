"""Design load from loading experiments: segmented regression with a plateau (Ajayi (2011) App. D-E).

Ajayi (2011) section 4.4 photographed his pilot drum at stepwise increasing loadings and
measured the area of the first unloading flight (FUF). The FUF area rises with the
loading until the flight is full at the 9 o'clock position, then stays constant; the
loading at the break is the **design load**. He fitted D'Errico's SLM spline (Appendix D:
``slmengine(x, y, 'knots', 3, 'rightslope', 0, 'degree', 1, 'interiorknots', 'free')``),
i.e. a continuous piecewise-linear function with one free interior knot and zero slope
to its right:

    area(x) = c + a * min(x, B)          (a: left slope, B: break point = design load)

which is what [`fit_break_point`][rotarydryer.lab.design_load_fit.fit_break_point] fits, by exact least squares (the residual sum of
squares is profiled over B, linear in a and c for fixed B).

Confidence interval of the break point
--------------------------------------
Ajayi (2011) Appendix E writes the break as ``B = (C_a - C_b)/(A_b - A_a) = G/H``
(Eq. E4) from the left line ``A_b x + C_b`` (E1) and the plateau ``C_a`` (E2, A_a = 0)
and propagates ``SE_B = B sqrt((SE_G/G)^2 + (SE_H/H)^2)`` (E5) with, as printed,
``SE_G = sqrt((E_ca/C_a)^2 + (E_cb/C_b)^2)`` (E6) and
``SE_H = sqrt((E_Ab/A_b)^2 + (E_Aa/A_a)^2)`` (E7). E6/E7 combine *relative* errors of
the terms of a *difference* (wrong for a difference; E7 contains 0/0 since A_a = 0) and
ignore the strong correlation between the slope and intercept of the left line. The
intervals available here (``methods=``):

* ``"delta"`` (default): delta method from the Gauss-Newton covariance of (c, a, B) of the
  continuous hinge fit; Student-t with n - 3 degrees of freedom.
* ``"profile"``: profile-likelihood (F-test) interval
  ``{B : RSS(B) <= RSS_min (1 + F(1, n-3; conf)/(n - 3))}``; asymmetric, better when
  few points lie on one side of the break. Bounds that do not close inside the data
  range are reported at the data range limit (``profile_closed`` tells).
* ``"ajayi_corrected"``: Ajayi's construction (separate left line and plateau mean,
  split at the fitted break) with the propagation done correctly:
  ``Var B = [Var C_a + Var C_b + 2 B Cov(A_b, C_b) + B^2 Var A_b] / A_b^2``; normal
  quantile (Ajayi used 1.96).
* ``"appendix_e"``: the printed E5-E7 in their only computable reading (relative
  errors of C_a and C_b for SE_G/G; SE_H/H = E_Ab/A_b, the 0/0 term dropped; 1.96).
  For comparison only: it is wrong.

The raw loading-area points behind Ajayi's Table 4.11 are not published (the notes,
section 3.4). [`mimic_ajayi_series`][rotarydryer.lab.design_load_fit.mimic_ajayi_series] generates synthetic series whose plateau and
break point are Table 4.11's and whose noise and slope reproduce his printed CIs, so
that the fit can be checked against his design loads.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from .._validation import check_choice, check_finite, check_positive, check_range
from ..estimation.uncertainty import linearised_uncertainty

__all__ = ["CI_METHODS", "BreakPointFit", "hinge", "fit_break_point", "read_design_rows", "synthetic_loading_series",
           "mimic_ajayi_series", "ajayi_table_4_11"]

CI_METHODS = ("delta", "profile", "ajayi_corrected", "appendix_e")


#: the largest loading or area the fit takes (sums of squares of larger values overflow; a unit error)
MAX_VALUE = 1e100


def hinge(loading, break_point, slope, intercept):
    """Continuous linear-plateau model ``intercept + slope * min(loading, break_point)``.

    Units follow the inputs (Ajayi: loading in kg, area in cm^2; slope in area per kg).
    Broadcasts over all arguments. Ajayi (2011) Appendix D (SLM, degree 1, 3 knots,
    right slope 0).
    """
    x = check_finite("loading", loading)
    b = check_finite("break_point", break_point)
    a = check_finite("slope", slope)
    c = check_finite("intercept", intercept)
    return c + a * np.minimum(x, b)


@dataclass(frozen=True)
class BreakPointFit:
    """Result of [`fit_break_point`][rotarydryer.lab.design_load_fit.fit_break_point].

    ``break_point`` (the design load, loading units), ``slope`` (area per loading unit),
    ``intercept`` and ``plateau`` (area units); ``ci``/``stderr`` per method
    (``stderr`` is None for the profile interval); ``residual_sd``, ``n``, ``rss``.
    """

    break_point: float
    slope: float
    intercept: float
    plateau: float
    plateau_ci: tuple
    ci: dict
    stderr: dict
    residual_sd: float
    rss: float
    n: int
    n_left: int
    n_right: int
    confidence: float
    profile_closed: tuple
    covariance: np.ndarray = field(repr=False)
    loading: np.ndarray = field(repr=False)
    area: np.ndarray = field(repr=False)

    def predict(self, loading):
        """Fitted area at ``loading``."""
        return hinge(loading, self.break_point, self.slope, self.intercept)


def _rss_at(x, y, B):
    """Vectorised over B: least-squares (a, c) and RSS for y ~ c + a min(x, B)."""
    B = np.atleast_1d(B)[:, None]
    z = np.minimum(x[None, :], B)
    zm = z.mean(1, keepdims=True)
    ym = y.mean()
    szz = ((z - zm) ** 2).sum(1)
    szy = ((z - zm) * (y - ym)).sum(1)
    with np.errstate(invalid="ignore", divide="ignore"):
        a = np.where(szz > 0, szy / szz, 0.0)
    c = ym - a * zm[:, 0]
    res = y[None, :] - c[:, None] - a[:, None] * z
    return a, c, (res**2).sum(1)


def fit_break_point(loading, area, *, confidence: float = 0.95, methods=CI_METHODS,
                    min_left: int = 2, min_right: int = 2) -> BreakPointFit:
    """Fit Ajayi's linear-plateau model (Appendix D) and the break point's confidence intervals.

    Parameters
    ----------
    loading : array_like
        Drum loadings (kg), one per photograph (repeats allowed).
    area : array_like
        Area of the first unloading flight (cm^2 or m^2) for each photograph.
    confidence : float
        Confidence level of the intervals (0.95 = Ajayi's "95 %").
    methods : iterable of str
        Interval methods, from `CI_METHODS` (see the module notes).
    min_left, min_right : int
        Minimum number of *distinct* loadings on each side of the break.
    """
    from scipy.optimize import brentq, minimize_scalar
    from scipy.stats import f as f_dist
    from scipy.stats import norm

    x = check_finite("loading", loading).ravel()
    y = check_finite("area", area).ravel()
    if x.size != y.size:
        raise ValueError(f"loading and area must have the same length, got {x.size} and {y.size}")
    for what, v in (("loading", x), ("area", y)):     # their squares and products stay finite
        if v.size and float(np.max(np.abs(v))) > MAX_VALUE:
            raise ValueError(f"{what} reaches {float(np.max(np.abs(v))):g}; the allowed range is [0, {MAX_VALUE:g}] "
                             "(the break point does not depend on the unit: rescale it)")
    conf = float(check_range("confidence", confidence, 0.0, 1.0))
    methods = tuple(methods)
    for m in methods:
        check_choice("methods", m, CI_METHODS)
    ux = np.unique(x)
    if ux.size < min_left + min_right or x.size < 5:
        raise ValueError(
            f"loading has {ux.size} distinct values ({x.size} points); at least "
            f"{min_left + min_right} distinct loadings and 5 points are needed"
        )
    n = x.size
    lo_b, hi_b = ux[min_left - 1], ux[-min_right]  # break between these keeps enough points each side
    # profile RSS on a grid, refine with a bounded scalar search in the best bracket
    grid = np.unique(np.concatenate([np.linspace(lo_b, hi_b, 401), ux[(ux >= lo_b) & (ux <= hi_b)]]))
    _, _, rss = _rss_at(x, y, grid)
    k = int(np.argmin(rss))
    a_lo, a_hi = grid[max(k - 1, 0)], grid[min(k + 1, grid.size - 1)]
    if a_hi > a_lo:
        r = minimize_scalar(lambda b: float(_rss_at(x, y, b)[2][0]), bounds=(a_lo, a_hi), method="bounded",
                            options={"xatol": 1e-10 * max(1.0, abs(hi_b))})
        B = float(r.x) if r.fun <= rss[k] else float(grid[k])
    else:
        B = float(grid[k])
    a_arr, c_arr, rss_arr = _rss_at(x, y, B)
    a, c, rss_min = float(a_arr[0]), float(c_arr[0]), float(rss_arr[0])
    if not a > 0:
        raise ValueError(
            f"the fitted left slope is {a:g} (area per loading unit): the area does not rise before a "
            "plateau, so there is no break point to estimate"
        )
    dof = n - 3
    if dof < 1:
        raise ValueError("at least 4 points are needed for three parameters and a residual variance")
    # a plateau at all: does the break fit better than one straight line through every point? An F-test of the
    # nested models (3 against 2 parameters; approximate: the break is not identified under the straight line,
    # Davies (1987)). Points on an exact line are refused; a break not significant at the interval's confidence
    # with fewer than 3 loadings after it (a straight line's fit puts the break at the last loadings) is a warning.
    # Series with Ajayi's scatter (`mimic_ajayi_series`) have 3-7 loadings on the plateau; 2 in 45 are not
    # significant there (p up to 0.3): his breaks are weakly defined, not absent
    line = np.polyfit(x, y, 1)
    rss_line = float(np.sum((y - np.polyval(line, x)) ** 2))
    f_stat = (rss_line - rss_min) / (rss_min / dof) if rss_min > 0.0 else (math.inf if rss_line > 0.0 else 0.0)
    p_line = 1.0 if not f_stat > 0 else float(f_dist.sf(f_stat, 1, dof))
    rises = (f"the area still rises by {line[0]:.4g} per loading unit up to the largest loading, {float(ux[-1]):g}: "
             "the flight may not have been loaded to its design load; add loadings beyond it")
    if rss_line <= 1e-12 * float(np.sum((y - y.mean()) ** 2)):
        raise ValueError(f"no plateau: the points lie on a straight line; {rises}")
    on_plateau = int(np.sum(ux > B))
    if p_line > 1.0 - conf and on_plateau < 3:
        warnings.warn(f"no plateau to speak of: the break leaves {on_plateau} loading(s) after it, and a straight line "
                      f"fits the area against the loading almost as well (F-test p = {p_line:.2g} against "
                      f"{1.0 - conf:.2g}); {rises}", RuntimeWarning, stacklevel=2)
    s2 = rss_min / dof
    unc = linearised_uncertainty(_hinge_jacobian(x, B, a), dof=dof, residual_variance=s2, confidence=conf)
    cov, tq = unc.covariance, unc.t_quantile
    zq = float(norm.ppf(0.5 + conf / 2.0))
    plateau = c + a * B
    se_plateau = unc.delta_se([1.0, B, a])
    ci, se = {}, {}
    closed = (True, True)
    left = x <= B
    right = ~left
    for m in methods:
        if m == "delta":
            seB = float(unc.std_errors[2])
            ci[m] = (B - tq * seB, B + tq * seB)
            se[m] = seB
        elif m == "profile":
            thr = rss_min * (1.0 + float(f_dist.ppf(conf, 1, dof)) / dof)

            def h(b):
                return float(_rss_at(x, y, b)[2][0]) - thr

            lo_lim, hi_lim = float(ux[0]), float(ux[-1])
            lo = brentq(h, lo_lim, B) if h(lo_lim) > 0 else lo_lim
            hi = brentq(h, B, hi_lim) if h(hi_lim) > 0 else hi_lim
            closed = (h(lo_lim) > 0, h(hi_lim) > 0)
            ci[m] = (lo, hi)
            se[m] = None
        else:  # Ajayi's construction: separate left line and plateau mean
            if left.sum() < 3 or right.sum() < 2:
                warnings.warn(f"the {m!r} interval needs >= 3 points before the break and >= 2 on the plateau "
                              f"(n_left = {int(left.sum())}, n_right = {int(right.sum())}); it is not available - "
                              "use 'delta' or 'profile'", RuntimeWarning, stacklevel=2)
                ci[m] = (math.nan, math.nan)
                se[m] = math.nan
                continue
            X = np.column_stack([np.ones(left.sum()), x[left]])
            coef, *_ = np.linalg.lstsq(X, y[left], rcond=None)
            covl = linearised_uncertainty(X, y[left] - X @ coef, max(left.sum() - 2, 1), inverse="inv",
                                          singular_rtol=0.0).covariance
            Cb, Ab = float(coef[0]), float(coef[1])
            yr = y[right]
            Ca = float(yr.mean())
            var_ca = float(yr.var(ddof=1)) / yr.size
            Bq = (Ca - Cb) / Ab  # Eq. E4
            if m == "ajayi_corrected":
                var = (var_ca + covl[0, 0] + 2.0 * Bq * covl[0, 1] + Bq * Bq * covl[1, 1]) / Ab**2
                seB = math.sqrt(max(var, 0.0))
            else:  # "appendix_e": printed E5-E7, computable reading
                rel_g = math.sqrt(var_ca / Ca**2 + covl[0, 0] / Cb**2)
                rel_h = math.sqrt(covl[1, 1]) / abs(Ab)
                seB = abs(Bq) * math.sqrt(rel_g**2 + rel_h**2)
            ci[m] = (Bq - zq * seB, Bq + zq * seB)
            se[m] = seB
    return BreakPointFit(
        break_point=B, slope=a, intercept=c, plateau=plateau,
        plateau_ci=(plateau - tq * se_plateau, plateau + tq * se_plateau), ci=ci, stderr=se,
        residual_sd=math.sqrt(s2), rss=rss_min, n=n, n_left=int(left.sum()), n_right=int(right.sum()),
        confidence=conf, profile_closed=closed, covariance=cov, loading=x, area=y,
    )


def synthetic_loading_series(design_load: float, plateau_area: float, *, slope: float, noise_sd: float,
                             loadings=None, photos_per_loading: int = 5, seed=None):
    """Synthetic (loading, FUF area) points: the linear-plateau model plus Gaussian noise.

    ``design_load`` (kg) is the break, ``plateau_area`` the saturated FUF area (cm^2),
    ``slope`` (cm^2/kg) the left slope, ``noise_sd`` (cm^2) the scatter per photograph.
    ``loadings`` (kg) default to 11 levels from 0.55 to 1.55 x the design load;
    ``photos_per_loading`` repeats each (Ajayi averaged 5 photographs per condition,
    Tables 4.8-4.10). Returns ``(loading, area)`` arrays.
    """
    B = float(check_positive("design_load", design_load, "kg"))
    P = float(check_finite("plateau_area", plateau_area))
    a = float(check_positive("slope", slope))
    sd = float(check_range("noise_sd", noise_sd, 0.0, math.inf, low_inclusive=True))
    if isinstance(photos_per_loading, bool) or int(photos_per_loading) != photos_per_loading or photos_per_loading < 1:
        raise ValueError(f"photos_per_loading = {photos_per_loading!r} must be an integer >= 1")
    lv = np.linspace(0.55 * B, 1.55 * B, 11) if loadings is None else check_positive("loadings", loadings, "kg").ravel()
    x = np.repeat(lv, int(photos_per_loading))
    rng = np.random.default_rng(seed)
    y = hinge(x, B, a, P - a * B) + sd * rng.standard_normal(x.size)
    return x, y


def _hinge_jacobian(x, B, a):
    """Jacobian of ``c + a min(x, B)`` with respect to (c, a, B), shape (n, 3)."""
    return np.column_stack([np.ones(x.size), np.minimum(x, B), np.where(x > B, a, 0.0)])


def _design_matrix_se(x, B, a):
    """Delta-method SE of B and of the plateau for unit residual SD."""
    unc = linearised_uncertainty(_hinge_jacobian(x, B, a), sigma_known=True)
    return float(unc.std_errors[2]), unc.delta_se([1.0, B, a])


def mimic_ajayi_series(design_load: float, design_load_ci: float, plateau_area: float, plateau_ci: float, *,
                       loadings=None, photos_per_loading: int = 5, seed=None):
    """Synthetic series mimicking one row of Ajayi (2011) Table 4.11.

    The break is the design load (kg) and the plateau the FUF area (cm^2); the noise SD
    is set so that the plateau's 95 % half-width equals ``plateau_ci`` (cm^2), and the
    left slope so that the delta-method 95 % half-width of the break equals
    ``design_load_ci`` (kg), both for the sampling design used (see
    [`synthetic_loading_series`][rotarydryer.lab.design_load_fit.synthetic_loading_series]). Returns ``(loading, area, truth)`` with ``truth``
    a dict of ``design_load``, ``plateau``, ``slope``, ``noise_sd``.
    """
    B = float(check_positive("design_load", design_load, "kg"))
    ciB = float(check_positive("design_load_ci", design_load_ci, "kg"))
    ciP = float(check_positive("plateau_ci", plateau_ci))
    lv = np.linspace(0.55 * B, 1.55 * B, 11) if loadings is None else check_positive("loadings", loadings, "kg").ravel()
    x = np.repeat(lv, int(photos_per_loading))
    # With unit noise, SE(plateau) does not depend on the slope a and SE(B) = SE(B; a=1)/a
    # exactly (the B column of the Jacobian is a * [x > B]), so both follow in closed form.
    seB1, seP1 = _design_matrix_se(x, B, 1.0)
    sd = ciP / (1.96 * seP1)
    a = 1.96 * sd * seB1 / ciB
    xs, ys = synthetic_loading_series(B, plateau_area, slope=a, noise_sd=sd, loadings=lv,
                                      photos_per_loading=photos_per_loading, seed=seed)
    return xs, ys, {"design_load": B, "plateau": float(plateau_area), "slope": a, "noise_sd": sd}


def ajayi_table_4_11() -> list[dict]:
    """Rows of Ajayi (2011) Table 4.11 (shipped ``ajayi_design_load_pilot.csv``) as floats.

    Keys: rpm, fluid_wt_pct, dyn_angle_of_repose_deg, angle_ci, design_load_kg,
    design_load_ci_kg, FUF_area_cm2, FUF_area_ci_cm2 (all +/- are 95 % CIs).
    """
    from ..published import read_published_csv

    keys = ("rpm", "fluid_wt_pct", "dyn_angle_of_repose_deg", "angle_ci", "design_load_kg",
            "design_load_ci_kg", "FUF_area_cm2", "FUF_area_ci_cm2")
    return [{k: float(r[k]) for k in keys} for r in read_published_csv("ajayi_design_load_pilot.csv")]


def read_design_rows(numbered_lines, name: str, loading_column: str = "loading_kg",
                     area_column: str = "FUF_area_cm2", group_column: Optional[str] = None) -> dict:
    """{group: [(loading, area), ...]} from the numbered lines of a design-load CSV (one row per
    photograph; ``rotarydryer lab design-load``): from `rotarydryer.rtd._datafile.data_lines`
    (a file) or `text_lines` (text in memory). At most
    200 000 rows; errors name ``name``, the line and the column (and the command-line option)."""
    from ..rtd._datafile import MAX_DATA_ROWS, csv_rows, fmt, parse_number, too_many_rows

    header = None
    groups: dict = {}
    n = 0
    for k, row in csv_rows(numbered_lines, name):
        if header is None:
            header = [h.strip() for h in row]
            for opt, col in (("--loading-column", loading_column), ("--area-column", area_column),
                             ("--group-column", group_column)):
                if col is not None and col not in header:
                    raise ValueError(f"{name} line {k}: no column {col!r} ({opt}); columns are {', '.join(header)}")
                if col is not None and header.count(col) > 1:     # the first was used silently (found by fuzzing)
                    raise ValueError(f"{name} line {k}: the header names {col!r} ({opt}) {header.count(col)} times; "
                                     "one column per quantity")
            il, ia = header.index(loading_column), header.index(area_column)
            ig = header.index(group_column) if group_column else None
            continue
        if len(row) != len(header):
            raise ValueError(f"{name} line {k}: {len(row)} columns, expected {len(header)} ({', '.join(header)})")
        n += 1
        if n > MAX_DATA_ROWS:
            raise too_many_rows(name, k, MAX_DATA_ROWS)
        x = parse_number(row[il], name, k, loading_column)
        y = parse_number(row[ia], name, k, area_column)
        if x < 0:
            raise ValueError(f"{name} line {k}: {loading_column} = {fmt(x)} is negative; a drum loading is >= 0")
        if y < 0:
            raise ValueError(f"{name} line {k}: {area_column} = {fmt(y)} is negative; an area is >= 0")
        groups.setdefault(row[ig].strip() if ig is not None else "all", []).append((x, y))
    if header is None:
        raise ValueError(f"{name}: empty file; expected a header line with {loading_column} and {area_column}")
    if not groups:
        raise ValueError(f"{name}: no data rows after the header")
    return groups
