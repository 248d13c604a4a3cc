"""The elastic half-space on NumPy arrays, the scaling laws and the tools from Python
(issue 25). Analytic answers are stated with their tolerances."""
import json
import math
import os
import pathlib

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


def test_laws_are_the_formulas():
    x = np.array([2.0, 20.0, 200.0])
    c0 = 0.7
    np.testing.assert_allclose(asperity.regime_two_law(x, c0),
                               3 * (2 * c0) ** (2 / 3) * x ** (-2 / 3), rtol=1e-15)
    # a/b_core^0 = 4/(pi (1 - nu)) alpha a^2/(R d)
    assert asperity.control_parameter(43.0, 535.0, 0.7, 0.5) == pytest.approx(
        8 / math.pi * 0.7 * 43.0 ** 2 / 535.0, rel=1e-14)
    assert asperity.nucleation_condition(0.01, c0) == 1.0  # Regime I: mu = alpha
    p = asperity.predict(50.0, 2.0, c0=0.7, k1=1.0, k2=1.5)
    assert p["regime"] in ("I", "II", "III")
    assert p["mu_over_alpha"] == max(p["nucleation"], p["integrated"])
    with pytest.raises(ValueError):
        asperity.predict(50.0, 2.0, c0=-1.0, k1=1.0, k2=1.5)


@pytest.fixture(scope="module")
def fit(tmp_path_factory):
    out = tmp_path_factory.mktemp("fit")
    return tools.fit_scaling([DATA / "reference" / "sweep_R535.csv"], out=out, k1=3.0, k2=1.2)


def test_fit_scaling_from_python_is_the_tools_output(fit):
    assert fit.summary is not None and "c0" in json.dumps(fit.summary)
    assert "predictions" in fit.tables
    assert any(p.name == "collapse.png" for p in fit.figures)


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
                            peierls=scan.out, forecast_R=[800], forecast_a=[150, 300, 450])
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
    with pytest.raises(RuntimeError, match="fit_scaling failed"):
        tools.fit_scaling([tmp_path / "missing.csv"], out=tmp_path / "o")


def test_peierls_scan_from_python(tmp_path):
    scan = tools.peierls_scan(b_core=[2, 3], theta=[0], L=64, out=tmp_path / "ps")
    rows = scan.tables["peierls"]
    assert len(rows) == 2 and set(rows["b_core"]) == {2.0, 3.0}
    assert np.all(rows["tau_P_over_tau_max_pos"] > 0)


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
