"""Laboratory data tools (issue 8).

* [`rotarydryer.lab.flight_rig`][rotarydryer.lab.flight_rig] - Lee (2008) ch. 5 flight-unloading rig: load-cell
  filtering, discharge rate, start-of-unloading alignment, +/- 2 SD repose-angle band,
  least-squares repose-angle fit with a confidence interval, synthetic runs.
* [`rotarydryer.lab.images`][rotarydryer.lab.images] - Ajayi (2011) ch. 4 photographs of a drum
  cross-section: segmentation, per-flight and curtain areas, annotated image,
  synthetic rendering from the exact flight geometry.
* [`rotarydryer.lab.design_load_fit`][rotarydryer.lab.design_load_fit] - Ajayi (2011) Appendix D segmented
  regression of the first-unloading-flight area against drum loading: break point =
  design load, with delta-method and profile-likelihood confidence intervals
  (Appendix E's propagation corrected).
* `rotarydryer.lab.steps` - Song (2003) ch. 4 dynamic step method: holdup from feed and
  discharge records of step tests, with the closure reconciliation (Eq. 4.1).
* [`rotarydryer.lab.drying_curves`][rotarydryer.lab.drying_curves] - drying curves (moisture against time at a few
  air temperatures): the six thin-layer laws with Arrhenius rate constants fitted to all
  curves at once, ranked (AICc, AIC, BIC, RMSE), with 95 % intervals, and the chosen law
  written into a material file the dryer model reads.

Submodules are imported lazily so that ``import rotarydryer.lab`` stays cheap.
"""

from __future__ import annotations

import importlib

__all__ = ["flight_rig", "images", "design_load_fit", "steps", "drying_curves"]


def __getattr__(name):
    if name in __all__:
        return importlib.import_module(f".{name}", __name__)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
