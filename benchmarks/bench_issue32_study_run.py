"""Issue 32: where a study run's CPU goes - one chunk of a Sobol study of 8 inputs on MMG (the inputs of
``bench_sensitivity.py``), warm starts, one process, one BLAS thread, compiled kernels.

Prints the CPU per run (``time.process_time``) of the whole chunk and of its stages (case load, model
build or re-parameterisation, the coupled solve, the transport view of the fill check), and the solver's
calls per run (residuals, Jacobians, shell refreezes). Run with the tree to measure, and with
``PYTHONPATH=OLD_CHECKOUT/src`` for the "before" side; alternate them (the machine is shared):

    python benchmarks/bench_issue32_study_run.py [runs]
"""

from __future__ import annotations

import collections
import sys
import time

from bench_sensitivity import MMG_PARAMS
from threadpoolctl import threadpool_limits

import rotarydryer
from rotarydryer import _jit
from rotarydryer import simulation as sim_mod
from rotarydryer.studies import sensitivity as sens
from rotarydryer.thermal import dryer as dryer_mod
from rotarydryer.thermal import states as states_mod

CPU: collections.Counter = collections.Counter()
CALLS: collections.Counter = collections.Counter()


def timed(owner, name, tag):
    """Wrap ``owner.name`` to add its CPU time and calls under ``tag``."""
    fn = getattr(owner, name)

    def wrapper(*a, **k):
        CALLS[tag] += 1
        t = time.process_time()
        try:
            return fn(*a, **k)
        finally:
            CPU[tag] += time.process_time() - t
    setattr(owner, name, wrapper)


def main(runs: int = 160) -> None:
    _jit.long_runs()
    params = sens.check_params(MMG_PARAMS)
    X = sens.saltelli_design(params, max(16, runs // 10 + 1), 0)
    keys, outputs = list(params), list(sens.OUTPUTS)
    with threadpool_limits(1):
        sens._run_chunk("ajayi2011_mmg", {}, keys, X[:20], outputs)        # warm-up: imports, kernels, tables
        t = time.process_time()
        sens._run_chunk("ajayi2011_mmg", {}, keys, X[:runs], outputs)
        plain = time.process_time() - t
        for owner, name, tag in ((sim_mod.Simulation, "__init__", "case load"),
                                 (sim_mod.Simulation, "thermal_dryer", "model build"),
                                 (dryer_mod.ThermalDryer, "with_parameters", "re-parameterisation"),
                                 (dryer_mod.ThermalDryer, "_pseudo_transient", "coupled solve"),
                                 (states_mod.ThermalSteadyState, "transport_state", "fill check's transport view"),
                                 (dryer_mod.ThermalDryer, "rhs", "residuals"),
                                 (dryer_mod.ThermalDryer, "jacobian", "Jacobians"),
                                 (dryer_mod.ThermalDryer, "_refreeze_shell", "shell refreezes")):
            timed(owner, name, tag)
        sens._run_chunk("ajayi2011_mmg", {}, keys, X[:runs], outputs)
    print(f"{rotarydryer.__file__}: {runs} runs, {plain / runs * 1e3:.2f} ms CPU per run (uninstrumented)")
    for tag, cpu in CPU.items():
        print(f"  {tag}: {cpu / runs * 1e3:.2f} ms per run, {CALLS[tag] / runs:.2f} calls per run")


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:]))
