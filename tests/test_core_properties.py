"""Property-based tests of the Python API (hypothesis): random scenes, laws, methods, controls
and parameters, including non-finite, huge, tiny, negative and zero values. Every call must end
in one of three ways: a ValueError whose message starts with the name of a parameter (or says
which names are unknown), an IntegrationError whose partial result is finite, or a finite
result on the requested grid.

The default run explores STICKSLIP_PROPERTY_EXAMPLES examples per test (300); a long run sets
it higher: STICKSLIP_PROPERTY_EXAMPLES=10000 .venv/bin/python -m pytest tests/test_core_properties.py
"""
from __future__ import annotations

import math
import os
import re
import warnings

import numpy as np
import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, event, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

import stickslip as ss  # noqa: E402

EXAMPLES = int(os.environ.get("STICKSLIP_PROPERTY_EXAMPLES", "300"))
SETTINGS = settings(max_examples=EXAMPLES, deadline=None, derandomize=True,
                    suppress_health_check=[HealthCheck.too_slow])

#: Names a ValueError may start with: every parameter, control and argument of the API.
NAMES = set(ss.REGISTRY["param"]) | set(ss.CONTROLS) | {
    "scene", "law", "method", "t_end", "x0", "v0", "z0", "n_out", "max_steps", "v", "n_grid",
    "threads", "keep_grid"}
NAMED = re.compile(r"^(?:row \d+ \([^)]*\): )?([a-z_0-9]+)(?:, [a-z_0-9]+)*: |^unknown parameter|^per-set arguments")

#: Numbers that probe the edges: non-finite, huge, tiny, negative, zero, and ordinary.
EDGY = st.one_of(
    st.sampled_from([math.nan, math.inf, -math.inf, 0.0, -0.0, 1e308, -1e308, 5e-324, 1e-300, -1.0]),
    st.floats(min_value=-1e3, max_value=1e3, allow_nan=False),
    st.floats(min_value=1e-9, max_value=1e2, allow_nan=False),
)


def _named(err: ValueError) -> bool:
    m = NAMED.match(str(err))
    return bool(m) and (m.group(1) is None or m.group(1) in NAMES)


def _finite(res) -> bool:
    return all(np.all(np.isfinite(a)) for a in (res.t, res.x, res.v, res.z))


@st.composite
def runs(draw):
    method = draw(st.sampled_from(ss.METHODS))
    info = ss.REGISTRY["method"][method]
    kw = {"scene": draw(st.sampled_from(ss.SCENES)), "law": draw(st.sampled_from(ss.LAWS)),
          "method": method,
          "t_end": draw(st.one_of(EDGY, st.floats(min_value=1e-3, max_value=5.0))),
          "n_out": draw(st.integers(min_value=1, max_value=50)),
          # bounded work: every example is quick, whatever the step size
          "max_steps": draw(st.integers(min_value=1, max_value=20_000))}
    if "h" in info["controls"]:
        kw["h"] = draw(st.one_of(EDGY, st.floats(min_value=1e-4, max_value=0.1)))
    for name in draw(st.lists(st.sampled_from(sorted(ss.REGISTRY["param"])), max_size=4, unique=True)):
        kw[name] = draw(EDGY)
    for name in draw(st.lists(st.sampled_from(["rtol", "atol", "hmin", "hmax", "h0", "x0", "v0"]),
                              max_size=3, unique=True)):
        if name in ("x0", "v0") or name in info["controls"]:
            kw[name] = draw(EDGY)
    return kw


@SETTINGS
@given(runs())
def test_simulate_ends_in_a_named_error_or_a_finite_result(kw):
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)     # h longer than the run: said, then run
            res = ss.simulate(**kw)
    except ValueError as err:
        event("ValueError")
        assert _named(err), str(err)
        return
    except ss.IntegrationError as err:
        event(type(err).__name__)
        assert _finite(err.result)
        return
    event("finite result")
    n_out = kw["n_out"]
    assert _finite(res) and res.t.size == n_out and res.x.size == n_out
    assert res.t[-1] == kw["t_end"]


@SETTINGS
@given(st.sampled_from(ss.LAWS), st.lists(EDGY, min_size=0, max_size=5),
       st.dictionaries(st.sampled_from(sorted(ss.REGISTRY["param"])), EDGY, max_size=3))
def test_friction_coefficient_is_finite_and_odd_or_a_named_error(law, v, params):
    try:
        mu = ss.friction_coefficient(law, v, **params)
    except ValueError as err:
        assert _named(err), str(err)
        return
    assert np.all(np.isfinite(mu)) and mu.shape == np.shape(v)
    assert np.array_equal(ss.friction_coefficient(law, -np.asarray(v), **params), -mu)


@SETTINGS
@given(st.lists(runs(), min_size=1, max_size=3))
@pytest.mark.filterwarnings("ignore::stickslip.UnstableStepWarning")   # random h: said, then run
def test_simulate_batch_rows_end_named_or_finite(rows):
    kw = {k: [r.get(k, r.get("h", 1e-3) if k == "h" else None) for r in rows]
          for k in ("scene", "law", "method", "t_end", "max_steps")}
    kw["h"] = [r.get("h", np.nan) for r in rows]
    extra = {k: v for k, v in rows[0].items() if k in ss.REGISTRY["param"] or k in ("x0", "v0")}
    try:
        b = ss.simulate_batch(n_grid=5, ignore_unused=True, **kw, **extra)   # random parameter sets
    except ValueError as err:
        assert _named(err), str(err)
        return
    assert len(b) == len(rows)
    for i, n in enumerate(b.n_state):      # each row's state finite, NaN beyond it (padding)
        assert np.all(np.isfinite(b.y_end[i, :n])) and np.all(np.isnan(b.y_end[i, n:]))
    assert np.all(np.isfinite(b.v_max))
