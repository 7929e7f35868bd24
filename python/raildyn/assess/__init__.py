"""raildyn.assess: the quantities of the acceptance standards from a results file.

- running safety and track loading (EN 14363): Y/Q, sum Y against Prud'homme, the
  instability criterion, Q_max, Y_qst / Q_qst in curves, Delta Q / Q (running_safety.py,
  track_loading.py);
- ride comfort (EN 12299): Wb, Wc, Wd weightings (filters.py), N_MV and Cc (comfort.py);
- wear: T gamma per patch and wheel, the surface fatigue index FI_surf as RCF index (wear.py);
- sliding means, rms values and percentiles (windows.py); the report (report.py).

Command line: ``raildyn assess RESULTS.h5 [--json] [--csv DIR] [--html DIR]`` (the runner calls
``python -m raildyn.assess``). Formulas, clauses and sources: docs/assessment.md.
"""
from .assessment import Assessment, assess
from .quantity import Quantity

__all__ = ["Assessment", "Quantity", "assess"]
