"""raildyn: Python side of the railway vehicle dynamics simulator.

- ``Results``: read a results file (HDF5, layout in docs/output.md).
- ``compare_results`` / ``compare_curves`` / ``plot_failures``: OpenFAST-style curve
  comparison with tolerances scaled to each channel's range
  (command line: ``python -m raildyn.compare test.h5 reference.h5``).
- ``Model``: ctypes wrapper over the C API (src/c_api/raildyn.h); ``RaildynError``.
- ``plots``: quick-look plots (``python -m raildyn.plots track|channels ...``).
- ``calculators`` (if present): stand-alone engineering calculators.
- ``assess`` (``import raildyn.assess``): EN 14363 / EN 12299 quantities and wear indices of a
  results file (``raildyn assess``, docs/assessment.md).
"""

import importlib as _importlib
import importlib.util as _util

from .results import Results, open_results_file
from .model import Model, RaildynError, find_library, load_library

__version__ = "0.1.0"

# The modules that double as command lines (python -m raildyn.compare / .plots) are
# imported on first use, so that running them does not import them twice.
_LAZY = {"ChannelComparison": "compare", "ComparisonReport": "compare",
         "compare_curves": "compare", "compare_results": "compare",
         "plot_failures": "compare", "compare": None, "plots": None}

__all__ = ["Results", "open_results_file", "Model", "RaildynError", "find_library",
           "load_library", *_LAZY]

# calculators.py is written separately: import it when present (its own errors are not
# hidden), tolerate its absence.
if _util.find_spec(f"{__name__}.calculators") is not None:
    from . import calculators  # noqa: F401
    __all__.append("calculators")


def __getattr__(name):
    if name in _LAZY:
        module = _importlib.import_module(f".{_LAZY[name] or name}", __name__)
        return module if _LAZY[name] is None else getattr(module, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
