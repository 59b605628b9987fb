"""stickslip_one_contact: a model of one body with one contact and constant signals, the
structure the slope and belt presets are built as, runs the specialised kernels of the static
laws (tools/gen_kernels.py). Every model is specialised when it is built, a user's too
(`Model.from_scene` runs the scene's kernel: tests/test_model.py checks that bit for bit).
Checked here against the general model path: the same scene as a `Model` whose normal force
is a step signal that never steps within the run (a signal, not a number: the model stays a
general model_system) must give the same motion to rounding (1e-11 of its scale: the two
paths order their arithmetic differently) with the same steps and evaluations."""
from __future__ import annotations

import warnings

import numpy as np
import pytest

import stickslip as ss

KERNEL_LAWS = ("coulomb", "recurdyn", "proposed", "stribeck")


#: (scene, method, controls): RK4 on both scenes; the adaptive methods on the slope, where the
#: general model's error norm (on the slip, stickslip_model_system) and the presets' (on |y|, as
#: the scenes had) coincide, since the ground does not move there.
CASES = [("slope", "rk4", {"h": 1e-3}), ("belt", "rk4", {"h": 1e-3}),
         ("slope", "dopri5", {"rtol": 1e-8, "atol": 1e-10}), ("slope", "radau5", {"rtol": 1e-6, "atol": 1e-8})]


def _general(model: ss.Model) -> ss.Model:
    """`model` with its contact's normal force N as a step from N to N at t = 1e9 s: the same
    value at every time of the run, but a signal, which `specialise` does not fold."""
    (c,) = model.contacts
    n = c.normal_force.args[0]
    c.normal_force = ss.signal.step(1e9, n, n)
    return model


@pytest.mark.parametrize("law", KERNEL_LAWS)
@pytest.mark.parametrize("scene, method, controls", CASES)
def test_the_specialised_kernel_equals_the_general_model(scene, law, method, controls):
    t_end = 2.0 if scene == "slope" else 6.0
    v0 = 0.2 if scene == "slope" else None
    kw = {} if v0 is None else {"v0": v0}
    with warnings.catch_warnings():
        # the paper's discontinuous laws warn by design (RegularisedLawWarning): not the subject
        warnings.simplefilter("ignore")
        fast = ss.simulate(scene, law, method=method, t_end=t_end, n_out=201, **kw, **controls)
        general = ss.simulate(_general(ss.Model.from_scene(scene, law, per_unit_mass=True, **kw)), method=method,
                              t_end=t_end, n_out=201, **controls)
    assert fast.stats["status"] == general.stats["status"]
    x, v = np.atleast_2d(fast.x)[0], np.atleast_2d(fast.v)[0]   # a scene's one body: 1-D rows
    assert np.max(np.abs(x - general.x[0])) <= 1e-11 * max(1.0, float(np.max(np.abs(general.x))))
    assert np.max(np.abs(v - general.v[0])) <= 1e-11 * max(1.0, float(np.max(np.abs(general.v))))
    assert (fast.stats["nstep"], fast.stats["nfev"]) == (general.stats["nstep"], general.stats["nfev"])



def _block(law: str, idle_body: bool, damper: bool) -> ss.Model:
    """A block on a spring to the wall and on a belt (a force and a damper where asked); with
    idle_body a second body, free and at rest, that no element touches: the model is then not
    one body with one contact and runs the general model path (`model_contact`)."""
    m = ss.Model()
    m.add_body(2.0, x0=0.01, v0=0.1)
    m.add_spring(0, None, k=50.0, rest_length=0.02)
    if damper:
        m.add_damper(0, None, c=0.4)
        m.add_force(0, 1.5)
    m.add_contact(0, None, law, normal_force=19.6, surface_velocity=0.3)
    if idle_body:
        m.add_body(1.0)
    return m


@pytest.mark.parametrize("law", ["coulomb", "stribeck"])
@pytest.mark.parametrize("damper", [False, True])
def test_the_one_contact_contact_model_equals_the_general_one(law, damper):
    """moreau on the one-contact model's own contact model (`one_contact_contact`: its normal
    force, offset and W solve written for one body) against the general model's
    (`model_contact`) on the same block beside an idle body: the same operations in the same
    order. The one body's step problem is solved by the rule's one-contact closed form
    (`local_solve`), the two bodies' by the rule's rounds: Coulomb's levels are constants, so
    the block's motion is the same to the last bit, step for step; Stribeck's slip speed is
    solved by Newton on the slip curve in the one and by the rounds' levels in the other, the
    same answer to rounding."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fast = ss.simulate(_block(law, False, damper), method="moreau", h=1e-4, t_end=1.5, n_out=151)
        general = ss.simulate(_block(law, True, damper), method="moreau", h=1e-4, t_end=1.5, n_out=151)
    assert fast.stats["status"] == general.stats["status"] == 0
    if law == "coulomb":
        assert np.array_equal(np.atleast_2d(fast.x)[0], general.x[0])
        assert np.array_equal(np.atleast_2d(fast.v)[0], general.v[0])
    else:
        np.testing.assert_allclose(np.atleast_2d(fast.x)[0], general.x[0], rtol=0, atol=1e-12)
        np.testing.assert_allclose(np.atleast_2d(fast.v)[0], general.v[0], rtol=0, atol=1e-12)
    assert np.all(general.x[1] == 0.0)
    assert fast.stats["nstep"] == general.stats["nstep"]
