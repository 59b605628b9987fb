"""The registry drives the Python side (issue 41 item 7): the facade's constants are read from
the library (stickslip_registry's registry_text) rather than copied, one hmin default holds for
Python, Fortran and C (the Fortran and C halves: tests/fortran/test_core.f90 and
test_integrators.f90), and the figure style gives a law or method the registry adds a name,
a colour and a marker of its own with no edit."""
from __future__ import annotations

import numpy as np
import pytest

import stickslip as ss
from stickslip import core, model


def test_the_constants_are_the_registrys():
    const = ss.REGISTRY["const"]
    assert core._DEFAULT_MAX_EVENTS == const["max_events"]["value"] == 10000
    assert core._MAX_BLOCKS == const["max_blocks"]["value"] == 10**6
    assert core.RTOL_MIN == const["rtol_min"]["value"] == 100.0 * np.finfo(float).eps
    kinds = sorted(ss.REGISTRY["event"].items(), key=lambda kv: kv[1]["code"])
    assert core._EVENT_KINDS == tuple(k for k, _ in kinds) == ("stick", "slip", "reversal")
    assert [info["code"] for _, info in kinds] == [1, 2, 3]


def test_the_constants_act_as_the_library_does():
    """The limits read from the registry are where the library draws its lines."""
    ss.simulate("belt", "proposed", method="dopri5", t_end=0.1, n_out=2, rtol=core.RTOL_MIN)
    with pytest.raises(ValueError, match="rtol"):
        ss.simulate("belt", "proposed", method="dopri5", t_end=0.1, n_out=2, rtol=0.99 * core.RTOL_MIN)
    with pytest.raises(ValueError, match=rf"n_blocks: must be an integer in \[1, {core._MAX_BLOCKS}\]"):
        ss.simulate("chain", "coulomb", method="moreau", h=1e-3, t_end=0.01, n_blocks=core._MAX_BLOCKS + 1)


def test_one_hmin_default():
    """1e-6 s from the facade, as the library states it (HMIN_DEFAULT); Fortran's new_controls
    and C's option defaults are checked against the same constant in the Fortran suites."""
    assert core.CONTROL_DEFAULTS["hmin"] == ss.REGISTRY["const"]["hmin"]["value"] == 1e-6
    assert ss.REGISTRY["const"]["hmin"]["unit"] == "s"


def test_the_laws_that_jump_are_the_registrys():
    """The laws implicit_euler and galpha solve over their modes on a model: those with modes."""
    modes = {law: info["modes"] for law, info in ss.REGISTRY["law"].items()}
    assert model._JUMP_LAWS == tuple(law for law in ss.LAWS if modes[law] > 0) == ("coulomb", "karnopp")
    assert ss.REGISTRY["law"]["karnopp"]["doc"] == "Karnopp stick band |v| < dv, mu_k outside"   # a '|' kept


def test_the_style_is_keyed_from_the_registry():
    """Every registered law and method has a name, a colour and a marker, distinct within its
    kind; a list with a law the style has never seen gives it its own colour and a name."""
    from harness import style
    for names, colours in ((ss.LAWS, style.LAW_COLORS), (ss.METHODS, style.METHOD_COLORS)):
        assert list(colours) == list(names) and len(set(colours.values())) == len(names)
    assert list(style.METHOD_MARKERS) == list(ss.METHODS)
    assert set(ss.LAWS) <= set(style.LAW_NAMES) and set(ss.METHODS) <= set(style.METHOD_NAMES)
    laws = (*ss.LAWS, "toy_law", "another_law")
    colours = style.keyed(laws, style._LAW_COLORS, style.SPARE_COLORS)
    assert len(set(colours.values())) == len(laws)
    assert {k: colours[k] for k in ss.LAWS} == style.LAW_COLORS        # the others unchanged
    assert style.keyed(["toy_law"], style._LAW_NAMES, (), style._spaced) == {"toy_law": "toy law"}
    markers = style.keyed((*ss.METHODS, "toy_method"), style.METHOD_MARKERS, style.SPARE_MARKERS)
    assert len(set(markers.values())) == len(ss.METHODS) + 1
