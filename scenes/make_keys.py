#!/usr/bin/env python3
"""Writes the key files of our animated scenes (robot_arm.key, v3_orrery.key) from scratch.

A key file (spec §14.1) lists, frame by frame, one column-major 4x4 matrix per DOF. The keys
loop: the frame after the last is frame 0 again, so the motions below are periodic.
"""
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))


def rot(axis, deg):
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    if axis == "x":
        return [[1, 0, 0], [0, c, -s], [0, s, c]]
    if axis == "y":
        return [[c, 0, s], [0, 1, 0], [-s, 0, c]]
    return [[c, -s, 0], [s, c, 0], [0, 0, 1]]


def block(r, t=(0, 0, 0)):
    """The 16 numbers of p' = R p + t, column by column."""
    cols = []
    for j in range(3):
        cols += [r[0][j], r[1][j], r[2][j], 0]
    cols += [t[0], t[1], t[2], 1]
    return " ".join(f"{v:.6f}".rstrip("0").rstrip(".") if v != 0 else "0" for v in cols)


def write(name, dofs, duration, frames, comment):
    path = os.path.join(HERE, name)
    with open(path, "w") as f:
        f.write(f"// {comment}\n// Written by make_keys.py.\n")
        f.write(f"#DOFS {len(dofs)} {' '.join(d for d, _ in dofs)}\n")
        f.write(f"#DURATION {duration}\n#FRAMES {frames}\n")
        for k in range(frames):
            f.write(f"// frame {k}\n")
            for d, fn in dofs:
                f.write(block(*fn(k / frames)) + "\n")


def robot_arm():
    tau = 2 * math.pi
    dofs = [
        ("base", lambda u: (rot("y", 70 * math.sin(tau * u)),)),
        ("shoulder", lambda u: (rot("z", -25 + 30 * math.sin(tau * u + 0.6)),)),
        ("elbow", lambda u: (rot("z", 55 + 35 * math.cos(tau * u)),)),
        # The wrist turns a full revolution per loop: 45 degrees per key, the short way.
        ("wrist", lambda u: (rot("y", 360 * u),)),
        ("finger", lambda u: ((rot("z", 0)), (0.12 + 0.1 * math.sin(2 * tau * u), 0, 0))),
    ]
    write("robot_arm.key", dofs, 4, 8, "A four-joint robot arm and its gripper: 8 keys, 4 s loop.")


def orrery():
    dofs = [
        ("earth_orbit", lambda u: (rot("y", 360 * u), tuple(4 * x for x in (math.cos(math.radians(-360 * u)), 0, math.sin(math.radians(-360 * u)))))),
        ("earth_spin", lambda u: (rot("y", 3 * 360 * u),)),
        ("moon_orbit", lambda u: (rot("y", 4 * 360 * u), (1.2 * math.cos(math.radians(-4 * 360 * u)), 0, 1.2 * math.sin(math.radians(-4 * 360 * u))))),
        ("mars_orbit", lambda u: (rot("y", 180 * u + 60), (6.5 * math.cos(math.radians(-180 * u - 60)), 0, 6.5 * math.sin(math.radians(-180 * u - 60))))),
    ]
    write("v3_orrery.key", dofs, 6, 24, "An orrery: orbits and spins, 24 keys over a 6 s loop.")


if __name__ == "__main__":
    robot_arm()
    orrery()
