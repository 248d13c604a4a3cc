"""asperity: friction of a crystalline sphere sliding on a crystalline flat, from Python.

The compiled core (asperity._asperity) runs the same code as the command-line tools; this
module turns its results into Python objects.

    import asperity
    scene = asperity.Scene({"contact": {"a": 30, "R": 535}})    # or Scene.from_toml(path)
    result = asperity.slide(scene, progress=print)
    result.mu_over_alpha, result.trace["Fx"], result.summary["cost"]
    asperity.slide({"contact": {"a": 10, "envelope": "adhesive", "tau0": 0.05}}).tau_fric

Scenes take the keys of a scene file (data/scenes/default.toml, docs/settings.md), as nested
dicts or dotted keys; a bad key or value raises ValueError naming the key, value and allowed
range. slide() releases the GIL while it runs and stops on Ctrl-C (KeyboardInterrupt).
"""

import json
import pathlib

import numpy as np

from . import _asperity

__all__ = ["Scene", "SlideResult", "slide", "version"]


def version():
    """The build's version and commit, as the tools print it."""
    return _asperity.version()


class Scene:
    """A validated slide scene: the keys of a scene file, with the tools' defaults and checks."""

    def __init__(self, settings=None):
        self._scene = _asperity.scene_from_dict(dict(settings or {}))

    @classmethod
    def from_toml(cls, path):
        """The scene of a TOML scene file, read as contact_slide reads it."""
        path = pathlib.Path(path)
        scene = cls.__new__(cls)
        scene._scene = _asperity.scene_from_toml(path.read_text(), str(path))
        return scene

    @property
    def settings(self):
        """Every setting, keyed as in a scene file ("contact.a", "solver.tolerance", ...)."""
        return json.loads(self._scene.settings_json())

    def __repr__(self):
        s = self.settings
        return f"Scene(a={s['contact.a']} d, R={s['contact.R']} d, alpha={s['contact.alpha']})"


class SlideResult:
    """A slide's result: what contact_slide writes to summary.json, and its trace."""

    def __init__(self, summary, columns):
        self.summary = summary
        names = list(columns)
        self.trace = np.rec.fromarrays([columns[n] for n in names], names=names)

    @property
    def mu(self):
        """Static friction coefficient max Fx/Fz; None for the adhesive envelope (no load)."""
        return self.summary["mu"]

    @property
    def mu_over_alpha(self):
        return self.summary["mu_over_alpha"]

    @property
    def tau_fric(self):
        """Friction stress Fx/A at the peak (G), A the contact-site area (summary "contact_area")."""
        return self.summary["tau_fric"]

    def __repr__(self):
        if self.mu_over_alpha is not None:
            friction = f"mu/alpha={self.mu_over_alpha:.6g}"
        elif self.summary.get("tau_fric_over_tau0") is not None:
            friction = f"tau_fric/tau0={self.summary['tau_fric_over_tau0']:.6g}"
        else:
            friction = "no friction (failed)"
        return (f"SlideResult({friction}, "
                f"{len(self.trace)} rows, {self.summary.get('slip_events')} slip events)")


def slide(scene, progress=None):
    """Slides `scene` (a Scene or a dict of settings) quasi-statically (MODEL.md 5).

    progress: None, or a callable taking a dict (phase, Dx, target_Dx, slip_events, steps,
    gf_applications, wall_s, iteration), called before every relaxation, after every accepted
    step and from inside long relaxations.
    """
    if not isinstance(scene, Scene):
        scene = Scene(scene)
    summary, columns = _asperity.slide(scene._scene, progress)
    return SlideResult(json.loads(summary), columns)
