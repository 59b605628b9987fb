"""An energy bound on the results of a model: a run whose mechanical energy exceeds what the
forces could have put in is wrong, whatever its status says.

The mechanical energy E = sum 1/2 m v^2 + sum 1/2 k (x_a - x_b - l0)^2 of a model changes by
the power of its forces: dampers and friction against the slip only take energy out (the laws
without internal states, whose coefficient mu(s) has the sign of the slip s), a force F on body
i puts in F v_i <= |F| sqrt(2 E / m_i), and a contact on a surface moving at w at most
mu_max N+ |w| (the friction force times the surface's speed; mu_max the largest |mu| of its law
over the slip velocities, N+ the normal force where positive). So E' <= a(t) sqrt(E) + b(t)
with a = sum |F_i| sqrt(2 / m_i) and b = sum mu_max N+ |w|, whence

    E(t) <= B(t) = ( sqrt(E(0) + int_0^t b) + 1/2 int_0^t a )^2,

(B^2's derivative exceeds a sqrt(B) + b). The bound holds between the output points too and
needs only the signals (integrated here on a fine grid, with a margin of MARGIN), not the
solution: a coarse output grid cannot raise a false alarm. It is exact for a free body pushed
along its velocity, and loose elsewhere (it counts every force as working at full speed): it
catches gross errors (an explicit method beyond its stability bound that did not blow up, an
energy-gaining scheme), not small ones. Models with laws that have internal states (their
bristles store energy) or whose mu does not oppose the slip are not checked.
"""
from __future__ import annotations

import math
import threading
from collections import OrderedDict
from collections.abc import Mapping
from typing import Any

import numpy as np

from .core import REGISTRY, friction_coefficient
from .signal import Signal

__all__ = ["EnergyBoundWarning", "energy_bound", "MARGIN"]

#: Relative margin on the signals' integrals and on the bound (their quadrature, mu_max's
#: sampling, rounding).
MARGIN: float = 1e-3
#: Points of the fine grid of the signals: at least this many, and 64 per period of the fastest
#: sine; none checked beyond MAX_POINTS. Between the corners (which join the grid) the signals
#: are linear or constant but for their sines, so the sines set the grid: 64 points a period
#: keep the quadrature's shortfall at a peak (1 - cos(pi/64) = 1.2e-3 of the peak over one
#: interval) within MARGIN of the integral.
MIN_POINTS, MAX_POINTS = 256, 2_000_000


class EnergyBoundWarning(UserWarning):
    """A model's result whose mechanical energy exceeds the bound of `energy_bound`."""


def _value(sig: Signal, t: np.ndarray) -> np.ndarray:
    """The signal at times t (as stickslip_signal evaluates it)."""
    k, a = sig.kind, sig.args
    if k == "constant":
        return np.full_like(t, a[0])
    if k == "step":
        return np.where(t < a[0], a[1], a[2])
    if k == "ramp":
        return a[2] * np.clip((t - a[0]) / a[1], 0.0, 1.0)
    if k == "sine":
        return a[0] * np.sin(2.0 * math.pi * a[1] * t + a[2]) + a[3]
    if k == "table":
        return np.interp(t, np.asarray(a[0]), np.asarray(a[1]))
    left, right = (_value(c, t) for c in sig.children)
    return {"add": left + right, "sub": left - right, "mul": left * right}[k]


def _features(sig: Signal, corners: list[float]) -> float:
    """Collect the signal's corners (steps, ramp ends, table points); its fastest frequency [Hz]."""
    k, a = sig.kind, sig.args
    if k == "step":
        corners.append(a[0])
    elif k == "ramp":
        corners.extend((a[0], a[0] + a[1]))
    elif k == "table":
        corners.extend(a[0])
    return max([abs(a[1]) if k == "sine" else 0.0] + [_features(c, corners) for c in sig.children])


def _mu_max(law: str, params: dict[str, float]) -> float | None:
    """The largest |mu| of `law` over slip velocities up to 1e3 m/s, or None when mu does not
    oppose the slip there or still grows at 1e3 m/s (no bound)."""
    v = np.concatenate([-np.geomspace(1e3, 1e-12, 1500), [0.0], np.geomspace(1e-12, 1e3, 1500)])
    mu = np.asarray(friction_coefficient(law, v, **params), dtype=np.float64)
    if not np.all(np.isfinite(mu)) or np.any(mu * v < 0.0):
        return None
    top = float(np.max(np.abs(mu)))
    if abs(mu[0]) > (1.0 - 1e-6) * top and abs(mu[0]) > abs(mu[1]):   # still rising at 1e3 m/s
        return None
    return top


def energy_bound(model: Any, t: np.ndarray, x: np.ndarray, v: np.ndarray,
                 arrays: Mapping[str, Any] | None = None) -> tuple[np.ndarray, np.ndarray] | None:
    """The mechanical energy E [J] of `model` at the output times `t` [s] (positions x and
    velocities v, shape (n_bodies, n_t), t[0] = 0) and its bound B [J] (see the module): a
    correct run has E <= B. None when the model is not checked (a law with internal states, a
    law whose mu does not oppose the slip or has no bound, signals too fast for the grid).
    `arrays`: `model.arrays()` where the caller has it (it identifies the model in the cache of
    the bounds)."""
    if t.size == 0 or t[0] != 0.0:
        return None
    mass = np.array([b.mass for b in model.bodies])
    e = (0.5 * mass) @ np.square(v)
    for a, b, k, l0 in model.springs:
        d = x[a] - (x[b] if b is not None else 0.0) - l0
        e = e + 0.5 * k * d * d
    bound = _cached_bound(model, t, model.arrays() if arrays is None else arrays, float(e[0]))
    return None if bound is None else (e, bound)


#: The bounds of the last CACHE_SIZE (model, output grid, initial energy) triples, by the
#: model's arrays, the grid and E(0): the same model run again on the same grid (a benchmark, a
#: study repeating a run) does not integrate its signals again.
CACHE_SIZE: int = 16
_CACHE: OrderedDict[bytes, np.ndarray | None] = OrderedDict()
_CACHE_LOCK = threading.Lock()


def _cached_bound(model: Any, t: np.ndarray, arrays: Mapping[str, Any], e0: float) -> np.ndarray | None:
    """`_bound(e0, *_signal_integrals(model, t))` (None where that is None), from the cache
    where the model (its `arrays`), the grid and e0 were seen."""
    key = b"|".join([np.ascontiguousarray(arrays[k]).tobytes() for k in sorted(arrays) if k != "pkeys"]
                    + [arrays["pkeys"].encode(), np.ascontiguousarray(t, dtype=np.float64).tobytes(),
                       np.float64(e0).tobytes()])
    with _CACHE_LOCK:
        if key in _CACHE:
            _CACHE.move_to_end(key)
            return _CACHE[key]
    integrals = _signal_integrals(model, t)
    found = None if integrals is None else _bound(e0, *integrals)
    if found is not None:
        found.flags.writeable = False      # shared by the calls that find it here
    with _CACHE_LOCK:
        _CACHE[key] = found
        while len(_CACHE) > CACHE_SIZE:
            _CACHE.popitem(last=False)
    return found


def _signal_integrals(model: Any, t: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """int_0^t a and int_0^t b (see the module) at the output times t, or None when the model
    is not checked (`energy_bound`)."""
    for c in model.contacts:
        if REGISTRY["law"][c.law]["n_states"] != 0 or c.law == "gms":
            return None
    mass = np.array([b.mass for b in model.bodies])
    corners: list[float] = []
    f_max = 0.0
    terms_a = [(s, math.sqrt(2.0 / mass[i])) for i, s in model.forces]
    terms_b = []
    for c in model.contacts:
        if c.surface_velocity is None:
            continue
        mu = _mu_max(c.law, dict(c.params))
        if mu is None:
            return None
        terms_b.append((c.normal_force, c.surface_velocity, mu))
    for s in [s for s, _ in terms_a] + [x for n, w, _ in terms_b for x in (n, w)]:
        f_max = max(f_max, _features(s, corners))
    t_end = float(t[-1])
    if not terms_a and not terms_b:           # nothing puts energy in: E <= E(0)
        return np.zeros_like(t), np.zeros_like(t)
    points = max(MIN_POINTS, int(64 * f_max * t_end) + 1)
    if points > MAX_POINTS:
        return None
    fine = np.union1d(np.linspace(0.0, t_end, points),
                      np.concatenate([t, [c for c in corners if 0.0 < c < t_end]]))
    a_t = np.zeros_like(fine)
    for s, scale in terms_a:
        a_t += np.abs(_value(s, fine)) * scale
    b_t = np.zeros_like(fine)
    for n, w, mu in terms_b:
        b_t += mu * np.maximum(_value(n, fine), 0.0) * np.abs(_value(w, fine))

    def integral(y: np.ndarray) -> np.ndarray:
        """An upper estimate of int_0^t y (y >= 0) at the output times: each interval of the
        fine grid at the larger of its ends' values (exact for a piecewise-constant y whose
        corners are grid points, above the integral where y is monotone between points)."""
        cum = np.concatenate([[0.0], np.cumsum(np.maximum(y[1:], y[:-1]) * np.diff(fine))])
        return np.interp(t, fine, cum)
    return integral(a_t), integral(b_t)


def _bound(e0: float, int_a: np.ndarray, int_b: np.ndarray) -> np.ndarray:
    """( sqrt(E0 + int b) + 1/2 int a )^2, with the margins."""
    int_a, int_b = int_a * (1.0 + MARGIN), int_b * (1.0 + MARGIN)
    return (np.sqrt(e0 + int_b) + 0.5 * int_a) ** 2 * (1.0 + MARGIN) + 1e-14 * max(e0, 1e-300)
