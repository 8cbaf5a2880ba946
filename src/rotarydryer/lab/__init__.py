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

Submodules are imported lazily so that ``import rotarydryer.lab`` stays cheap.
"""

from __future__ import annotations

import importlib

__all__ = ["flight_rig", "images", "design_load_fit", "steps"]


def __getattr__(name):
    if name in __all__:
        return importlib.import_module(f".{name}", __name__)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
