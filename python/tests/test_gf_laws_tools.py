"""The elastic half-space on NumPy arrays, the scaling laws and the tools from Python
(issue 25). Analytic answers are stated with their tolerances."""
import json
import math
import os
import pathlib
import signal
import threading
import time

import numpy as np
import pytest

import asperity
import asperity.tools as tools

DATA = pathlib.Path(os.environ["ASPERITY_DATA"])


def test_free_gf_far_field_is_cerruti():
    # A unit force along x on one site of a 96 x 96 block; the displacement along x at r = 30 d
    # on the x axis. Cerruti (point force on a half-space): u_x = F (1 - nu + nu x^2/r^2) /
    # (2 pi G r) = 1 / (2 pi r) at nu = 0.5 on the axis. The patch model differs from a point
    # force by O((d/r)^2) ~ 1e-3 of it at r = 30 d: tolerance 2e-3 relative.
    gf = asperity.FreeSurfaceGF((96, 96), components="in_plane", G=1.0, nu=0.5)
    f = np.zeros((2, 96, 96))
    f[0, 20, 48] = 1.0
    u = gf.apply(f)
    assert u[0, 50, 48] == pytest.approx(1 / (2 * math.pi * 30), rel=2e-3)
    # The convolution is its coefficients (to FFT rounding).
    assert u[0, 50, 48] == pytest.approx(gf.coefficient(0, 0, 30, 0), rel=1e-12)
    assert gf.applications == 1


@pytest.mark.parametrize("G,nu", [(1.0, 0.0), (2.0, 0.25), (0.5, 0.5)])
def test_free_gf_far_field_carries_the_modulus_and_poisson_ratio(G, nu):
    # Cerruti at r = 30 d: along the force's axis u_x = F / (2 pi G r) whatever nu; across it
    # (x = 0) u_x = F (1 - nu) / (2 pi G r). Off the axes the cross term: u_y = F nu x y /
    # (2 pi G r^3). Patch against point force: O((d/r)^2), tolerance 2e-3 relative (the cross
    # term at (21, 21) d, r = 29.7 d: the same).
    gf = asperity.FreeSurfaceGF((96, 96), components="in_plane", G=G, nu=nu)
    f = np.zeros((2, 96, 96))
    f[0, 20, 40] = 1.0
    u = gf.apply(f)
    assert u[0, 50, 40] == pytest.approx(1 / (2 * math.pi * G * 30), rel=2e-3)
    assert u[0, 20, 70] == pytest.approx((1 - nu) / (2 * math.pi * G * 30), rel=2e-3)
    r = math.hypot(21, 21)
    assert u[1, 41, 61] == pytest.approx(nu * 21 * 21 / (2 * math.pi * G * r ** 3), rel=2e-3,
                                         abs=1e-12)


def test_free_gf_writes_in_place_without_copies():
    gf = asperity.FreeSurfaceGF((32, 40), components="full")
    rng = np.random.default_rng(3)
    f = rng.standard_normal((3, 32, 40))
    out = np.empty_like(f)
    got = gf.apply(f, out=out)
    assert got is out
    np.testing.assert_array_equal(out, gf.apply(f))
    # A Fortran-ordered input is converted (a copy) and gives the same numbers.
    np.testing.assert_array_equal(gf.apply(np.asfortranarray(f)), out)
    with pytest.raises(TypeError, match="C-contiguous float64"):
        gf.apply(f, out=np.empty((3, 32, 40), dtype=np.float32))
    with pytest.raises(ValueError, match=r"expected \(3, 32, 40\)"):
        gf.apply(f[:2])
    with pytest.raises(ValueError, match="overlap"):
        gf.apply(out, out=out)
    with pytest.raises(ValueError, match="nu"):
        asperity.FreeSurfaceGF((8, 8), nu=0.7)
    with pytest.raises(ValueError, match="components"):
        asperity.FreeSurfaceGF((8, 8), components="xy")


def test_periodic_gf_and_stiffness_are_inverse_but_for_the_mean():
    # K G f = f - mean(f) per component (the q = 0 mode is left out): to rounding, 1e-12.
    gf = asperity.PeriodicSurfaceGF((24, 16), components="in_plane", alias_images=4)
    f = np.random.default_rng(5).standard_normal((2, 24, 16))
    back = gf.apply_stiffness(gf.apply(f))
    expected = f - f.mean(axis=(1, 2), keepdims=True)
    np.testing.assert_allclose(back, expected, rtol=0, atol=1e-12)


def test_periodic_gf_near_its_source_is_the_free_surfaces():
    # Near the source the periodic cell's images add a field that is smooth there: of order
    # F/(2 pi G L) and varying by F r/(2 pi G L^2) over r. So differences u(r1) - u(r2) a few
    # d from the source are the free surface's to 3e-4 of their size at L = 256 d (r <= 8 d;
    # the images' change over 8 d is 8/256^2 of 1/(2 pi G) against a difference of about
    # (1/2 - 1/8)/(2 pi G)), tolerance 1e-3 relative. G and nu are not 1 and 0.5, so that a
    # binding that dropped either would fail; and the same cell with G doubled halves u.
    G, nu, L = 1.7, 0.3, 256
    per = asperity.PeriodicSurfaceGF((L, L), components="in_plane", G=G, nu=nu)
    free = asperity.FreeSurfaceGF((16, 16), components="in_plane", G=G, nu=nu)
    f = np.zeros((2, L, L))
    f[0, 100, 100] = 1.0
    u = per.apply(f)
    for k, (o0, o1) in [(0, (2, 0)), (0, (0, 2)), (1, (3, 4)), (0, (5, 5))]:
        got = u[k, 100 + o0, 100 + o1] - u[k, 108, 100]
        want = free.coefficient(k, 0, o0, o1) - free.coefficient(k, 0, 8, 0)
        assert got == pytest.approx(want, rel=1e-3), (k, o0, o1)
    stiffer = asperity.PeriodicSurfaceGF((L, L), components="in_plane", G=2 * G, nu=nu)
    np.testing.assert_allclose(stiffer.apply(f), u / 2, rtol=0, atol=1e-12 * np.abs(u).max())


def test_laws_are_the_formulas():
    x = np.array([2.0, 20.0, 200.0])
    c0 = 0.7
    np.testing.assert_allclose(asperity.regime_two_law(x, c0),
                               3 * (2 * c0) ** (2 / 3) * x ** (-2 / 3), rtol=1e-15)
    # a/b_core^0 = 4/(pi (1 - nu)) alpha a^2/(R d)
    for nu in (0.5, 0.25):
        assert asperity.control_parameter(43.0, 535.0, 0.7, nu) == pytest.approx(
            4 / (math.pi * (1 - nu)) * 0.7 * 43.0 ** 2 / 535.0, rel=1e-14)
    assert asperity.nucleation_condition(0.01, c0) == 1.0  # Regime I: mu = alpha
    # The Regime II law is the nucleation condition's expansion for small b_core: their ratio
    # tends to 1 as x^(-2/3), a factor 10^(2/3) = 4.64 a decade (to 10%).
    misses = [abs(asperity.nucleation_condition(x, c0) / asperity.regime_two_law(x, c0) - 1)
              for x in (1e2, 1e3, 1e4, 1e5)]
    for big, small in zip(misses, misses[1:]):
        assert big / small == pytest.approx(10 ** (2 / 3), rel=0.1)
    # Regime II at x = 50, beta = b_core^0/d = 2 (MODEL.md 8): the central Regime III estimate
    # is k1 exp(-k2 beta), the law the Regime II formula, and the nucleation condition wins.
    p = asperity.predict(50.0, 2.0, c0=0.7, k1=1.0, k2=1.5)
    assert p["central"] == pytest.approx(math.exp(-3.0), rel=1e-14)
    assert p["law_two"] == pytest.approx(asperity.regime_two_law(50.0, 0.7), rel=1e-14)
    assert p["nucleation"] == pytest.approx(asperity.nucleation_condition(50.0, 0.7), rel=1e-14)
    assert p["nucleation"] > p["integrated"] and p["regime"] == "II"
    assert p["mu_over_alpha"] == p["nucleation"]
    with pytest.raises(ValueError):
        asperity.predict(50.0, 2.0, c0=-1.0, k1=1.0, k2=1.5)


@pytest.fixture(scope="module")
def fit(tmp_path_factory):
    out = tmp_path_factory.mktemp("fit")
    return tools.fit_scaling([DATA / "reference" / "sweep_R535.csv"], out=out, k1=3.0, k2=1.2)


def test_fit_scaling_from_python_is_the_tools_output(fit):
    # sweep_R535's Regime II points give c0 = 0.2118 +- 0.0115 (data/reference/sweep_R535.md,
    # the value the regression tier stores too; k1, k2 do not enter the Regime II fit), and a
    # prediction for every row of the table, all at its radius.
    two = fit.summary["regime_two"]
    assert two["c0"] == pytest.approx(0.2118, rel=1e-3)
    assert two["points"] >= 3 and two["within_max_deviation"]
    assert 0 < two["c0_error"] < 0.1 * two["c0"]
    with open(DATA / "reference" / "sweep_R535.csv") as table:
        rows = sum(1 for _ in table) - 1
    predictions = fit.tables["predictions"]
    assert len(predictions) == rows > 0
    assert set(np.asarray(predictions["R"], dtype=float)) == {535.0}
    collapse = [p for p in fit.figures if p.name == "collapse.png"]
    assert len(collapse) == 1 and collapse[0].stat().st_size > 10_000


def test_fit_regime_two_in_process_equals_fit_scaling(fit):
    # The same points, window rule, bootstrap and seed as fit_scaling: the same c0, bit for bit.
    table = tools.read_table(DATA / "reference" / "sweep_R535.csv")
    keep = table["failed"] == 0
    ours = asperity.fit_regime_two(table["a_over_bcore0"][keep], table["mu_over_alpha"][keep],
                                   a=table["a"][keep], R=table["R"][keep],
                                   lower_bound=table["mu_is_lower_bound"][keep])
    c0 = fit.summary["regime_two"]["c0"]
    assert ours["valid"]
    assert ours["c0"] == c0
    assert ours["c0_error"] == fit.summary["regime_two"]["c0_error"]


def test_forecast_in_process_equals_fit_scalings(tmp_path):
    # fit_scaling's forecast.csv and asperity.forecast with the same c0, law and errors: the same
    # numbers, bit for bit (given k1, k2 errors are used as they are; alpha and nu are the table's).
    run = tools.fit_scaling([DATA / "reference" / "sweep_R535.csv"], out=tmp_path / "f", k1=3.0,
                            k2=1.2, k1_error=0.1, k2_error=0.02, forecast_R=[800, 1700],
                            forecast_a=[150, 300, 450])
    table = run.tables["forecast"]
    assert len(table) == 6
    c0 = run.summary["regime_two"]["c0"]
    c0_error = run.summary["regime_two"]["c0_error"]
    for row in table:
        ours = asperity.forecast(row["a"], row["R"], c0=c0, k1=3.0, k2=1.2, c0_error=c0_error,
                                 k1_error=0.1, k2_error=0.02)
        assert ours["mu_over_alpha"] == row["predicted"]
        assert ours["mu_over_alpha_error"] == row["predicted_error"]
        assert ours["log_slope"] == row["log_slope"]
        assert ours["regime"] == row["predicted_regime"]
    # With the project's own Peierls scan (--peierls): its plain k1, k2 errors times the
    # summary's reported_error_factor, its correlation and its window, as docs/python.md says.
    scan = tools.peierls_scan(out=tmp_path / "ps")
    run = tools.fit_scaling([DATA / "reference" / "sweep_R535.csv"], out=tmp_path / "g",
                            peierls=scan, forecast_R=[800], forecast_a=[150, 300, 450])
    law = run.summary["peierls"]
    factor = law["reported_error_factor"]
    assert factor > 1.0
    b_min, b_max = law["window_b_core"]
    for row in run.tables["forecast"]:
        ours = asperity.forecast(row["a"], row["R"], c0=run.summary["regime_two"]["c0"],
                                 k1=law["k1"], k2=law["k2"],
                                 c0_error=run.summary["regime_two"]["c0_error"],
                                 k1_error=law["k1_error"] * factor,
                                 k2_error=law["k2_error"] * factor,
                                 correlation=law["k1_k2_correlation"], b_min=b_min, b_max=b_max)
        assert ours["mu_over_alpha"] == row["predicted"]
        assert ours["mu_over_alpha_error"] == row["predicted_error"]
        assert ours["law_extrapolated"] == bool(row["law_extrapolated"])
        assert ours["undetermined"] == bool(row["regime_undetermined"])
    # Regime II falls with a (slope about -4/3), whatever the law says after the crossover.
    first = asperity.forecast(150, 1700, c0=c0, k1=3.0, k2=1.2)
    assert first["regime"] == "II" and -1.4 < first["log_slope"] < -1.3
    with pytest.raises(ValueError):
        asperity.forecast(-1, 800, c0=c0, k1=3.0, k2=1.2)


def test_a_scan_summary_without_its_points_is_flagged(tmp_path):
    # The scan's errors are plain standard errors, scaled by the t factor of the fit's degrees
    # of freedom (points - 2); a summary without the points leaves them unscaled, which the
    # summary says, as it says a missing correlation.
    law = {"fits": {"edge": {"valid": True, "k1": 2.3, "k1_error": 0.1, "k2": 1.8,
                             "k2_error": 0.01, "window_b_core": [2, 6]}}}
    (tmp_path / "law.json").write_text(json.dumps(law))
    run = tools.fit_scaling([DATA / "reference" / "sweep_R535.csv"], out=tmp_path / "o",
                            peierls=tmp_path / "law.json")
    peierls = run.summary["peierls"]
    assert peierls["reported_error_factor"] == 1.0
    assert "points_missing" in peierls and "correlation_missing" in peierls
    law["fits"]["edge"].update(points=6, k1_k2_correlation=0.9)
    (tmp_path / "law6.json").write_text(json.dumps(law))
    run = tools.fit_scaling([DATA / "reference" / "sweep_R535.csv"], out=tmp_path / "o6",
                            peierls=tmp_path / "law6.json")
    peierls = run.summary["peierls"]
    # t_4(Phi(2)) / 2 for 6 points (statistics.hpp): Student's t with 4 degrees of freedom at
    # Phi(2) = 0.97725 is 2.8693 (its density integrated numerically), so 1.4347.
    assert peierls["reported_error_factor"] == pytest.approx(1.4347, abs=1e-3)
    assert "points_missing" not in peierls and "correlation_missing" not in peierls


def test_a_window_by_hand_names_its_regime_three_points(tmp_path):
    # --window takes every measured point inside it: at R = 40 d, a/b_core^0 4..60 reaches the
    # rising branch (simulated Regime III from a = 28 d, regime3_R40_fill.md), which the
    # summary lists and the tool warns of; the automatic window stops before the upturn.
    tables = [DATA / "reference" / name
              for name in ("sweep_R535.csv", "regime3_R40.csv", "regime3_R40_fill.csv")]
    auto = tools.fit_scaling(tables, out=tmp_path / "auto", k1=2.3, k2=1.8)
    assert auto.summary["regime_two"]["window_regime_three"] == []
    assert "rising branch" not in auto.stderr
    given = tools.fit_scaling(tables, out=tmp_path / "given", k1=2.3, k2=1.8, window=[4, 60])
    rising = given.summary["regime_two"]["window_regime_three"]
    assert rising and all(p["R"] == 40.0 and p["a"] >= 28.0 for p in rising)
    # The same points as predictions.csv's rows in the window and simulated III.
    table = given.tables["predictions"]
    expected = sorted((r["a"], r["R"]) for r in table
                      if r["in_window"] == 1 and r["simulated_regime"] == "III")
    assert sorted((p["a"], p["R"]) for p in rising) == expected
    assert "rising branch" in given.stderr


def test_read_table_empty_cells(tmp_path):
    # A numeric column with empty cells (slips.csv's cost columns in rows an earlier build wrote)
    # stays numeric, NaN where empty; text, and a column with no value at all, stay str.
    path = tmp_path / "t.csv"
    path.write_text("slip,gf_applications,stop_reason,note\n1,,distance cap,\n2,140428,,\n")
    t = tools.read_table(path)
    assert t["slip"].dtype == float and list(t["slip"]) == [1.0, 2.0]
    assert t["gf_applications"].dtype == float
    assert np.isnan(t["gf_applications"][0]) and t["gf_applications"][1] == 140428.0
    assert t["stop_reason"].dtype.kind == "U" and list(t["stop_reason"]) == ["distance cap", ""]
    assert t["note"].dtype.kind == "U"


def test_tool_errors_raise_with_the_tools_message(tmp_path):
    # The tool's own words (its stderr), not only the wrapper's "fit_scaling failed" prefix.
    with pytest.raises(RuntimeError, match="missing.csv: no such sweep table"):
        tools.fit_scaling([tmp_path / "missing.csv"], out=tmp_path / "o")


def test_ctrl_c_stops_a_tool_cleanly_and_it_resumes(tmp_path):
    # Ctrl-C in Python (here SIGINT to this process, as a notebook's interrupt sends it) reaches
    # the tool as one SIGINT; the call waits while the tool saves its checkpoint, then raises
    # KeyboardInterrupt with the tool's "continue with" message. (subprocess.run would kill the
    # tool 0.25 s after the interrupt, before its checkpoint.) The resumed slide gives the
    # uninterrupted slide's mu. a = 43 d, R = 535 d: about two seconds; the signal is sent once
    # the first state is written (snapshots/start.nc, after the tool's stop handlers are in).
    full = tools.contact_slide(out=tmp_path / "full", a=43, R=535, threads=1)
    out = tmp_path / "cut"
    start = out / "snapshots" / "start.nc"

    def interrupt_once_started():
        deadline = time.monotonic() + 60
        while not start.exists() and time.monotonic() < deadline:
            time.sleep(0.01)
        os.kill(os.getpid(), signal.SIGINT)

    timer = threading.Thread(target=interrupt_once_started)
    timer.start()
    with pytest.raises(KeyboardInterrupt, match="continue with") as stopped:
        tools.contact_slide(out=out, a=43, R=535, threads=1)
    timer.join()
    assert "--resume" in str(stopped.value)
    assert (out / "checkpoint.cbor").exists()
    resumed = tools.contact_slide(out=out, a=43, R=535, threads=1, resume=True)
    assert resumed.summary["mu"] == full.summary["mu"]


def test_peierls_scan_from_python(tmp_path):
    scan = tools.peierls_scan(b_core=[2, 3], theta=[0], L=64, out=tmp_path / "ps")
    rows = scan.tables["peierls"]
    assert len(rows) == 2 and set(rows["b_core"]) == {2.0, 3.0}
    assert np.all(rows["tau_P_over_tau_max_pos"] > 0)
    # Every setting echoed by its key, the keyword arguments (flags) among them.
    settings = scan.summary["settings"]
    assert settings["scan.b_core"] == [2.0, 3.0] and settings["scan.theta"] == [0.0]
    assert settings["cell.L"] == 64


def test_fit_regime_two_never_fits_a_lower_bound():
    # Exact Regime II points at one R, then a capped slide whose bound lies 5% under the law:
    # flagged, it changes nothing (not fitted; it does not rise past the lowest point);
    # unflagged, it is a fifth point of the window and moves c0.
    c0 = 0.2
    x = np.array([8.0, 15.0, 30.0, 60.0, 90.0])
    mu = np.array([asperity.regime_two_law(v, c0) for v in x])
    mu[4] *= 0.95
    R = np.full(5, 535.0)
    a = x.copy()
    flags = np.array([0, 0, 0, 0, 1])
    with_bound = asperity.fit_regime_two(x, mu, a=a, R=R, lower_bound=flags)
    without = asperity.fit_regime_two(x[:4], mu[:4], a=a[:4], R=R[:4])
    unflagged = asperity.fit_regime_two(x, mu, a=a, R=R)
    assert with_bound["valid"] and without["valid"] and unflagged["valid"]
    assert with_bound["c0"] == without["c0"]
    assert with_bound["points"] == 4
    assert unflagged["points"] == 5
    assert unflagged["c0"] != without["c0"]


def test_friction_sweep_takes_the_slide_flags(tmp_path):
    # A sweep's slide settings as keyword arguments (the slide scene's flags): they reach every
    # point as the scene's keys would (tests/regression/sweep_flags.sh checks the rows equal).
    scene = tmp_path / "tiny.toml"
    scene.write_text("[sweep]\nR = [535]\na = [4]\n[slide]\ndistance = 0.6\n[fft]\nthreads = 1\n")
    sweep = tools.friction_sweep(scene, out=tmp_path / "sw", alpha=0.6, tolerance=1e-7,
                                 step_growth=2)
    rows = sweep.tables["sweep"]
    assert len(rows) == 1 and rows["alpha"][0] == 0.6
    point = json.loads((tmp_path / "sw" / "points" / "a4_R535" / "summary.json").read_text())
    assert point["settings"]["contact.alpha"] == 0.6
    assert point["settings"]["solver.tolerance"] == 1e-7
    assert point["settings"]["slide.step_growth"] == 2
    with pytest.raises(RuntimeError, match="--tip-angle and --tip-angles"):
        tools.friction_sweep(scene, out=tmp_path / "bad", tip_angle=1, tip_angles=[2, 3])


def test_stub_defaults_are_the_modules():
    # _asperity.pyi restates every default of the compiled module for type checkers; the module
    # takes them from the C++ structs (Material, ContactScene, RegimeTwoFitOptions, ...). Each
    # default in the stub must be the one the module's own signature shows.
    import ast
    import re

    import asperity._asperity as compiled

    stub = pathlib.Path(compiled.__file__).with_name("_asperity.pyi")
    tree = ast.parse(stub.read_text())
    checked = 0

    def runtime_defaults(obj):
        first = obj.__doc__.splitlines()[0]
        return {m.group(1): m.group(2)
                for m in re.finditer(r"(\w+): [^=,()\[\]]+(?:\[[^\]]*\])? = ([^,)]+)", first)}

    def compare(node, obj, where):
        nonlocal checked
        args = node.args.args
        defaults = dict(zip([a.arg for a in args[len(args) - len(node.args.defaults):]],
                            node.args.defaults))
        shown = runtime_defaults(obj)
        for name, value in defaults.items():
            if not isinstance(value, ast.Constant):
                continue
            assert name in shown, f"{where}: {name} has no default in the module: {shown}"
            assert ast.literal_eval(value) == ast.literal_eval(shown[name]), (where, name)
            checked += 1

    for node in tree.body:
        if isinstance(node, ast.FunctionDef) and hasattr(compiled, node.name):
            compare(node, getattr(compiled, node.name), node.name)
        elif isinstance(node, ast.ClassDef) and hasattr(compiled, node.name):
            for item in node.body:
                if isinstance(item, ast.FunctionDef) and item.name == "__init__":
                    compare(item, getattr(compiled, node.name).__init__, node.name)
    # GF constructors, find_lines, front_stresses, control_parameter, predict, forecast,
    # fit_regime_two: dozens of defaults.
    assert checked >= 30, checked


def test_stub_names_are_the_modules():
    # The stub describes the whole module: every public name of the module is in it, every
    # function, class, method and attribute of the stub is in the module, and each function's
    # and method's parameters (names, in order) are those of the module's own signature (the
    # first line of its pybind11 docstring).
    import ast
    import re

    import asperity._asperity as compiled

    stub = pathlib.Path(compiled.__file__).with_name("_asperity.pyi")
    tree = ast.parse(stub.read_text())

    def runtime_names(obj):
        first = (obj.__doc__ or "").splitlines()[0] if obj.__doc__ else ""
        m = re.match(r"[\w.]+\((.*)\)\s*->", first)
        assert m and not m.group(1).startswith("*args"), f"no single signature: {first!r}"
        return [n for n in re.findall(r"(?:^|, )(\**\w+): ", m.group(1)) if n != "self"]

    def stub_names(node):
        a = node.args
        return [x.arg for x in a.posonlyargs + a.args + a.kwonlyargs if x.arg != "self"]

    stubbed, compared, attributes = set(), 0, 0
    for node in tree.body:
        if isinstance(node, ast.AnnAssign):
            stubbed.add(node.target.id)
            assert hasattr(compiled, node.target.id), node.target.id
        if not isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            continue
        stubbed.add(node.name)
        assert hasattr(compiled, node.name), f"{node.name}: in the stub, not in the module"
        if isinstance(node, ast.FunctionDef):
            assert stub_names(node) == runtime_names(getattr(compiled, node.name)), node.name
            compared += 1
            continue
        cls = getattr(compiled, node.name)
        for item in node.body:
            name = item.target.id if isinstance(item, ast.AnnAssign) else getattr(item, "name", None)
            if name is None:
                continue
            where = f"{node.name}.{name}"
            assert hasattr(cls, name), f"{where}: in the stub, not in the module"
            is_property = isinstance(item, ast.FunctionDef) and any(
                isinstance(d, ast.Name) and d.id == "property" for d in item.decorator_list)
            if isinstance(item, ast.AnnAssign) or is_property:
                attributes += 1
            elif name == "__init__" or not name.startswith("__"):
                assert stub_names(item) == runtime_names(getattr(cls, name)), where
                compared += 1
    public = {n for n in dir(compiled) if not n.startswith("_")}
    assert public <= stubbed, f"not in the stub: {sorted(public - stubbed)}"
    # 21 signatures and 8 attributes when this test was written.
    assert compared >= 20 and attributes >= 8, (compared, attributes)


def test_a_boolean_setting_takes_python_true(tmp_path):
    # tools.py passes True (NumPy's too) as a bare flag; a boolean setting's flag alone is true
    # (--xyz), so xyz=True writes every snapshot as extended XYZ beside its NetCDF file.
    slide = tools.contact_slide(out=tmp_path / "s", a=8, threads=1, xyz=np.True_)
    snapshots = tmp_path / "s" / "snapshots"
    assert sorted(p.stem for p in snapshots.glob("*.xyz")) == sorted(
        p.stem for p in snapshots.glob("*.nc")) != []
    assert slide.summary["settings"]["output.xyz"] is True
    # "false" (False leaves the flag out) turns off a scene's true.
    scene = tmp_path / "xyz.toml"
    scene.write_text("[contact]\na = 8\n[output]\nxyz = true\n[fft]\nthreads = 1\n")
    off = tools.contact_slide(scene, out=tmp_path / "off", xyz="false")
    assert off.summary["settings"]["output.xyz"] is False
    assert not list((tmp_path / "off" / "snapshots").glob("*.xyz"))
