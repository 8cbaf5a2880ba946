"""rotarydryer: an open simulator of flighted rotary dryers.

Units are SI inside the package (kg, m, s, K unless a docstring says otherwise);
angles are in degrees at the public API.

The public names below are loaded on first use (``import rotarydryer`` stays cheap) and listed
by ``dir(rotarydryer)``, so tab completion shows them:

    >>> import rotarydryer
    >>> "Simulation" in dir(rotarydryer)
    True
"""

from importlib import import_module

__version__ = "0.1.0"

#: public name -> the module that defines it (loaded on first use)
_PUBLIC = {
    "Simulation": "rotarydryer.simulation",
    "SteadyResult": "rotarydryer.simulation",
    "run_case": "rotarydryer.simulation",
    "load_case": "rotarydryer.cases",
    "load_case_text": "rotarydryer.cases",
    "list_cases": "rotarydryer.cases",
    "Results": "rotarydryer.results",
    "load_results": "rotarydryer.results",
    "load_material": "rotarydryer.properties.materials",
    "list_materials": "rotarydryer.properties.materials",
    "load_tracer_dataset": "rotarydryer.rtd",
}

__all__ = sorted(_PUBLIC) + ["__version__"]


def __getattr__(name):   # lazy: importing rotarydryer stays cheap
    module = _PUBLIC.get(name)
    if module is None:
        raise AttributeError(f"module 'rotarydryer' has no attribute {name!r}")
    value = getattr(import_module(module), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(__all__) | {"__version__", "__doc__", "__name__", "__path__", "__file__"})
