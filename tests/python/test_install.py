"""`cmake --install` gives a runner, library, headers and Python package that work without
the build or source tree: the runner from any working directory, the package (on PYTHONPATH)
with the library installed beside it."""
import json
import os
import shutil
import subprocess
import sys
import textwrap

import h5py
import pytest

DECK = """! damped spring-mass carried along a straight track
&simulation title = 'install check', t_end = 0.05, speed = 10.0, gravity = 0.0,
            equilibrium = 'none' /
&output interval = 0.01 /
&body name = 'mass', mass = 1000.0, ixx = 10.0, iyy = 10.0, izz = 10.0,
      position = 0.0, 0.0, 1.0, velocity = 0.0, 0.0, 0.1, frozen = 'x', 'y', 'yaw', 'roll', 'pitch' /
&element name = 'spring', type = 'spring_damper', body1 = 'ground', body2 = 'mass',
      point1 = 0.0, 0.0, 1.0, stiffness = 0.0, 0.0, 4.0e5, damping = 0.0, 0.0, 400.0 /
"""


@pytest.fixture(scope="module")
def installed(build_dir, tmp_path_factory):
    """Install the build tree into a fresh prefix; (prefix, package folder)."""
    cmake = shutil.which("cmake")
    if cmake is None:
        pytest.fail("cmake not on PATH")
    prefix = tmp_path_factory.mktemp("prefix")
    res = subprocess.run([cmake, "--install", str(build_dir), "--prefix", str(prefix)],
                         capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stdout + res.stderr
    packages = sorted(prefix.rglob("raildyn/__init__.py"))
    assert len(packages) == 1, packages
    return prefix, packages[0].parent.parent


def clean_env(**extra):
    """The environment of a user who has only the installation: no build tree settings."""
    env = {k: v for k, v in os.environ.items()
           if k not in ("RAILDYN_BUILD_DIR", "RAILDYN_LIB", "RAILDYN_EXE", "PYTHONPATH")}
    env.update(extra)
    return env


def test_installed_files(installed):
    prefix, site = installed
    assert os.access(prefix / "bin" / "raildyn", os.X_OK)
    assert list(prefix.glob("lib*/libraildyn.so")) or list(prefix.glob("lib*/*/libraildyn.so"))
    assert (prefix / "include" / "raildyn.h").is_file()
    assert (site / "raildyn" / "_installed_layout.py").is_file()
    assert (prefix / "share" / "doc" / "raildyn" / "LICENSE").is_file()
    assert (prefix / "share" / "doc" / "raildyn" / "NOTICE").is_file()


def test_runner_from_another_directory(installed, tmp_path):
    """check and run a deck from a folder that is neither the deck's nor the prefix; -o puts
    the results where it says, relative to the working directory."""
    prefix, _ = installed
    exe = prefix / "bin" / "raildyn"
    decks, elsewhere = tmp_path / "decks", tmp_path / "elsewhere"
    decks.mkdir()
    elsewhere.mkdir()
    (decks / "mass.nml").write_text(DECK)
    res = subprocess.run([str(exe), "check", "../decks/mass.nml"], cwd=elsewhere, env=clean_env(),
                         capture_output=True, text=True, timeout=60)
    assert res.returncode == 0, res.stderr
    assert "mass.nml: ok" in res.stdout
    res = subprocess.run([str(exe), "run", "../decks/mass.nml", "-o", "result.h5"], cwd=elsewhere,
                         env=clean_env(), capture_output=True, text=True, timeout=60)
    assert res.returncode == 0, res.stderr
    with h5py.File(elsewhere / "result.h5") as f:
        assert f["time"][-1] == pytest.approx(0.05)
    res = subprocess.run([str(exe), "run", "--help"], cwd=elsewhere, env=clean_env(),
                         capture_output=True, text=True, timeout=60)
    assert res.returncode == 0 and res.stdout.startswith("usage: raildyn run")
    # the campaign command hands over to the installed Python package
    res = subprocess.run([str(exe), "campaign", "--help"], cwd=elsewhere, env=clean_env(),
                         capture_output=True, text=True, timeout=60)
    assert res.returncode == 0, res.stderr
    assert res.stdout.startswith("usage: raildyn campaign")


def test_package_from_the_install(installed, tmp_path):
    """import raildyn from the installed folder: the library and the runner it finds are the
    installed ones, and a model steps."""
    prefix, site = installed
    (tmp_path / "mass.nml").write_text(DECK)
    code = textwrap.dedent("""
        import json, raildyn
        from raildyn.executable import find_raildyn_executable
        with raildyn.Model.from_file("mass.nml") as m:
            m.initialize(write_output=False)
            m.advance(0.02)
            t = m.time
        print(json.dumps({"package": raildyn.__file__, "library": raildyn.find_library(),
                          "runner": str(find_raildyn_executable()), "time": t}))
    """)
    res = subprocess.run([sys.executable, "-c", code], cwd=tmp_path,
                         env=clean_env(PYTHONPATH=str(site)), capture_output=True, text=True,
                         timeout=60)
    assert res.returncode == 0, res.stderr
    found = json.loads(res.stdout.splitlines()[-1])
    for key in ("package", "library", "runner"):
        assert found[key].startswith(str(prefix) + os.sep), (key, found[key])
    assert found["time"] == pytest.approx(0.02)
