"""The slider-crank of examples/slider_crank.json, driven at one turn a second: the piston's
position against the closed form x = r cos(theta) + sqrt(l^2 - r^2 sin(theta)^2) of the crank
angle theta, plotted with matplotlib.

    python3 python/examples/slider_crank_plot.py [--out slider_crank.png] [--seconds 2]
"""

import argparse
import math
import pathlib

import numpy as np

import linx

ROOT = pathlib.Path(__file__).resolve().parents[2]
R, L = 0.1, 0.3  # crank and rod lengths (m) of the scene


def simulate(seconds: float):
    world = linx.load(ROOT / "examples" / "slider_crank.json")
    crank, piston = world.joint("crank"), world.body("piston")
    t, theta, x = [], [], []
    for _ in range(round(seconds / world.timestep)):
        world.step()
        t.append(world.time)
        theta.append(crank.coordinates[0])
        x.append(piston.position[0])
    return np.array(t), np.array(theta), np.array(x)


def closed_form(theta):
    return R * np.cos(theta) + np.sqrt(L * L - (R * np.sin(theta)) ** 2)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="slider_crank.png", help="the plot (PNG)")
    parser.add_argument("--seconds", type=float, default=2.0)
    args = parser.parse_args()

    t, theta, x = simulate(args.seconds)
    exact = closed_form(theta)
    error = np.abs(x - exact).max()
    print(f"{len(t)} steps, {theta[-1] / (2 * math.pi):.3f} turns; "
          f"largest piston error against the closed form: {error:.3e} m")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(7, 5))
    top.plot(t, x, label="linx")
    top.plot(t, exact, "--", label="closed form")
    top.set_ylabel("piston x (m)")
    top.legend()
    bottom.semilogy(t, np.maximum(np.abs(x - exact), 1e-18))
    bottom.set_ylabel("|error| (m)")
    bottom.set_xlabel("time (s)")
    fig.tight_layout()
    fig.savefig(args.out, dpi=100)
    print(f"plot: {args.out}")


if __name__ == "__main__":
    main()
