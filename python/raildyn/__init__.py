"""raildyn: Python side of the railway vehicle dynamics simulator.

- ``Results``: read a results file (HDF5, layout in docs/output.md).
- ``compare_results`` / ``compare_curves`` / ``plot_failures``: OpenFAST-style curve
  comparison with tolerances scaled to each channel's range.
- ``Model``: ctypes wrapper over the C API (src/c_api/raildyn.h); ``RaildynError``.
- ``calculators`` (if present): stand-alone engineering calculators.
"""

from .results import Results, open_results_file
from .compare import (ChannelComparison, ComparisonReport, compare_curves, compare_results,
                      plot_failures)
from .model import Model, RaildynError, find_library, load_library

__all__ = ["Results", "open_results_file", "ChannelComparison", "ComparisonReport",
           "compare_curves", "compare_results", "plot_failures", "Model", "RaildynError",
           "find_library", "load_library"]

import importlib.util as _util

# calculators.py is written separately: import it when present (its own errors are not
# hidden), tolerate its absence.
if _util.find_spec(f"{__name__}.calculators") is not None:
    from . import calculators  # noqa: F401
    __all__.append("calculators")

__version__ = "0.1.0"
