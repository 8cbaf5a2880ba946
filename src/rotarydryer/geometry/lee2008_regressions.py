r"""Lee (2008) regression surrogates of the geometric flight-unloading model.

Lee (2008) could not call his geometric unloading model (Ch. 4) from gPROMS, so he
fitted polynomial regressions to it over a grid of dynamic angle of repose
$\phi$ and flight loading factor $f$ (Lee (2008) Eq. 4.24-4.28; the
full-precision coefficients are those of the gPROMS Geometry model, Appendix I,
source lines 12152-12249 of ``000_fc0990cb8ea413f0.txt``).  They are valid
**only for the CSR Invicta Mill dryer No. 2 flights** (R = 2.5 m, s1 = 0.195 m,
s2 = 0.183 m, alpha1 = 90 deg, alpha2 = 117 deg, 28 flights); the fitted range of
phi and f is not stated (the class accepts 20-70 deg).

The coefficients are embedded below (they are short and never change); each
block cites its source line.  The same numbers are in
``/work/shared/data/lee_gproms_geometry_regressions.csv``.

The class implements the "cell geometry model" interface used by
[`rotarydryer.transport`][rotarydryer.transport] (shared with the exact
``rotarydryer.geometry.FlightedDrum``): [`cascade`][rotarydryer.geometry.lee2008_regressions.Lee2008Regressions.cascade],
[`design_load_area`][rotarydryer.geometry.lee2008_regressions.Lee2008Regressions.design_load_area] and [`loading_factor`][rotarydryer.geometry.lee2008_regressions.Lee2008Regressions.loading_factor].
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from .._validation import check_choice, check_positive, check_range, describe
from .flights import TwoSectionFlight

__all__ = [
    "Lee2008Regressions",
    "CascadeSummary",
    "PASSIVE_TIME_BRANCHES",
    "invicta_tip_radius",
]

from .unloading import CascadeSummary

#: Names of the two readings of the passive (flight) time, see :meth:`Lee2008Regressions.cascade`.
PASSIVE_TIME_BRANCHES = ("eq3.4", "lee2008_ch7")

# --- coefficients (Lee (2008) Appendix I, Geometry model) -------------------------
# Terms: 1, phi, phi^2, phi^3, f, f^2, f^3, phi f, phi f^2, phi^2 f, phi^2 f^2
# Eq. 4.24, mass-averaged fall height "mafh" [m], source lines 12156-12164
_FALL_HEIGHT = (
    1.80225658814015, 0.0517970853538827, -0.000629336469614827, 6.32035529121722e-08,
    1.22476072594873, 2.16717025928665, -1.21939160376451,
    0.010656063519491, -0.0301050931666396, 0.000647364680432361, -0.00059240889866885,
)
# Eq. 4.25, mass-averaged fall time "maft" [s], source lines 12172-12180
_FALL_TIME = (
    0.649949441894023, 0.00467465968739589, -8.34170550900737e-05, 1.10469313271619e-07,
    0.401111371313164, -0.105617246423208, -0.012464783688614,
    -0.00275163282481117, -0.00121958102772624, 0.000113383344526596, -9.32689258128505e-05,
)
# Eq. 4.27, design-load area "P_A" [m^2], powers phi^0..phi^6, source lines 12189-12193
# (the thesis text prints 8.64e-6 for the phi^4 coefficient; the code's 8.651e-6 is used)
_DESIGN_AREA = (
    -2.31115676858565, 0.339781159235542, -0.0184202242225151, 0.000536975704927556,
    -8.65128896429708e-06, 7.328805813683e-08, -2.54709110347933e-10,
)
# Eq. 4.28, flight loading factor "f_load_c" [-], terms as above with d for f,
# source lines 12199-12207 (commented out in Lee's code).  The thesis text prints
# 1.84 for the linear d coefficient: a typo (f(50 deg, d=1) would be 1.59); the
# code value 1.15296535419475 is used.
_LOADING = (
    -0.0450480367762793, -0.00099740007061655, 2.72671900427568e-05, -1.2070957963739e-07,
    1.15296535419475, -1.83760510849243, 1.68000076986581,
    0.00618147656427936, -0.00605940458513032, -0.000141023308476207, 0.000121061698308722,
)

_PHI_RANGE = (20.0, 70.0)


def invicta_tip_radius(radius=2.5, s1=0.195, s2=0.183, alpha1=90.0, alpha2=117.0) -> float:
    r"""Flight-tip radius R_F (m) of a two-section flight, Lee (2008) Eq. 4.1-4.6, by
    [`rotarydryer.geometry.TwoSectionFlight.tip_radius`][rotarydryer.geometry.flights.TwoSectionFlight.tip_radius] (the flight is validated there).
    Lengths in m, angles in deg. Invicta (defaults) gives 2.22789 m.
    """

    return TwoSectionFlight(s1, s2, alpha1, alpha2).tip_radius(radius)


def _poly_phi_f(c, phi, f):
    return (
        c[0] + c[1] * phi + c[2] * phi**2 + c[3] * phi**3
        + c[4] * f + c[5] * f**2 + c[6] * f**3
        + c[7] * phi * f + c[8] * phi * f**2 + c[9] * phi**2 * f + c[10] * phi**2 * f**2
    )


class Lee2008Regressions:
    r"""Lee (2008) regression surrogates (Eq. 4.24-4.28) as a cell geometry model.

    Parameters
    ----------
    tip_radius : float, optional
        Flight-tip radius R_F (m) used in Eq. 4.26.  Default: the Invicta value from
        Lee (2008) Eq. 4.6, 2.22789 m.
    drum : object, optional
        A drum object with a ``tip_radius`` attribute (m), e.g. the exact
        ``FlightedDrum``; used for R_F when ``tip_radius`` is not given.  The
        regressions themselves remain the Invicta ones.

    Notes
    -----
    Angles are in degrees at the interface and in degrees inside the polynomials
    (Lee fitted them in degrees).  The slope only enters Lee's model through the
    forward coefficient (Eq. 3.7), not through these surrogates; ``slope`` is
    accepted for interface compatibility and validated.
    """

    name = "lee2008_regressions"
    default_passive_time_branch = "lee2008_ch7"

    def __init__(self, tip_radius=None, drum=None):
        if tip_radius is None and drum is not None:
            tip_radius = getattr(drum, "tip_radius", None)
            if tip_radius is None:
                raise ValueError("drum must have a tip_radius attribute (m) for Lee2008Regressions")
        if tip_radius is None:
            tip_radius = invicta_tip_radius()
        self.tip_radius = float(check_positive("tip_radius", tip_radius, unit="m"))

    def __repr__(self) -> str:
        return f"Lee2008Regressions(tip_radius={self.tip_radius:.6g})"

    # -- individual correlations ---------------------------------------------------
    @staticmethod
    def _check_phi(repose_angle):
        return check_range("repose_angle", repose_angle, *_PHI_RANGE,
                           low_inclusive=True, high_inclusive=True, unit="deg")

    def mean_fall_height(self, repose_angle, loading_factor=1.0):
        """Mass-averaged fall height h_m (m), Lee (2008) Eq. 4.24 (R^2 = 0.997).

        repose_angle: dynamic angle of repose phi (deg, 20-70); loading_factor: f_load (-, 0-1).
        """
        phi = self._check_phi(repose_angle)
        f = check_range("loading_factor", loading_factor, 0.0, 1.0, low_inclusive=True, high_inclusive=True)
        return _poly_phi_f(_FALL_HEIGHT, phi, f)

    def mean_fall_time(self, repose_angle, loading_factor=1.0):
        """Mass-averaged fall time t_m (s) = active residence time, Lee (2008) Eq. 4.25 (R^2 = 0.996)."""
        phi = self._check_phi(repose_angle)
        f = check_range("loading_factor", loading_factor, 0.0, 1.0, low_inclusive=True, high_inclusive=True)
        return _poly_phi_f(_FALL_TIME, phi, f)

    def design_load_area(self, repose_angle):
        r"""Passive-solids area at design load over the whole drum section, m^2.

        Lee (2008) Eq. 4.27 (R^2 = 0.999): m_p,des = rho_b (L/N) P_A(phi), with
        P_A a 6th-order polynomial in phi (deg).  Kg per cell = bulk_density (kg/m^3)
        * cell_length (m) * area.  Reproduces the root-at-90 deg design-load
        convention (see notes lee_models.md 6.5).
        """
        phi = self._check_phi(repose_angle)
        c = _DESIGN_AREA
        return c[0] + phi * (c[1] + phi * (c[2] + phi * (c[3] + phi * (c[4] + phi * (c[5] + phi * c[6])))))

    def loading_factor(self, dryer_loading, repose_angle):
        r"""Flight loading factor f_load (-) from the dryer loading d_load = M_p/M_p,des.

        Lee (2008) Eq. 4.28 (R^2 = 0.991) with the clipping of the gPROMS code:
        f = 0 if the polynomial is negative, f = 1 if d_load > 1 or the polynomial
        exceeds 1.  The linear d coefficient is the code's 1.15297; the thesis
        prints 1.84, a typo (it would give f(50 deg, d = 1) = 1.59).
        dryer_loading: d_load (-, >= 0); repose_angle: phi (deg).
        """
        d = check_range("dryer_loading", dryer_loading, 0.0, math.inf, low_inclusive=True)
        phi = self._check_phi(repose_angle)
        fc = _poly_phi_f(_LOADING, phi, d)
        f = np.clip(fc, 0.0, 1.0)
        return np.where(d > 1.0, 1.0, f)

    def mean_release_angle(self, repose_angle, loading_factor=1.0, *, passive_time_branch=None):
        r"""Mass-averaged release angle psi_m (deg, flight-root angle from the drum bottom).

        Lee (2008) Eq. 4.26 inverts the vertical chord of the tip circle,
        h_m = 2 R_F |cos psi_m|:

        * ``"eq3.4"``: psi_m = 90 + asin(h_m / 2R_F), as printed in the Appendix I code;
        * ``"lee2008_ch7"``: psi_m = 270 - asin(h_m / 2R_F), the past-the-top
          branch that reproduces Lee's Ch. 4 example (201.6 deg) and Ch. 7 tables.
        """
        branch = check_choice("passive_time_branch", passive_time_branch or self.default_passive_time_branch,
                              PASSIVE_TIME_BRANCHES)
        h = self.mean_fall_height(repose_angle, loading_factor)
        ratio = h / (2.0 * self.tip_radius)
        if np.any(ratio > 1.0):
            raise ValueError(
                f"repose_angle = {describe(repose_angle, 'deg')}: Eq. 4.24 fall height {np.max(h):.4g} m exceeds "
                f"the tip-circle diameter 2*tip_radius = {2 * self.tip_radius:.4g} m; Eq. 4.26 is undefined "
                "(regression used outside its range)"
            )
        a = np.degrees(np.arcsin(ratio))
        return 90.0 + a if branch == "eq3.4" else 270.0 - a

    def cascade(self, repose_angle, loading_factor=1.0, *, rpm, slope=0.0, passive_time_branch=None):
        r"""Mass-averaged cascade summary per cell (vectorised).

        Parameters
        ----------
        repose_angle : array_like
            Dynamic angle of repose phi, deg (20-70).
        loading_factor : array_like
            Flight loading factor f_load, - (0-1).  Lee's Ch. 7 runs use 1.
        rpm : float or array_like
            Drum speed, rev/min (> 0).
        slope : float
            Drum slope theta, deg (0-45); not used by the surrogates.
        passive_time_branch : {"eq3.4", "lee2008_ch7"}, optional
            Reading of the passive time, Lee (2008) Eq. 3.4
            t_p = (2 psi_m - 180)/omega with psi_m from Eq. 4.26:

            * ``"eq3.4"``: psi_m = 90 + asin(h_m/2R_F), hence
              t_p = 2 asin(h_m/2R_F)/omega (the Appendix I code line);
            * ``"lee2008_ch7"`` (default here): psi_m = 270 - asin(h_m/2R_F), hence
              t_p = 2(180 - asin(h_m/2R_F))/omega, i.e. the revolution minus the
              eq3.4 arc.  This is the branch that reproduces Lee's Table 7.6 cycle
              times (10.685-12.816 s) and Tables 7.3/7.5/7.9, so it is the default
              for the surrogates.

        Returns
        -------
        CascadeSummary
            mean_release_angle (deg), mean_fall_height (m), mean_fall_time (s)
            (Eq. 4.25), passive_time (s).
        """
        rpm = check_positive("rpm", rpm, unit="rev/min")
        check_range("slope", slope, 0.0, 45.0, low_inclusive=True, unit="deg")
        psi = self.mean_release_angle(repose_angle, loading_factor, passive_time_branch=passive_time_branch)
        h = self.mean_fall_height(repose_angle, loading_factor)
        t = self.mean_fall_time(repose_angle, loading_factor)
        omega_deg = 360.0 * rpm / 60.0  # deg/s
        tp = (2.0 * psi - 180.0) / omega_deg
        psi, h, t, tp = np.broadcast_arrays(psi, h, t, tp)
        values = dict(
            mean_release_angle=np.array(psi, dtype=float),
            mean_fall_height=np.array(h, dtype=float),
            mean_fall_time=np.array(t, dtype=float),
            passive_time=np.array(tp, dtype=float),
        )
        # fields the surrogates cannot provide (e.g. discharge_start_angle,
        # initial_holdup_area of the exact model) are filled with NaN
        for fld in dataclasses.fields(CascadeSummary):
            values.setdefault(fld.name, np.full(psi.shape, np.nan))
        return CascadeSummary(**values)
