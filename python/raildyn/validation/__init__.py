"""Validation harness: runs the validation scenes, compares them with published and expected
behaviour, writes a self-contained HTML report.

    python -m raildyn.validation [run] [--cases NAME ...] [--reuse] [--out DIR] [--exe PATH]
                                 [--results CASE=FILE ...]
    python -m raildyn.validation list
    python -m raildyn.validation freeze CASE [--channels CH ...] [--rel 0.02] [--abs 1e-6]

Cases (``CASES``): a deck in ``inputs/``, what to extract from its results, the comparison
and its acceptance rule. Reference data and thresholds live in ``validation/`` (CSV files
with their provenance in header comments):

- ``validation/manchester_v1_tc1/packages.csv``: thesis tables 5.9-5.11 as printed,
  ``corrections.csv``: documented digit slips. Acceptance: ``manchester_acceptance``.
- ``validation/tgv_checks.csv``: the TGV 001 expectations with thresholds and justification;
  the ``kind`` column names the check function in ``CHECK_KINDS``.
- ``validation/curves/<case>/*.csv``: optional reference curves with tolerance bands
  (columns time, value, lower, upper; the channel in a ``# channel:`` header line).
- ``validation/baselines/<case>.csv``: frozen approved runs of our own (``freeze``), compared
  at every later run of the case.

Runs use the runner (``<build>/bin/raildyn run DECK -o OUT``), read results with
``raildyn.Results``; everything is SI and follows docs/conventions.md. See
docs/validation.md for the cases, rules and how to add one.

Modules: ``core`` (what a case reports), ``references`` (reference data), ``signals``, ``runs``
(decks, running a deck, the evaluation context), ``manchester``, ``planar`` (the independent
linear models), ``tgv``, ``cases`` (the registry, running a case), ``fidelity_map`` (the
published fidelity map, a section of the report), ``cli``.
"""
from .core import INPUTS, REPO, VALIDATION, CaseError, CaseResult, Check, ReportSection, Table
from .fidelity_map import published_section
from .references import PACKAGES, UNIT_SCALE, freeze_baseline, load_package_table, read_band_csv
from .signals import compare_band_curve, growth_rate, half_cycle_peaks, oscillation_wavelength, window_mean
from .runs import Case, Context, RunInfo, deck_assumptions, deck_files, deck_wheelsets, run_deck, run_notes
from .manchester import (band_verdict, family_scales, manchester_acceptance, manchester_window_times,
                         manchester_window_values)
from .cases import CASES, run_case, run_cases
from .cli import main

__all__ = ["CASES", "Case", "CaseResult", "Check", "band_verdict", "family_scales", "manchester_acceptance",
           "load_package_table", "half_cycle_peaks", "growth_rate", "oscillation_wavelength",
           "window_mean", "run_case", "run_cases", "freeze_baseline", "compare_band_curve",
           "read_band_csv", "deck_assumptions", "deck_files", "run_notes", "main"]
