"""The Python examples run as a user runs them, and do what they say: the slider-crank matches its
closed form, the PD controller balances the pole, the 100-run study gives the serial table on a
local cluster of 2 workers."""

import os
import pathlib
import re
import subprocess
import sys

EXAMPLES = pathlib.Path(__file__).resolve().parents[1] / "examples"


def run(script, *args, cwd):
    done = subprocess.run([sys.executable, str(EXAMPLES / script), *args], cwd=cwd,
                          capture_output=True, text=True, env=dict(os.environ), timeout=600)
    assert done.returncode == 0, done.stderr
    return done.stdout


def test_slider_crank_follows_the_closed_form(tmp_path):
    out = run("slider_crank_plot.py", "--out", "crank.png", cwd=tmp_path)
    error = float(re.search(r"closed form: (\S+) m", out).group(1))
    assert error < 1e-9
    assert (tmp_path / "crank.png").read_bytes()[:4] == b"\x89PNG"


def test_pd_controller_balances_the_pole(tmp_path):
    out = run("cart_pole.py", "--seconds", "10", "--plot", "pole.png", cwd=tmp_path)
    m = re.search(r"pole (\S+) rad from upright, cart at (\S+) m", out)
    assert abs(float(m.group(1))) < 1e-3 and abs(float(m.group(2))) < 1e-2
    assert (tmp_path / "pole.png").exists()


def test_study_on_two_workers_is_the_serial_table(tmp_path):
    run("piston_mass_study.py", "--runs", "100", "--workers", "2", "--out", "dask.csv",
        cwd=tmp_path)
    run("piston_mass_study.py", "--runs", "100", "--serial", "--out", "serial.csv", cwd=tmp_path)
    table = (tmp_path / "dask.csv").read_text()
    assert table == (tmp_path / "serial.csv").read_text()
    rows = table.splitlines()[1:]
    assert len(rows) == 100
    torques = [float(r.split(",")[1]) for r in rows]
    assert torques[-1] > 5 * torques[0]  # a heavier piston needs more torque
