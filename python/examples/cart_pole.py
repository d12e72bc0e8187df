"""A PD controller balancing an inverted pendulum on a cart, at 1 kHz: every step reads the pole's
angle and the cart's position with their rates, and sets the force on the cart's rail.

The cart (1 kg) runs on a slider along x; the pole (a 1 m rod of 0.1 kg) is hinged on it about y,
released 0.2 rad from upright. The force F = kp theta + kd theta' + kx x + kv x' pushes the cart
under the pole and then back to the origin.

    python3 python/examples/cart_pole.py [--seconds 10] [--plot cart_pole.png]
"""

import argparse

import numpy as np

import linx

GAINS = {"kp": 40.0, "kd": 8.0, "kx": 2.0, "kv": 3.5}  # N/rad, N s/rad, N/m, N s/m


def cart_pole() -> linx.World:
    scene = linx.Scene(gravity=[0, 0, -9.81], timestep=1e-3)
    scene.body("ground", static=True, shapes=[linx.plane()])
    scene.body("cart", mass=1.0, position=[0, 0, 0.1], shapes=[linx.box([0.3, 0.2, 0.1])])
    scene.body("pole", mass=0.1, position=[0, 0, 0.65], shapes=[linx.box([0.02, 0.02, 1.0])])
    scene.joint("slider", "cart", name="rail", axis=[1, 0, 0])
    # The pole's angle about +y: positive tips its top towards +x. It starts 0.2 rad over.
    scene.joint("hinge", "pole", "cart", name="pivot", anchor=[0, 0, 0.15], axis=[0, 1, 0],
                initial=0.2)
    return scene.build()


def balance(seconds: float, gains=GAINS):
    world = cart_pole()
    rail, pivot = world.joint("rail"), world.joint("pivot")
    t, theta, x = [], [], []
    for _ in range(round(seconds / world.timestep)):
        angle, angle_rate = pivot.coordinates[0], pivot.rates[0]
        position, speed = rail.coordinates[0], rail.rates[0]
        force = (gains["kp"] * angle + gains["kd"] * angle_rate + gains["kx"] * position
                 + gains["kv"] * speed)
        rail.set_force(force)  # along the rail, until changed: one value per step
        world.step()
        t.append(world.time)
        theta.append(angle)
        x.append(position)
    return np.array(t), np.array(theta), np.array(x)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--plot", help="write a plot of the angle and the position (PNG)")
    args = parser.parse_args()
    t, theta, x = balance(args.seconds)
    print(f"after {t[-1]:.1f} s: pole {theta[-1]:+.2e} rad from upright, cart at {x[-1]:+.2e} m; "
          f"largest angle {np.abs(theta).max():.3f} rad")
    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(7, 3.5))
        ax.plot(t, theta, label="pole angle (rad)")
        ax.plot(t, x, label="cart position (m)")
        ax.set_xlabel("time (s)")
        ax.legend()
        fig.tight_layout()
        fig.savefig(args.plot, dpi=100)
        print(f"plot: {args.plot}")


if __name__ == "__main__":
    main()
