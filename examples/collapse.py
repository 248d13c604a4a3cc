"""The seed's Fig. 4 from Python: mu/alpha of the lateral force model against a/b_core^0 for
two sphere radii collapses onto one curve (MODEL.md 8): 1 in Regime I, falling as
(a/b_core^0)^(-2/3) in Regime II.

    PYTHONPATH=build/python /usr/bin/python3 examples/collapse.py [--out collapse.png]

Contacts are chosen by their control parameter x = a/b_core^0 = c alpha a^2 / (R d),
c = 4 / (pi (1 - nu)), from 0.3 to 10 at R = 160 d and 535 d (a from 5 to 55 d); a few
seconds. Prints each point's mu/alpha, as contact_slide prints it for the same contact.
"""
import argparse
import math

import matplotlib

matplotlib.use("Agg")  # files, no display
import matplotlib.pyplot as plt

import asperity

ALPHA, NU = 0.7, 0.5
TARGETS = [0.3, 1.0, 3.0, 10.0]


def contact_radius(x, R):
    """a for a/b_core^0 = x at sphere radius R (d = 1)."""
    c = 4.0 / (math.pi * (1.0 - NU))
    return math.sqrt(x * R / (c * ALPHA))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="collapse.png")
    out = parser.parse_args().out
    fig, ax = plt.subplots(figsize=(6, 4))
    for R in (160.0, 535.0):
        xs, ys = [], []
        for target in TARGETS:
            a = contact_radius(target, R)
            r = asperity.slide({"contact": {"a": a, "R": R, "alpha": ALPHA}, "material.nu": NU})
            xs.append(r.summary["a_over_bcore0"])
            ys.append(r.mu_over_alpha)
            print(f"R = {R:g} d, a = {a!r} d: a/b_core^0 = {xs[-1]:.4g}, "
                  f"mu/alpha = {r.mu_over_alpha!r}")
        ax.loglog(xs, ys, "o-", label=f"R = {R:g} d")
    guide = [3.0, 10.0]
    ax.loglog(guide, [0.9 * (g / 3.0) ** (-2.0 / 3.0) for g in guide], "k--", label="slope -2/3")
    ax.set_xlabel("a / b_core^0")
    ax.set_ylabel("mu / alpha")
    ax.legend()
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    print(f"figure: {out}")


if __name__ == "__main__":
    main()
