"""Published data sets (CSV, first line = source); read them with rotarydryer.published."""
import functools
from importlib import resources

#: file-name prefix of the shipped tracer curves (``tracer_<name>.csv``)
TRACER_PREFIX = "tracer_"


def tracer_dataset_names() -> list[str]:
    """Names of the shipped tracer curves (`rotarydryer.rtd.tracer_datasets`), without importing
    the RTD package (the case loader checks ``tracer.dataset`` with it on every run: the package's
    files are listed once per process)."""
    return list(_tracer_dataset_names())


@functools.cache
def _tracer_dataset_names() -> tuple[str, ...]:
    root = resources.files(__name__)
    return tuple(sorted(p.name[len(TRACER_PREFIX):-4] for p in root.iterdir()
                        if p.name.startswith(TRACER_PREFIX) and p.name.endswith(".csv")))
