"""`raildyn COMMAND --help` (and -h) for every command of the runner: that command's usage
on stdout, nothing on stderr, exit 0; `raildyn help COMMAND` prints the same."""
import re
import subprocess

import pytest

COMMANDS = ["run", "check", "track", "profile-scan", "eigen", "critical-speed", "conicity", "campaign", "export",
            "assess", "hertz", "creep", "version", "help"]


def runner(exe, *args, cwd=None):
    return subprocess.run([str(exe), *map(str, args)], capture_output=True, text=True, timeout=60,
                          cwd=cwd)


def test_every_command_of_the_overview_is_covered(raildyn_exe):
    """The overview names exactly the commands tested here (a new command needs its help)."""
    res = runner(raildyn_exe, "help")
    assert res.returncode == 0 and res.stderr == ""
    overview = res.stdout.splitlines()[0]
    assert overview.startswith("usage: raildyn ")
    named = [alt.split()[0] for alt in overview[len("usage: raildyn "):].split(" | ")]
    assert sorted(named) == sorted(COMMANDS)


@pytest.mark.parametrize("flag", ["--help", "-h"])
@pytest.mark.parametrize("command", COMMANDS)
def test_command_help(raildyn_exe, command, flag, tmp_path):
    res = runner(raildyn_exe, command, flag, cwd=tmp_path)
    assert res.returncode == 0, res.stderr
    assert res.stderr == ""
    assert re.match(rf"usage: raildyn {command}\b", res.stdout), res.stdout
    if command != "campaign":        # the campaign's help is argparse's, several lines
        assert res.stdout.count("\n") == 1, res.stdout
        assert runner(raildyn_exe, "help", command).stdout == res.stdout
    assert list(tmp_path.iterdir()) == []       # help writes nothing


def test_help_after_other_arguments(raildyn_exe, tmp_path):
    """--help wins over the rest of the line: no run starts, no file is read."""
    res = runner(raildyn_exe, "run", tmp_path / "absent.nml", "-o", tmp_path / "x.h5", "--help")
    assert res.returncode == 0 and res.stdout.startswith("usage: raildyn run DECK")
    assert not (tmp_path / "x.h5").exists()


def test_usage_errors_name_the_command(raildyn_exe, tmp_path):
    """A usage error prints the command's own usage line on stderr, exit 1."""
    res = runner(raildyn_exe, "track", tmp_path / "a.nml", "--frobnicate")
    assert res.returncode == 1
    assert "unknown option '--frobnicate'" in res.stderr
    assert res.stderr.splitlines()[-1].startswith("usage: raildyn track DECK")
    res = runner(raildyn_exe, "help", "frobnicate")
    assert res.returncode == 1 and "unknown command 'frobnicate'" in res.stderr
    res = runner(raildyn_exe, "version", "extra")
    assert res.returncode == 1 and res.stderr.splitlines()[-1] == "usage: raildyn version"
