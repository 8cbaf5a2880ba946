"""FMI 2.0 co-simulation FMU of the dynamic dryer (issue 17, part 3), built with ``pythonfmu``.

`build_fmu` writes an FMU whose slave (`SLAVE_TEMPLATE`) builds the case's
`ThermalDryer` (`rotarydryer.Simulation`), starts
from its steady state and, at every communication step, applies the inputs and integrates
``dryer.simulate(z, step)`` exactly as `DryerStepper` (the Python reference) does.

Inputs: ``feed_rate`` (kg/s wet), ``feed_moisture`` (kg/kg wet), ``gas_inlet_temperature``
(degC), ``rpm`` (rev/min), ``gas_flow`` (kg/s wet gas), ``gas_inlet_humidity`` (kg/kg wet gas), ``feed_temperature``
(degC), ``fouling`` (-): every input a schedule may move but a burner's fuel rate; start values = the case's. Outputs: ``product_moisture`` (kg/kg
wet), ``product_temperature`` (degC), ``exhaust_temperature`` (degC), ``exhaust_humidity``
(kg/kg dry gas), ``holdup`` (kg). Parameters (strings): ``case``, ``overrides`` (JSON).

A case's text is stored in the FMU at export (a file's, or a shipped case's as this version ships it): the FMU
runs the dryer it was exported with, whatever becomes of the file (edited, moved or deleted; a case never names
another file) or of the shipped case (refitted by a later version). A ``case`` parameter
set by the importing tool to another case name or file runs that one instead.

The FMU runs Python inside the importing tool (pythonfmu's embedded interpreter): it needs a
Python with ``rotarydryer`` importable - the build records this interpreter's ``sys.path`` in
the slave, so the FMU is meant for the machine (environment) that built it.
"""

from __future__ import annotations

import hashlib
import json
import math
import sys
import tempfile
from importlib import resources
from pathlib import Path

import numpy as np

from .cases import list_cases

__all__ = ["DryerStepper", "build_fmu", "start_values", "INPUTS", "OUTPUTS"]

#: every schedulable input of `rotarydryer dynamics --schedule` but the burner's fuel rate (a case's own, which the
#: gas inlet temperature stands for)
INPUTS = ("feed_rate", "feed_moisture", "gas_inlet_temperature", "rpm", "gas_flow", "gas_inlet_humidity",
          "feed_temperature", "fouling")
OUTPUTS = ("product_moisture", "product_temperature", "exhaust_temperature", "exhaust_humidity", "holdup")
#: each variable's quantity and unit (the model description's ``description``: pythonfmu writes no units)
DESCRIPTIONS = {
    "feed_rate": "wet feed rate, kg/s", "feed_moisture": "feed moisture, kg/kg wet",
    "gas_inlet_temperature": "gas inlet temperature, degC", "rpm": "drum speed, rev/min",
    "gas_flow": "gas flow, kg/s wet gas", "gas_inlet_humidity": "gas inlet humidity, kg/kg wet gas",
    "feed_temperature": "feed temperature, degC", "fouling": "fouling of the flights, - (as transport.fouling)",
    "product_moisture": "product moisture, kg/kg wet",
    "product_temperature": "product temperature, degC", "exhaust_temperature": "exhaust gas temperature, degC",
    "exhaust_humidity": "exhaust humidity, kg/kg dry gas", "holdup": "solids holdup in the drum, kg",
    "case": "the case: a case name or .toml file (the exported file's text is stored in the FMU)",
    "overrides": "case key overrides, a JSON object ({\"operating.feed_rate\": 30.0})",
}


#: relative change of an input below which a step keeps the inputs in force: an importer's interpolation between
#: two equal table values gives them to rounding (fmpy: 0.19999999999999998 between two rows of 0.2), and taking
#: that as a change restarted the integration (the series parted from `dynamics` by 2e-4)
INPUT_RESOLUTION = 1e-12


def _same_input(a: float, b: float) -> bool:
    return a == b or abs(a - b) <= INPUT_RESOLUTION * max(abs(a), abs(b))


class DryerStepper:
    """The stepping of the FMU in Python: ``step(dt, **inputs)`` -> outputs dict.

    The inputs are held over each step (FMI co-simulation); the integration
    ([`DryerIntegrator`][rotarydryer.thermal.schedule.DryerIntegrator]) carries on across steps whose
    inputs did not change, exactly as ``rotarydryer dynamics --schedule``
    ([`simulate_schedule`][rotarydryer.thermal.schedule.simulate_schedule]) does."""

    def __init__(self, case, overrides=None, case_text=None):
        """``case``: a case name or .toml path; ``case_text``: the TOML text of the case (then ``case`` is only
        its name in messages), as an FMU stores the file it was exported from."""
        from .simulation import Simulation
        from .thermal.schedule import DryerIntegrator, base_inputs

        if case_text is not None:       # as of a file of that text (its network rebuilt as the inputs move)
            sim = Simulation.from_text(case_text, str(case), overrides or {})
        else:
            sim = Simulation(case, overrides or {})
        steady = sim.dynamic_start("the FMU")
        self.base = steady.dryer
        self.dryer = self.base
        self.z = np.asarray(steady.state, float)
        self.time = 0.0
        self.inputs = base_inputs(self.base, INPUTS)
        #: the case's own values of the inputs (the FMU's start values when it runs the case it was exported with)
        self.case_inputs = dict(self.inputs)
        self._applied = dict(self.inputs)
        self._integrator = DryerIntegrator(self.base, self.z)
        self.outputs = self._outputs(self.base)

    def _outputs(self, d):
        from .thermal.schedule import outlets

        o = outlets(d, self.z)
        return {k: o[k] for k in OUTPUTS}

    def step(self, dt, **inputs):
        from .thermal.schedule import apply_inputs

        unknown = set(inputs) - set(INPUTS)
        if unknown:
            raise ValueError(f"unknown FMU input(s) {sorted(unknown)}; use {', '.join(INPUTS)}")
        if not (isinstance(dt, (int, float)) and math.isfinite(dt) and dt >= 0):
            raise ValueError(f"dt = {dt!r}: a communication step is a finite number of seconds >= 0")
        wanted = {**self.inputs, **{k: float(v) for k, v in inputs.items()}}
        if any(not _same_input(v, self._applied[k]) for k, v in wanted.items()):
            # applied first, kept only if the model takes them: a refused input leaves the last ones in force
            dryer = apply_inputs(self.base, wanted, self.z)
            self._integrator.restart(dryer)
            self.dryer, self._applied = dryer, dict(wanted)
        self.inputs = wanted
        if dt > 0:
            self.z = self._integrator.advance(self.time + float(dt))
        self.time += dt
        self.outputs = self._outputs(self.dryer)
        return dict(self.outputs)


SLAVE_TEMPLATE = '''"""rotarydryer FMU slave (generated by rotarydryer.fmu.build_fmu)."""
import json
import sys

for _p in {paths!r}:
    if _p not in sys.path:
        sys.path.append(_p)

from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Real, String

INPUTS = {inputs!r}
OUTPUTS = {outputs!r}
DESCRIPTIONS = {descriptions!r}
#: the case as exported: its reference (a name or the file's path) and the file's text (None: a shipped case)
CASE = {case!r}
CASE_TEXT = {case_text!r}
#: the inputs' start values (the exported case's own): an input the importer leaves at it takes the value of the case
#: the FMU runs, which differs where the importer sets the case or overrides parameters
STARTS = {starts!r}


class RotaryDryer(Fmi2Slave):
    author = "rotarydryer"
    description = "Flighted rotary dryer, dynamic coupled heat-and-mass model (rotarydryer.thermal)"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.case = CASE
        self.overrides = {overrides!r}
        self._stepper = None
        for name in ("case", "overrides"):
            self.register_variable(String(name, causality=Fmi2Causality.parameter,
                                          variability=Fmi2Variability.fixed, description=DESCRIPTIONS[name]))
        for name, start in STARTS.items():
            setattr(self, name, start)
            self.register_variable(Real(name, causality=Fmi2Causality.input, description=DESCRIPTIONS[name]))
        for name, start in {out_starts!r}.items():
            setattr(self, name, start)
            self.register_variable(Real(name, causality=Fmi2Causality.output, description=DESCRIPTIONS[name]))

    def _ensure(self):
        if self._stepper is None:
            from rotarydryer.fmu import DryerStepper

            overrides = json.loads(self.overrides or "{{}}")
            # the exported file's text, unless the importing tool named another case
            text = CASE_TEXT if self.case == CASE else None
            self._stepper = DryerStepper(self.case, overrides, case_text=text)
            for k, v in self._stepper.outputs.items():
                setattr(self, k, v)

    def exit_initialization_mode(self):
        self._ensure()

    def do_step(self, current_time, step_size):
        self._ensure()
        own = self._stepper.case_inputs
        out = self._stepper.step(step_size, **{{k: own[k] if getattr(self, k) == STARTS[k] else getattr(self, k)
                                               for k in INPUTS}})
        for k, v in out.items():
            setattr(self, k, v)
        return True
'''


def build_fmu(case, out, overrides=None, progress=None) -> Path:
    """Build ``out`` (an ``.fmu`` file) for ``case`` (name or .toml path) with ``overrides``
    (dict). Requires ``pythonfmu`` (extra ``fmu``). Returns the path."""
    try:
        from pythonfmu.builder import FmuBuilder
    except ImportError as exc:   # pragma: no cover - depends on the environment
        raise ValueError("the FMU export needs pythonfmu: pip install 'rotarydryer[fmu]'") from exc
    out = Path(out)
    if out.suffix.lower() != ".fmu":
        raise ValueError(f"-o {str(out)!r}: the FMU file name must end in .fmu")
    if progress:
        progress("steady state of the case (start values of the FMU) ...")
    is_file = Path(str(case)).suffix == ".toml"
    case_ref = str(Path(case).resolve()) if is_file else str(case)
    # the file's text as read now: the FMU runs this dryer (the same text as the start values below come from)
    case_text = None
    if is_file:
        try:
            case_text = Path(case).read_bytes().decode("utf-8")
        except (OSError, UnicodeDecodeError):
            case_text = None        # DryerStepper's load of the path says what is wrong with it
    elif str(case) in list_cases():     # a shipped case as this version ships it (a later one may refit it)
        case_text = (resources.files("rotarydryer.cases") / f"{case}.toml").read_text(encoding="utf-8")
    st = DryerStepper(case if case_text is None else case_ref, overrides, case_text=case_text)   # validates; start values
    here = str(Path(__file__).resolve().parent.parent)
    paths = [here] + [p for p in sys.path if p and Path(p).is_dir()]
    src = SLAVE_TEMPLATE.format(paths=paths, inputs=INPUTS, outputs=OUTPUTS, descriptions=DESCRIPTIONS, case=case_ref,
                                case_text=case_text, overrides=json.dumps(overrides or {}), starts=st.inputs,
                                out_starts=st.outputs)
    with tempfile.TemporaryDirectory() as tmp:
        # a module name of this export's own: an FMU's Python slave is imported by its module's name, and a
        # second FMU with the same name in one process (two dryers in one co-simulation) would get the first's
        tag = hashlib.sha256(src.encode("utf-8")).hexdigest()[:12]
        script = Path(tmp) / f"rotary_dryer_fmu_{tag}.py"
        script.write_text(src, encoding="utf-8")
        dest = Path(tmp) / "build"
        dest.mkdir()
        if progress:
            progress("building the FMU (pythonfmu) ...")
        built = FmuBuilder.build_FMU(script, dest=dest)
        from ._io import write_bytes_atomic

        write_bytes_atomic(out, Path(built).read_bytes())
    return out


def start_values(path) -> dict:
    """The start values of an exported FMU's inputs (the case's operating point at export), ``{name: value}``: the
    ``base`` of `InputSchedule.signals` for driving it with a schedule. Reads the model description (needs fmpy)."""
    try:
        import fmpy
    except ImportError as exc:   # pragma: no cover - depends on the environment
        raise ValueError("reading an FMU needs fmpy: pip install 'rotarydryer[fmu]'") from exc
    md = fmpy.read_model_description(str(path))
    return {v.name: float(v.start) for v in md.modelVariables if v.causality == "input"}
