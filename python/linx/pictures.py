"""Pictures of worlds: a run folder recorded with World.record() (or written by `linx run`) is
rendered with POV-Ray by `linx render`, or shown in the browser by `linx view`
(docs/visualization.md)."""

from __future__ import annotations

import os
import subprocess
import webbrowser
from typing import Optional, Union

from linx import _programs
from linx._linx import Error

__all__ = ["render", "view", "Viewer"]

Path = Union[str, "os.PathLike[str]"]


def _run(args: list[str]) -> str:
    done = subprocess.run([_programs.LINX, *args], capture_output=True, text=True)
    if done.returncode != 0:
        raise Error(done.stderr.strip() or f"linx {args[0]} failed (exit {done.returncode})")
    return done.stdout


def render(run: Path, *, frame: Union[float, str, None] = "last", width: int = 800,
           height: int = 600, fps: float = 30.0, video: Optional[str] = None,
           antialias: bool = True) -> str:
    """Renders a recorded run with POV-Ray. frame: the time (s) of the one frame to render, or
    "last"; None renders every frame (at `fps`) and, with video "mp4" or "gif", a video.
    Returns the path of the PNG (one frame) or of the folder of frames (and video). Raises
    linx.Error with the program's message (no POV-Ray, not a run folder, ...)."""
    args = ["render", os.fspath(run), "--width", str(width), "--height", str(height),
            "--antialias", "on" if antialias else "off"]
    if frame is not None:
        out = _run(args + ["--frame", str(frame)])
        return out.strip().splitlines()[-1]
    args += ["--fps", str(fps), "--video", video or "none"]
    _run(args)
    return os.path.join(os.fspath(run), "render")


class Viewer:
    """A running `linx view` server: url, and close() (or a with block) to stop it."""

    def __init__(self, process: subprocess.Popen, url: str) -> None:
        self.process = process
        self.url = url

    def close(self) -> None:
        """Stops the server."""
        if self.process.poll() is None:
            self.process.terminate()
            self.process.wait(timeout=10)

    def __enter__(self) -> "Viewer":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def view(run: Path, *, port: int = 0, open_browser: bool = True) -> Viewer:
    """Serves the browser viewer of a recorded run on 127.0.0.1 and opens it in the browser.
    Returns the Viewer (its url; close() stops it)."""
    process = subprocess.Popen([_programs.LINX, "view", os.fspath(run), "--port", str(port)],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert process.stdout is not None
    for line in process.stdout:
        if "http://" in line:
            url = line[line.index("http://"):].split()[0]
            if open_browser:
                webbrowser.open(url)
            return Viewer(process, url)
    message = process.stderr.read().strip() if process.stderr else ""
    process.wait()
    raise Error(message or f"linx view failed (exit {process.returncode})")
