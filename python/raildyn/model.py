"""ctypes wrapper over the raildyn C API (src/c_api/raildyn.h).

    from raildyn import Model
    with Model.from_file("inputs/manchester_v1_straight.nml") as m:
        m.initialize(write_output=False)
        m.advance(1.0)
        print(m.time, m.output("bodies/car/position_track"))

Every C call returns a status; a non-zero status raises ``RaildynError(status, message)``
with the handle's message from ``rd_error_message``. Handles are opaque int64 values
(NEKO style), so any number of models may live in one process; a closed model's handle is
never valid again. A failed ``initialize`` may be called again; after a failed ``advance``
the run is over (its results file records the failure) and stepping raises again with that
message (raildyn.h). All quantities SI (docs/conventions.md).
"""

from __future__ import annotations

import ctypes
import os
from pathlib import Path
from typing import Iterable

import numpy as np

try:                            # written by cmake --install only
    from . import _installed_layout
except ImportError:             # a source tree
    _installed_layout = None

__all__ = ["Model", "RaildynError", "find_library", "load_library", "STATUS_NAMES"]

#: Status codes of raildyn.h (mirror src/fortran/common/rd_error.f90).
RD_OK = 0
STATUS_NAMES = {
    0: "ok",
    1: "input error",
    2: "runtime error",
    3: "physics limit",
    4: "i/o error",
    5: "internal error",
    6: "invalid handle or call order",
}

_MESSAGE_LEN = 8192
_NAME_LEN = 512
_NOTES_LEN = 65536     # rd_run_notes: about 120 characters per wheel that lost contact
_rd_handle = ctypes.c_int64
_c_double_p = ctypes.POINTER(ctypes.c_double)


class RaildynError(RuntimeError):
    """A raildyn C API call failed: ``status`` (raildyn.h code) and ``message``."""

    def __init__(self, status: int, message: str):
        self.status = int(status)
        self.message = message
        super().__init__(f"{STATUS_NAMES.get(self.status, 'unknown status')} "
                         f"(status {self.status}): {message}")


def find_library() -> str:
    """Path of libraildyn.so: env ``RAILDYN_LIB``, else
    ``$RAILDYN_BUILD_DIR/src/c_api/libraildyn.so``, else the library installed with this
    package (``cmake --install``), else the repository's ``build/src/c_api/libraildyn.so``."""
    candidates: list[Path] = []
    if os.environ.get("RAILDYN_LIB"):
        lib = Path(os.environ["RAILDYN_LIB"])
        if not lib.is_file():
            raise FileNotFoundError(f"RAILDYN_LIB={lib} does not exist")
        return str(lib)
    if os.environ.get("RAILDYN_BUILD_DIR"):
        candidates.append(Path(os.environ["RAILDYN_BUILD_DIR"]) / "src/c_api/libraildyn.so")
    if _installed_layout is not None:
        candidates.append(_installed_layout.LIBRARY)
    candidates.append(Path(__file__).resolve().parents[2] / "build/src/c_api/libraildyn.so")
    for path in candidates:
        if path.is_file():
            return str(path)
    raise FileNotFoundError("libraildyn.so not found; build it (cmake --build build) or set "
                            "RAILDYN_LIB or RAILDYN_BUILD_DIR. Tried: "
                            + ", ".join(str(p) for p in candidates))


_libraries: dict[str, ctypes.CDLL] = {}


def load_library(path: str | None = None) -> ctypes.CDLL:
    """Load (once per path) the shared library and declare the prototypes of raildyn.h."""
    path = path or find_library()
    if path in _libraries:
        return _libraries[path]
    lib = ctypes.CDLL(path)
    h, hp = _rd_handle, ctypes.POINTER(_rd_handle)
    c_int, c_char_p, c_double = ctypes.c_int, ctypes.c_char_p, ctypes.c_double
    prototypes = {
        "rd_version": (c_char_p, []),
        "rd_create_from_file": (c_int, [c_char_p, hp]),
        "rd_create_from_string": (c_int, [c_char_p, c_char_p, hp]),
        "rd_initialize": (c_int, [h, c_int]),
        "rd_advance": (c_int, [h, c_double]),
        "rd_get_time": (c_int, [h, ctypes.POINTER(c_double)]),
        "rd_get_state_size": (c_int, [h, ctypes.POINTER(c_int)]),
        "rd_get_state": (c_int, [h, _c_double_p, c_int]),
        "rd_set_state": (c_int, [h, _c_double_p, c_int]),
        "rd_set_start": (c_int, [h, c_double, _c_double_p, c_int]),
        "rd_linearize": (c_int, [h, _c_double_p, c_int]),
        "rd_output_count": (c_int, [h, ctypes.POINTER(c_int)]),
        "rd_output_name": (c_int, [h, c_int, ctypes.c_char_p, c_int]),
        "rd_output_size": (c_int, [h, c_char_p, ctypes.POINTER(c_int)]),
        "rd_get_output": (c_int, [h, c_char_p, _c_double_p, c_int]),
        "rd_set_input": (c_int, [h, c_char_p, _c_double_p, c_int]),
        "rd_finalize": (c_int, [h]),
        "rd_error_message": (c_int, [h, ctypes.c_char_p, c_int]),
        "rd_run_notes": (c_int, [h, ctypes.c_char_p, c_int]),
        "rd_destroy": (c_int, [h]),
    }
    for name, (restype, argtypes) in prototypes.items():
        fn = getattr(lib, name)   # AttributeError names a missing entry point
        fn.restype = restype
        fn.argtypes = argtypes
    _libraries[path] = lib
    return lib


def _encode(text: str | os.PathLike) -> bytes:
    return os.fspath(text).encode("utf-8")


class Model:
    """One raildyn scene behind an opaque handle. Create with ``from_file`` or
    ``from_string``; release with ``close()`` or a ``with`` block."""

    def __init__(self, handle: int, lib: ctypes.CDLL):
        # Use from_file / from_string; the constructor takes an existing handle.
        self._handle = int(handle)
        self._lib = lib

    # -- creation -----------------------------------------------------------------
    @classmethod
    def _create(cls, lib: ctypes.CDLL, call, what: str) -> "Model":
        handle = _rd_handle(0)
        status = call(ctypes.byref(handle))
        if status != RD_OK:
            message = ""
            if handle.value != 0:
                # The C API keeps a handle on failure so that the message can be read.
                message = cls._message(lib, handle.value)
                lib.rd_destroy(handle)
            raise RaildynError(status, message or what)
        if handle.value == 0:
            raise RaildynError(5, f"{what}: status ok but no handle returned")
        return cls(handle.value, lib)

    @classmethod
    def from_file(cls, deck_path: str | os.PathLike, library: str | None = None) -> "Model":
        """Create a model from a namelist deck file."""
        lib = load_library(library)
        path = _encode(deck_path)
        return cls._create(lib, lambda hp: lib.rd_create_from_file(path, hp),
                           f"rd_create_from_file({os.fspath(deck_path)!r}) failed")

    @classmethod
    def from_string(cls, deck_text: str, base_dir: str | os.PathLike | None = None,
                    library: str | None = None) -> "Model":
        """Create a model from deck text; relative paths in it resolve against base_dir
        (default: the current directory)."""
        lib = load_library(library)
        text = deck_text.encode("utf-8")
        base = _encode(base_dir) if base_dir is not None else None
        return cls._create(lib, lambda hp: lib.rd_create_from_string(text, base, hp),
                           "rd_create_from_string failed")

    # -- errors -------------------------------------------------------------------
    @staticmethod
    def _message(lib: ctypes.CDLL, handle: int) -> str:
        buffer = ctypes.create_string_buffer(_MESSAGE_LEN)
        if lib.rd_error_message(_rd_handle(handle), buffer, _MESSAGE_LEN) != RD_OK:
            return ""
        return buffer.value.decode("utf-8", errors="replace")

    def _check(self, status: int) -> None:
        if status != RD_OK:
            raise RaildynError(status, self._message(self._lib, self._handle))

    @property
    def handle(self) -> int:
        if self._handle == 0:
            raise RaildynError(6, "model is closed")
        return self._handle

    @property
    def version(self) -> str:
        return self._lib.rd_version().decode()

    # -- stepping -------------------------------------------------------------------
    def initialize(self, write_output: bool = True) -> None:
        """Build the scene, set the initial state, open the output file if the deck asks
        for one (write_output) and write step 0."""
        self._check(self._lib.rd_initialize(self.handle, 1 if write_output else 0))

    def advance(self, t_target: float) -> None:
        """Integrate up to t_target [s] (>= current time)."""
        self._check(self._lib.rd_advance(self.handle, float(t_target)))

    @property
    def time(self) -> float:
        """Current simulated time [s]."""
        value = ctypes.c_double()
        self._check(self._lib.rd_get_time(self.handle, ctypes.byref(value)))
        return value.value

    def state(self) -> np.ndarray:
        """Copy of the integrator's state vector."""
        size = ctypes.c_int()
        self._check(self._lib.rd_get_state_size(self.handle, ctypes.byref(size)))
        values = np.zeros(size.value, dtype=np.float64)
        self._check(self._lib.rd_get_state(self.handle, values.ctypes.data_as(_c_double_p),
                                           size.value))
        return values

    def set_state(self, state: Iterable[float]) -> None:
        """Replace the state at the current time (after initialize)."""
        array = np.ascontiguousarray(np.asarray(state, dtype=np.float64).ravel())
        self._check(self._lib.rd_set_state(self.handle, array.ctypes.data_as(_c_double_p), array.size))

    def set_start(self, time: float, state: Iterable[float]) -> None:
        """A restart: start at ``time`` [s] from ``state`` (before initialize)."""
        array = np.ascontiguousarray(np.asarray(state, dtype=np.float64).ravel())
        self._check(self._lib.rd_set_start(self.handle, float(time),
                                           array.ctypes.data_as(_c_double_p), array.size))

    def linearize(self) -> np.ndarray:
        """The linearised system matrix A = df/dy of y' = f(t, y) about the current time and
        state, at the running speed in force (``set_input("speed", V)`` changes it), as an
        (n, n) array; rows and columns in the layout of ``state()`` (docs/output.md,
        /state/y). Its eigenvalues are the modes of ``raildyn eigen``
        (docs/theory_stability.md). After initialize."""
        size = ctypes.c_int()
        self._check(self._lib.rd_get_state_size(self.handle, ctypes.byref(size)))
        n = size.value
        matrix = np.zeros(n * n, dtype=np.float64)
        self._check(self._lib.rd_linearize(self.handle, matrix.ctypes.data_as(_c_double_p), n * n))
        return matrix.reshape(n, n)

    # -- outputs and inputs ---------------------------------------------------------
    def output_names(self) -> list[str]:
        count = ctypes.c_int()
        self._check(self._lib.rd_output_count(self.handle, ctypes.byref(count)))
        names = []
        buffer = ctypes.create_string_buffer(_NAME_LEN)
        for index in range(1, count.value + 1):   # 1-based in the C API
            self._check(self._lib.rd_output_name(self.handle, index, buffer, _NAME_LEN))
            names.append(buffer.value.decode("utf-8"))
        return names

    def output(self, name: str) -> np.ndarray:
        """Current values of the named output (SI, docs/output.md)."""
        key = name.encode("utf-8")
        size = ctypes.c_int()
        self._check(self._lib.rd_output_size(self.handle, key, ctypes.byref(size)))
        values = np.zeros(size.value, dtype=np.float64)
        self._check(self._lib.rd_get_output(self.handle, key,
                                            values.ctypes.data_as(_c_double_p), size.value))
        return values

    def outputs(self) -> dict[str, np.ndarray]:
        """All outputs at the current time, name -> values."""
        return {name: self.output(name) for name in self.output_names()}

    def set_input(self, name: str, values: float | Iterable[float]) -> None:
        """Set a named input from now on ('speed' [m/s], 'body/<name>/external_force'
        6 values [N, N m] in fixed-frame components)."""
        array = np.ascontiguousarray(np.atleast_1d(np.asarray(values, dtype=np.float64)))
        if not np.all(np.isfinite(array)):
            raise ValueError(f"set_input({name!r}): values must be finite")
        self._check(self._lib.rd_set_input(self.handle, name.encode("utf-8"),
                                           array.ctypes.data_as(_c_double_p), array.size))

    def run_notes(self) -> list[str]:
        """The run's notes so far (wheels without contact in some output samples: share of
        samples, largest sampled vertical force), one string each."""
        buffer = ctypes.create_string_buffer(_NOTES_LEN)
        self._check(self._lib.rd_run_notes(self.handle, buffer, _NOTES_LEN))
        return [line for line in buffer.value.decode("utf-8").splitlines() if line]

    # -- end ------------------------------------------------------------------------
    def finalize(self) -> None:
        """Flush and close the output file; the model can still be queried."""
        self._check(self._lib.rd_finalize(self.handle))

    def close(self) -> None:
        """Free the model (closes its output file if still open: status 'completed' if the
        deck's t_end was reached, else 'stopped'; ``finalize`` records 'completed'). Idempotent."""
        if self._handle != 0:
            handle, self._handle = self._handle, 0
            status = self._lib.rd_destroy(_rd_handle(handle))
            if status != RD_OK:
                raise RaildynError(status, f"rd_destroy({handle}) failed")

    def __enter__(self) -> "Model":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def __del__(self):
        try:
            self.close()
        except Exception:
            pass

    def __repr__(self) -> str:
        return f"Model(handle={self._handle})"
