"""Pictures from Python: a run folder recorded with World.record() is the same as `linx run`
writes, POV-Ray renders a frame of it, and the browser viewer serves it."""

import json
import urllib.request

import numpy as np
import pytest

import linx


@pytest.fixture(autouse=True)
def programs_without_preload(monkeypatch):
    # Under the sanitizers ctest preloads their runtimes into python3; the linx program links
    # them itself, and POV-Ray (which it runs) must not get them.
    monkeypatch.delenv("LD_PRELOAD", raising=False)


def test_recording_matches_linx_run(examples, linx_program, tmp_path):
    import subprocess
    subprocess.run([linx_program, "run", str(examples / "double_pendulum.json"), "--out",
                    str(tmp_path / "cli"), "--duration", "0.2", "--every", "50"],
                   check=True, capture_output=True)
    world = linx.load(examples / "double_pendulum.json")
    with world.record(tmp_path / "py", every=50) as rec:
        for _ in range(4):
            world.step(50)
            rec.record()
    for name in ("bodies.csv", "joints.csv", "world.csv"):
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    # The scene is the same but for where it came from and the run's length (--duration).
    py, cli = (json.loads((tmp_path / d / "scene.json").read_text()) for d in ("py", "cli"))
    for d in (py, cli):
        d.pop("source"), d.pop("duration")
    assert py == cli


def test_render_a_frame(examples, tmp_path):
    world = linx.load(examples / "pendulum.json")
    rec = world.record(tmp_path, every=100)
    world.step(100)
    rec.record()
    rec.close()
    with pytest.raises(ValueError, match="closed"):
        rec.record()
    png = linx.render(tmp_path, frame="last", width=160, height=120, antialias=False)
    data = open(png, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"


def test_render_errors_raise_with_the_programs_message(tmp_path):
    with pytest.raises(linx.Error, match="nothing"):
        linx.render(tmp_path / "nothing")


def test_view_serves_the_run(examples, tmp_path):
    world = linx.load(examples / "pendulum.json")
    with world.record(tmp_path, every=10) as rec:
        world.step(10)
        rec.record()
    with linx.view(tmp_path, open_browser=False) as viewer:
        assert viewer.url.startswith("http://127.0.0.1:")
        with urllib.request.urlopen(viewer.url + "run/scene.json", timeout=10) as r:
            assert b"bob" in r.read()
    assert viewer.process.poll() is not None
    assert np.isfinite(world.positions).all()


def test_plot_of_a_recording_with_hostile_names_runs_nothing(linx_program, tmp_path):
    # Names given in Python reach gnuplot's titles as data (issue 43): a backquoted command or
    # $(...) in a joint's name runs nothing, and the SVG's titles show the names.
    import subprocess
    import xml.etree.ElementTree as ET
    canary = tmp_path / "CANARY"
    names = [f"pivot`touch {canary}1` > owned", f"$(touch {canary}2) @m \"q\" 'x' \\"]
    scene = linx.Scene(gravity=[0, 0, -9.81], timestep=0.001)
    scene.body("bob\x1b[2J", mass=1, position=[1.0, 0, 0], shapes=[linx.sphere(0.05)])
    scene.body("bob2", mass=1, position=[2.0, 0, 0], shapes=[linx.sphere(0.05)])
    scene.joint("hinge", "bob\x1b[2J", "world", name=names[0], anchor=[0, 0, 0], axis=[0, 1, 0])
    scene.joint("hinge", "bob2", "bob\x1b[2J", name=names[1], anchor=[1, 0, 0], axis=[0, 1, 0])
    world = scene.build()
    with world.record(tmp_path / "run", every=10) as rec:
        for _ in range(5):
            world.step(10)
            rec.record()
    done = subprocess.run([linx_program, "plot", str(tmp_path / "run")], capture_output=True)
    assert done.returncode == 0, done.stderr
    assert not list(tmp_path.rglob("CANARY*"))
    svg = ET.parse(tmp_path / "run" / "plots" / "joint_coordinates.svg")
    texts = ["".join(e.itertext()) for e in svg.iter() if e.tag.endswith("text")]
    for name in names:
        assert f"{name} (hinge)" in texts
