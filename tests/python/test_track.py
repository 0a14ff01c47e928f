"""hbfriction.track() and optimize(method="tracking"): the same curves as hbf track, checked
against independent references (the paper's limit friction coefficient; FRFs at the optimum)."""
import math
import warnings

import numpy as np
import pytest

import hbfriction as hb


def coulomb(mu, **kw):
    return hb.absorber("coulomb", fe=1.0, mu=mu, **kw)


def test_peaks_follow_the_frfs_refined_peaks():
    r = hb.track(coulomb, 0.6, 0.8, omega=0.91, at=[0.7])
    assert r.outcome == "completed" and r.exact and r.feature == "peak"
    (c,) = r.curves
    assert c.status == "completed" and c.p[0] == 0.6 and c.p[-1] == 0.8
    k = int(np.flatnonzero(c.kind == "at")[0])
    b = hb.frf(coulomb(0.7))
    assert abs(c.w[k] - b.peak["w"]) < 1e-8 * c.w[k]
    assert abs(c.value[k] - b.peak["value"]) < 1e-8 * c.value[k]
    assert np.all(c.curvature < 0)


def test_stick_boundaries_are_the_limit_friction_coefficient():
    r = hb.track(coulomb, 0.3, 1.5, feature="boundary")
    stick = [c for c in r.curves if c.boundary == "stick|stick-slip"]
    assert len(stick) == 2
    for c in stick:
        assert c.status == "completed"
        for mu, w in zip(c.p, c.w):
            limit = 1.0 * 0.1 * w * w / abs(1.0 - 1.1 * w * w)  # fe r w^2 / |1 - (1 + r) w^2|
            assert abs(limit - mu) < 1e-10 * mu


def test_optimize_by_tracking_agrees_with_the_frf_at_its_optimum():
    def tuned(mu):
        return hb.absorber("coulomb", mu=mu, wa=1 / 1.1)

    r = hb.optimize(tuned, 0.005, 5.0, method="tracking", threads=2)
    assert r.status == "converged" and r.kind == "equal peaks" and r.outcome == "completed"
    assert len(r.trace["parameter"]) == 0 and r.frfs > 13 and r.solves > 0
    b = hb.frf(tuned(r.parameter))
    assert abs(b.peak["value"] - r.peak["value"]) < 1e-8 * r.peak["value"]
    assert 0.1527 < r.parameter < 0.1528


def test_bad_input_and_statuses():
    with pytest.raises(ValueError, match="no peak of y1 within 10 %"):
        hb.track(coulomb, 0.6, 0.8, omega=1.45)
    with pytest.raises(ValueError, match="feature = 'fold2' is not known"):
        hb.track(coulomb, 0.6, 0.8, feature="fold2")
    with pytest.raises(ValueError, match="p_end = 0.6 is out of range"):
        hb.track(coulomb, 0.6, 0.6)
    with pytest.raises(ValueError, match="method = 'newton' is not known"):
        hb.optimize(coulomb, 0.1, 1.0, method="newton")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        r = hb.track(coulomb, 0.6, 1.0, omega=0.91, wmax=0.92)
    assert r.curves[0].status == "left_range" and r.outcome == "incomplete"
    assert any(issubclass(w.category, hb.IncompleteResultWarning) for w in caught)


def test_folds_merge_in_a_cusp():
    import os
    path = os.path.join(os.environ["HBF_SOURCE_DIR"], "examples", "systems", "dahl_superharmonic_fold.toml")
    base = hb.load(path)

    def scaled(fe):
        s = hb.load(path)
        s.excitation = np.asarray(base.excitation) * fe
        return s

    r = hb.track(scaled, 1.0, 0.5, feature="fold", error_points=0)  # the folds are checked, not the FRF's accuracy
    assert r.outcome == "completed" and r.feature == "fold" and not r.exact
    assert [c.status for c in r.curves] == ["vanished", "vanished"]
    (cusp,) = [e for e in r.events if e["kind"] == "cusp"]
    assert 0.6 < cusp["p"] < 0.8
    # the folds at the start are the FRF's
    folds = hb.frf(base).folds
    assert abs(r.curves[0].w[0] - folds[0]["w"]) < 1e-6 * folds[0]["w"]


def test_a_time_limit_stops_the_curves_where_they_are():
    # The Dahl absorber's peaks over fe in steps of at most 1e-4 of the range take far more than
    # 1 s: stopped, every curve ends with status stopped (incomplete, a warning).
    with pytest.warns(hb.IncompleteResultWarning, match="time limit of 1 s"):
        r = hb.track(lambda fe: hb.absorber("dahl", fe=fe, mu=0.5), 0.8, 1.0, max_step=1e-4, time_limit=1)
    assert r.outcome == "incomplete"
    assert r.curves and all(c.status == "stopped" for c in r.curves)
