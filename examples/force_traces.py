"""The seed's Fig. 5 from Python: force traces Fx/(alpha Fz) against the tip position in the
three regimes of the lateral force model (MODEL.md 5, 8).

    PYTHONPATH=build/python /usr/bin/python3 examples/force_traces.py [--out traces.png]

Regime I (a = 8 d, R = 535 d: atoms move in step, a smooth periodic trace), Regime II
(a = 43 d, R = 535 d: one loop sweeps the contact at each slip) and Regime III (a = 24 d,
R = 40 d over 2.3 d: small slips of arrested loops). About ten seconds. Prints mu/alpha of
each, the numbers contact_slide prints for the same scenes.
"""
import argparse

import matplotlib

matplotlib.use("Agg")  # files, no display
import matplotlib.pyplot as plt

import asperity

# Steps of at most 0.05 d (the default 0.4 d brackets the slips as finely but draws the smooth
# parts as straight lines).
SCENES = {
    "Regime I: a = 8 d, R = 535 d": {"contact": {"a": 8, "R": 535}, "slide.max_step": 0.05},
    "Regime II: a = 43 d, R = 535 d": {"contact": {"a": 43, "R": 535}, "slide.max_step": 0.05},
    "Regime III: a = 24 d, R = 40 d": {
        "contact": {"a": 24, "R": 40}, "slide": {"distance": 2.3, "max_step": 0.05}},
}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="force_traces.png")
    out = parser.parse_args().out
    fig, ax = plt.subplots(figsize=(7, 4))
    for title, settings in SCENES.items():
        r = asperity.slide(settings)
        alpha = r.summary["alpha"]
        ax.plot(r.trace["Dx"], r.trace["Fx"] / (alpha * r.trace["Fz"]), ".-", label=title)
        print(f"{title}: mu/alpha = {r.mu_over_alpha!r}, {r.summary['slip_events']} slip events")
    ax.set_xlabel("Dx / d")
    ax.set_ylabel("Fx / (alpha Fz)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    print(f"figure: {out}")


if __name__ == "__main__":
    main()
