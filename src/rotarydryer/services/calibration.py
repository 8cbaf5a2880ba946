"""Options and runs of ``rotarydryer calibrate`` and of the web app's Calibration page: case keys
fitted to the measured responses of many tests at once (`rotarydryer.estimation.calibrate`),
the calibration record as TOML and the case file with the record appended."""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

from ..cases import load_case_text
from ..cases.calibration import CalibrationRecord
from ..estimation.calibrate import (
    CONFIGURATION_KEYS,
    RESPONSES,
    TEST_KEY_PREFIX,
    CaseCalibration,
    calibrate,
    held_overrides,
    record_toml,
)

__all__ = ["parse_tests", "parse_sigmas", "check_name", "case_text", "CalibrationRun", "run_calibration", "RESPONSES"]


def parse_tests(text) -> list[int] | None:
    """``"2,3,4"`` -> ``[2, 3, 4]`` (None: every test); ``ValueError`` naming ``--tests``."""
    if text is None:
        return None
    out = []
    for part in str(text).split(","):
        part = part.strip()
        if not part.lstrip("-").isdigit():
            raise ValueError(f"--tests {text!r}: expected test numbers separated by commas, e.g. 2,3,4")
        if int(part) in out:
            raise ValueError(f"--tests {text!r}: test {int(part)} is given twice (each test's data count once)")
        out.append(int(part))
    if not out:
        raise ValueError("--tests: give at least one test number")
    return out


def parse_sigmas(items) -> dict[str, float]:
    """``["gas_outlet_temperature=5"]`` -> ``{"gas_outlet_temperature": 5.0}``; ``ValueError`` naming ``--sigma``."""
    out: dict[str, float] = {}
    for item in items or []:
        if "=" not in item:
            raise ValueError(f"--sigma {item!r}: expected RESPONSE=VALUE, e.g. gas_outlet_temperature=5")
        k, v = (s.strip() for s in item.split("=", 1))
        if k in out:
            raise ValueError(f"--sigma {k} is given twice; give each response's standard deviation once")
        if k not in RESPONSES:
            raise ValueError(f"--sigma {item!r}: {k!r} is not a response; responses: {', '.join(RESPONSES)}")
        try:
            out[k] = float(v)
        except ValueError:
            raise ValueError(f"--sigma {item!r}: {v!r} is not a number") from None
        if not out[k] > 0 or not math.isfinite(out[k]):
            raise ValueError(f"--sigma {k} = {v}: a standard deviation must be a finite number > 0")
    return out


def check_name(name) -> None:
    if name is not None and not 0 < len(str(name).strip()) <= 200:
        raise ValueError("--name must have 1-200 characters")


def case_text(case: str) -> str:
    """The text of a case file (a path) or of a shipped case (a name)."""
    src = Path(case)
    if src.suffix == ".toml" and src.exists():
        return src.read_text("utf-8")
    return (resources.files("rotarydryer.cases") / f"{case}.toml").read_text("utf-8")


@dataclass
class CalibrationRun:
    """A calibration, its record (TOML) and the case with the record appended (checked to load)."""

    calibration: CaseCalibration
    record: CalibrationRecord
    record_text: str
    calibrated_case_text: str

    def to_dict(self) -> dict:
        d = self.calibration.to_dict()
        d["record"] = self.record.model_dump(exclude_none=True)
        return d


def run_calibration(case: str, parameters, *, tests=None, responses=None, sigmas=None, base_overrides=None,
                    starts: int = 1, profile: bool = False, name: str | None = None, progress=None,
                    source_text: str | None = None, executor=None) -> CalibrationRun:
    """Calibrate ``parameters`` of ``case`` (`rotarydryer.estimation.calibrate.calibrate`), and make the
    record and the calibrated case text (``source_text``: the case file's text, default read from
    ``case``). The calibrated case must load (else ``ValueError``: nothing to write). ``executor``
    (`rotarydryer.executor.Executor`) runs the starts."""
    check_name(name)
    fitted = list(responses or [])
    twice = sorted({r for r in fitted if fitted.count(r) > 1})
    if twice:       # its data counted twice: an interval narrower by sqrt(2)
        raise ValueError(f"--response {twice[0]} is given twice (each response's data count once)")
    unused = sorted(set(sigmas or {}) - set(fitted)) if fitted else []
    if unused:
        raise ValueError(f"--sigma {unused[0]}: not a fitted response (--response {', '.join(fitted)}); a standard "
                         "deviation is given for a response the calibration fits")
    if "operating.test" in (base_overrides or {}):
        raise ValueError("--set operating.test: a calibration runs each test of --tests (every test by default) with "
                         "its own operating point; give the tests with --tests")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cal = calibrate(case, parameters, tests=tests, responses=responses or None, base_overrides=base_overrides,
                        sigmas=sigmas, n_starts=starts, profile=profile, progress=progress, executor=executor)
        record = cal.record(name=name)
        text = record_toml(record)
        base = case_text(case) if source_text is None else source_text
        calibrated = base.rstrip("\n") + "\n\n# ---- appended by rotarydryer calibrate ----\n" + text
        load_case_text(calibrated, "the calibrated case")      # the new file loads, or nothing is written
    inputs = plant_inputs_set(base_overrides, cal.keys)
    if inputs:
        # the record holds the model's coefficients, not the plant's inputs: a validation of the written case without
        # the same --set gave other numbers, silently (found by review)
        warnings.warn(f"the calibration ran with --set {', '.join(f'{k}={base_overrides[k]}' for k in inputs)} (the "
                      "plant's inputs), which the record and the calibrated case do not hold: they reproduce this fit "
                      "only with the same --set; put the value in the case file to keep it", UserWarning, stacklevel=2)
    return CalibrationRun(cal, record, text, calibrated)


def plant_inputs_set(base_overrides, fitted) -> list[str]:
    """The keys of a calibration's ``--set`` that are the plant's inputs (the operating point, the gas, the material,
    the site, the drum): neither fitted, nor held by the record (`held_overrides`), nor its configuration."""
    held = set(held_overrides(base_overrides or {}, list(fitted)))
    return [k for k in (base_overrides or {}) if k not in held and k not in fitted and k not in CONFIGURATION_KEYS
            and not k.startswith(TEST_KEY_PREFIX)]
