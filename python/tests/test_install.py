"""The wheel-free install: `cmake --install BUILD --component python --prefix VENV` into a fresh
virtual environment of Debian's python3 (--system-site-packages) gives an importable linx that
finds its linx program."""

import os
import subprocess
import sys

import pytest


def test_install_into_a_virtual_environment(tmp_path, examples):
    build = os.environ.get("LINX_BUILD_DIR")
    if not build:
        pytest.skip("LINX_BUILD_DIR not set (ctest sets it)")
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", str(venv)],
                   check=True)
    subprocess.run(["cmake", "--install", build, "--component", "python", "--prefix", str(venv)],
                   check=True, capture_output=True)
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    script = ("import linx, os; w = linx.load(%r); w.step(10); "
              "from linx import _programs; assert os.access(_programs.LINX, os.X_OK); "
              "print(linx.__file__, w.time)") % str(examples / "pendulum.json")
    done = subprocess.run([str(venv / "bin" / "python3"), "-c", script], env=env, cwd=tmp_path,
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    where, time = done.stdout.split()
    assert where.startswith(str(venv)) and float(time) == pytest.approx(0.01)
