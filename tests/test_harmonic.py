"""Harmonic balance (stickslip.harmonic) against shooting (stickslip.periodic_orbit) and a
linear oscillator's closed form, and its refusal of laws that jump at zero slip."""
from __future__ import annotations

import math

import pytest

import stickslip as ss
from cases import gallery_denhartog as dh
from benchmarks.steady_bifurcations import caughey_amplitudes, jenkins_oscillator
from test_steady import G, forced_linear


def proposed_oscillator() -> ss.Model:
    model = ss.Model()
    b = model.add_body(1.0)
    model.add_spring(b, None, k=4.0)
    model.add_force(b, ss.signal.sine(10.0, 0.25))
    model.add_contact(b, None, "proposed", normal_force=G, mu_s=0.4, mu_k=0.3, v_s=0.5)
    return model


def test_harmonic_balance_converges_to_shooting() -> None:
    from stickslip.harmonic import harmonic_balance
    model = proposed_oscillator()
    orb = ss.periodic_orbit(model, method="dopri5")
    errors, prev = [], None
    for h in (1, 5, 15, 41):
        hb = harmonic_balance(model, h, guess=prev)
        prev = hb
        assert hb.residual < 1e-9
        errors.append(abs(hb.amplitude[0] / orb.amplitude[0] - 1.0))
    assert all(b < a for a, b in zip(errors, errors[1:])), errors
    assert errors[-1] < 1e-3


def test_harmonic_balance_of_a_linear_oscillator_is_exact_with_one_harmonic() -> None:
    from stickslip.harmonic import harmonic_balance
    hb = harmonic_balance(forced_linear(0.05, 0.3), 1)
    w = 2 * math.pi * 0.3
    assert hb.amplitude[0] == pytest.approx(1.0 / math.hypot(4.0 - w**2, 0.2 * w), rel=1e-10)
    with pytest.raises(ValueError, match="jumps at zero slip"):
        harmonic_balance(dh.model(2.0, 0.3), 3)


@pytest.mark.parametrize("w", [0.9, 1.2])
def test_one_harmonic_of_bilinear_hysteresis_is_caugheys_closed_form(w: float) -> None:
    """A mass on a spring and a Jenkins element (the elastoplastic law in its limit z_ba_ratio
    -> 1; benchmarks/steady_bifurcations.py, `jenkins_oscillator`), its states evaluated along
    the series' motion: with one harmonic and 2048 instants the amplitude is Caughey's (1960,
    J. Appl. Mech. 27(4) 640-643) one-harmonic closed form, (k a + C - m w^2 a)^2 + (S + c w
    a)^2 = P^2 with the element's describing function C = k_t a (beta - sin(2 beta) / 2) / pi,
    S = 4 F_s (1 - x_y / a) / pi, cos(beta) = 1 - 2 x_y / a (`caughey_residual`), to 1e-6
    (measured 2.4e-7 and 3.2e-8: the sampling of the force's kinks); with 256 instants to 1e-4
    (measured 2.0e-5 and 5.8e-6)."""
    from stickslip.harmonic import harmonic_balance
    exact = caughey_amplitudes(w)[0]
    coarse = harmonic_balance(jenkins_oscillator(w, 0.9999), 1, n_samples=256)
    fine = harmonic_balance(jenkins_oscillator(w, 0.9999), 1, n_samples=2048, guess=coarse)
    assert fine.residual < 1e-9 and coarse.residual < 1e-9
    assert fine.amplitude[0] == pytest.approx(exact, rel=1e-6)
    assert coarse.amplitude[0] == pytest.approx(exact, rel=1e-4)
