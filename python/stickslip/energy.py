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

import functools
import math
import threading
import warnings
from collections import OrderedDict
from collections.abc import Mapping
from typing import Any

import numpy as np

from . import core
from .core import CHATTER_FRACTION, CONTROL_DEFAULTS, REGISTRY, friction_coefficient
from .signal import Signal

__all__ = ["EnergyBoundWarning", "ConsistencyWarning", "energy_bound", "check_result", "MARGIN"]

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


def _interval_max(sig: Signal, t: np.ndarray) -> np.ndarray:
    """The largest value of the signal over each output interval [t_i, t_(i+1)]: at its ends,
    at the signal's corners inside it (a table's peak, a normal force that rises above 0 and
    falls back between two samples) and, for a signal with a sine or a product, at points in
    between (8 an interval, and 64 a period of the fastest sine), so that a force that acts
    only between two samples is not missed."""
    if sig.kind == "constant":
        return np.full(t.size - 1, float(sig.args[0]))
    corners: list[float] = []
    freq = _features(sig, corners)
    dt = np.diff(t)
    # between its corners a signal without sines or products is linear: its ends and corners
    # hold its largest value; otherwise points between them too
    parts = np.full(dt.size, 8 if freq > 0.0 or _has_product(sig) else 1, dtype=np.int64)
    if freq > 0.0:
        parts = np.maximum(parts, np.ceil(64.0 * freq * dt).astype(np.int64))
    parts = np.minimum(parts, max(1, MAX_POINTS // max(dt.size, 1)))
    rep = np.repeat(np.arange(dt.size), parts)                  # each point's interval
    offs = np.arange(rep.size) - np.repeat(np.cumsum(parts) - parts, parts)
    inner = t[:-1][rep] + offs / parts[rep] * dt[rep]
    c = np.asarray(corners, dtype=np.float64)
    c = c[(c > t[0]) & (c < t[-1])]
    grid = np.unique(np.concatenate([t, inner, c, np.nextafter(c, -np.inf)]))
    vals = _value(sig, grid)
    start = np.searchsorted(grid, t[:-1])
    stop = np.searchsorted(grid, t[1:])        # each interval's points, its end included
    out = np.maximum.reduceat(vals, start)[:dt.size] if dt.size else vals[:0]
    # reduceat runs each from its start to the next start (the next interval's first point is
    # this one's end): take the end in too
    return np.maximum(out, vals[stop])


def _has_product(sig: Signal) -> bool:
    """Does the signal multiply two signals anywhere in its tree?"""
    return sig.kind == "mul" or any(_has_product(c) for c in sig.children)


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


#: The slip velocities at which _mu_max samples a law [m/s]: 0 and 1e-12 .. 1e3 either way.
_MU_GRID: np.ndarray = np.concatenate([-np.geomspace(1e3, 1e-12, 1500), [0.0], np.geomspace(1e-12, 1e3, 1500)])


def _mu_max(law: str, params: Mapping[str, float]) -> float | None:
    """The largest |mu| of `law` over slip velocities up to 1e3 m/s, or None when mu does not
    oppose the slip there or still grows at 1e3 m/s (no bound); remembered per law and
    parameters (every checked run of a model asks for each of its contacts)."""
    return _mu_max_of(law, tuple(sorted(params.items())))


@functools.lru_cache(maxsize=256)
def _mu_max_of(law: str, items: tuple[tuple[str, float], ...]) -> float | None:
    """_mu_max of a law and its parameters as sorted (name, value) pairs."""
    params = dict(items)
    v = _MU_GRID
    mu = np.asarray(friction_coefficient(law, v, **params), dtype=np.float64)
    if not np.all(np.isfinite(mu)) or np.any(mu * v < 0.0):
        return None
    top = float(np.max(np.abs(mu)))
    if abs(mu[0]) > (1.0 - 1e-6) * top and abs(mu[0]) > abs(mu[1]):   # still rising at 1e3 m/s
        return None
    if law in ("karnopp", "stribeck"):  # their stick (Karnopp's band; the set-valued methods'
        # and the modal steps' static set) holds with up to mu_s, which mu(v) alone may not reach
        top = max(top, abs(params.get("mu_s", REGISTRY["param"]["mu_s"]["default"])))
    return top


def energy_bound(model: Any, t: np.ndarray, x: np.ndarray, v: np.ndarray,
                 arrays: Mapping[str, Any] | None = None, memo: list[Any] | None = None
                 ) -> tuple[np.ndarray, np.ndarray] | None:
    """The mechanical energy E [J] of `model` at the output times `t` [s] (positions x and
    velocities v, shape (n_bodies, n_t), t[0] = 0) and its bound B [J] (see the module; read-only): a
    correct run has E <= B. None when the model is not checked (a law with internal states, a
    law whose mu does not oppose the slip or has no bound, signals too fast for the grid, a
    drive, whose work no force of the model bounds).
    `arrays`: `model.arrays()` where the caller has it; `memo`: the list that keeps what the
    check read of this model's content (`_plan`; its arrays identify it otherwise)."""
    if not _bounded(model, t):
        return None
    return _energy_and_bound(model, _plan(model, t, arrays, memo), x, v)


def _bounded(model: Any, t: np.ndarray) -> bool:
    """Whether `energy_bound` may bound the model's energy on the grid t: t from 0, no drive."""
    return t.size > 0 and t[0] == 0.0 and not getattr(model, "drives", None)


def _energy_and_bound(model: Any, plan: "_Plan", x: np.ndarray, v: np.ndarray
                      ) -> tuple[np.ndarray, np.ndarray] | None:
    """`energy_bound` of a model without drives on its plan's grid (t[0] = 0)."""
    e = (0.5 * plan.mass) @ np.square(v)
    springs = plan.springs
    if springs.count:
        d = springs.stretch(x) - springs.rest[:, None]
        # E + each spring's 1/2 k d^2 in turn (a reduction over the rows adds them in order)
        e = np.add.reduce(np.concatenate([e[None, :], 0.5 * springs.coef[:, None] * d * d]), axis=0)
    bound = plan.bound(model, float(e[0]))
    return None if bound is None else (e, bound)


#: What the check read of the last CACHE_SIZE (model, output grid) pairs it was not given a
#: memo for (`_plan`), by the model's arrays and the grid: the same model run again on the
#: same grid (a benchmark, a study repeating a run, the batch's rows) does not integrate its
#: signals again.
CACHE_SIZE: int = 16
_CACHE: OrderedDict[bytes, "_Plan"] = OrderedDict()
_CACHE_LOCK = threading.Lock()
#: Grids a memo keeps plans for (`_plan`): a model run on a fixed grid needs one; a run with
#: every_step output has a grid of its own each time.
MEMO_GRIDS: int = 4
#: A part of a _Plan not computed yet.
_UNSET: Any = object()


class _Links:
    """The springs or the dampers of a model as arrays: each one's bodies a and b (b = n, the
    ground's row, for None), its coefficient k or c [N/m] or [N s/m] and rest length [m]
    (0 for a damper), and the order in which the check adds their forces to the bodies: for
    each element, a with the sign +1, then b with -1 (not the ground); `layers` splits that
    order into rounds in which each body comes once (a body's k-th term in round k), so that
    each round is one array addition and every body's terms are added in order."""

    __slots__ = ("count", "a", "b", "coef", "rest", "elem", "body", "sign", "layers")

    def __init__(self, links: list[tuple[Any, ...]], n: int) -> None:
        self.count = len(links)
        self.a = np.array([link[0] for link in links], dtype=np.intp)
        self.b = np.array([n if link[1] is None else link[1] for link in links], dtype=np.intp)
        self.coef = np.array([link[2] for link in links], dtype=np.float64)
        self.rest = np.array([link[3] if len(link) > 3 else 0.0 for link in links], dtype=np.float64)
        order = [(i, body, sign) for i, link in enumerate(links) for body, sign in ((link[0], 1.0), (link[1], -1.0))
                 if body is not None]
        self.elem = np.array([i for i, _, _ in order], dtype=np.intp)
        self.body = np.array([body for _, body, _ in order], dtype=np.intp)
        self.sign = np.array([sign for _, _, sign in order], dtype=np.float64)
        seen: dict[int, int] = {}
        rounds: list[list[int]] = []
        for k, (_, body, _) in enumerate(order):
            seen[body] = seen.get(body, -1) + 1
            if seen[body] == len(rounds):
                rounds.append([])
            rounds[seen[body]].append(k)
        self.layers = [np.array(r, dtype=np.intp) for r in rounds]

    def stretch(self, y: np.ndarray) -> np.ndarray:
        """y_a - y_b of each element (y_b = 0 for the ground) from the bodies' rows y, one row
        an element."""
        ground = np.concatenate([y, np.zeros((1, y.shape[1]))])
        return ground[self.a] - ground[self.b]

    def add_means(self, f: np.ndarray, mean_f: np.ndarray, slack: np.ndarray) -> None:
        """Add each element's force f (one row an element, at the output times) to its bodies'
        trapezoid means over the output intervals (mean_f, +f on a and -f on b) and half its
        change to their allowances (slack), in the order of `body`."""
        mean = self.sign[:, None] * 0.5 * (f[:, 1:] + f[:, :-1])[self.elem]
        half = (0.5 * np.abs(np.diff(f, axis=1)))[self.elem]
        for k in self.layers:
            body = self.body[k]
            mean_f[body] += mean[k]
            slack[body] += half[k]


class _Plan:
    """What the consistency check reads of a model on an output grid t (shape (n_t,)), which
    depends on neither its motion nor the method: the bodies' masses, whether its laws are
    checked (no internal states), its driven bodies, whether nothing puts energy in (no force,
    drive or moving surface), and, computed when first asked, the signals' integrals of the
    energy bound (`_signal_integrals`) and the friction check's terms (`_friction_terms`). One
    for a model's content and grid (`_plan`); the model is passed to the parts computed later
    (a model of that content)."""

    __slots__ = ("t", "mass", "springs", "dampers", "checked", "driven", "closed", "_integrals", "_friction",
                 "_bound")

    def __init__(self, model: Any, t: np.ndarray) -> None:
        self.t = np.array(t, dtype=np.float64)
        self.t.flags.writeable = False
        self.mass = np.array([b.mass for b in model.bodies], dtype=np.float64)
        self.springs = _Links(model.springs, self.mass.size)
        self.dampers = _Links(model.dampers, self.mass.size)
        self.checked = not any(REGISTRY["law"][c.law]["n_states"] != 0 or c.law == "gms" for c in model.contacts)
        self.driven = np.array([model.driven(j) for j in range(len(model.bodies))], dtype=bool)
        self.closed = not (model.forces or getattr(model, "drives", None)
                           or any(c.surface_velocity is not None for c in model.contacts))
        self._integrals: Any = _UNSET
        self._friction: Any = _UNSET
        self._bound: tuple[float, np.ndarray] | None = None

    def bound(self, model: Any, e0: float) -> np.ndarray | None:
        """`_bound(e0, *integrals)` (None where the integrals are None); the last one kept (a
        run of the model again starts from the same energy). Read-only: shared by the calls."""
        integrals = self.integrals(model)
        if integrals is None:
            return None
        last = self._bound
        if last is not None and last[0] == e0:
            return last[1]
        found = _bound(e0, *integrals)
        found.flags.writeable = False
        self._bound = (e0, found)
        return found

    def integrals(self, model: Any) -> tuple[np.ndarray, np.ndarray] | None:
        """`_signal_integrals(model, t)`, computed once."""
        if self._integrals is _UNSET:
            self._integrals = _signal_integrals(model, self.t)
        return self._integrals

    def friction(self, model: Any) -> tuple[list[tuple[int, np.ndarray, np.ndarray]], np.ndarray] | None:
        """`_friction_terms(model, t)`, computed once."""
        if self._friction is _UNSET:
            self._friction = _friction_terms(model, self.t, self.mass.size)
        return self._friction


def _plan(model: Any, t: np.ndarray, arrays: Mapping[str, Any] | None = None,
          memo: list[Any] | None = None) -> _Plan:
    """The _Plan of `model` on the grid `t`: from `memo` where given (a list kept with the run
    of the model's content in simulate's cache, `stickslip.model.simulate_model`: its plans by
    grid, newest first, at most MEMO_GRIDS), else, and for a grid the memo has not seen (which
    then keeps it), from _CACHE by the model's `arrays` (`model.arrays()` where None) and the
    grid: a model built again with the same content finds it there."""
    if memo is not None:
        with _CACHE_LOCK:
            for plan in memo:
                if plan.t.shape == t.shape and np.array_equal(plan.t, t):
                    return plan
    arrays = model.arrays() if arrays is None else arrays
    key = b"|".join([np.ascontiguousarray(arrays[k]).tobytes() for k in sorted(arrays) if k != "pkeys"]
                    + [arrays["pkeys"].encode(), np.ascontiguousarray(t, dtype=np.float64).tobytes()])
    with _CACHE_LOCK:
        plan = _CACHE.get(key)
        if plan is not None:
            _CACHE.move_to_end(key)
    if plan is None:
        plan = _Plan(model, t)
        with _CACHE_LOCK:
            _CACHE[key] = plan
            while len(_CACHE) > CACHE_SIZE:
                _CACHE.popitem(last=False)
    if memo is not None:
        with _CACHE_LOCK:
            memo.insert(0, plan)
            del memo[MEMO_GRIDS:]
    return plan


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


# -- the consistency check of a result (docs/guide/results.md, "The consistency check") --------

class ConsistencyWarning(UserWarning):
    """A result that fails the consistency check (`check_result`): its positions disagree with
    the integral of its velocities, its energy rises where only friction and dampers act, or a
    body's friction exceeds its laws' bound. The message gives the numbers; the same sentence
    is in ``Result.stats["notes"]``."""


#: Safety factor on the allowances of the consistency check (its error estimates are
#: estimates: the variation of the acceleration within an output interval is taken from the
#: mean accelerations of the interval and its neighbours).
SAFETY: float = 4.0
#: Rounding: the allowance never falls below ROUNDING eps times the scale of the quantity.
ROUNDING: float = 64.0
#: The kinematic check needs an output grid that resolves the motion: at least MIN_INTERVALS
#: intervals, and v reversing its direction between fewer than CHATTER_FRACTION of them (the
#: batch's rule for a run that chattered at the grid's scale, stickslip.batch). On a coarser
#: grid the acceleration's variation within an interval cannot be estimated from its
#: neighbours, and the run is not checked.
MIN_INTERVALS: int = 64
#: An absolute floor of the kinematic check's allowance [m], far below any length a run
#: resolves (a body held at x = 0 may carry velocities of 1e-31 m/s).
TINY: float = 1e-20


class _Rows:
    """A run's output as the check reads it: the times t [s], the positions x [m] and
    velocities v [m/s] (a row a body), their differences over the output intervals (dt, dx,
    dv; ok: dt > 0), |dv| (adv) and each body's max |v| (vmax), each taken once."""

    __slots__ = ("t", "x", "v", "dt", "ok", "dx", "dv", "adv", "vmax")

    def __init__(self, t: np.ndarray, x: np.ndarray, v: np.ndarray, dt: np.ndarray | None = None) -> None:
        self.t, self.x, self.v = t, x, v
        self.dt = np.diff(t) if dt is None else dt
        self.ok = self.dt > 0.0
        self.dx, self.dv = np.diff(x, axis=1), np.diff(v, axis=1)
        self.adv, self.vmax = np.abs(self.dv), np.max(np.abs(v), axis=1)

    def distinct(self) -> "_Rows":
        """The rows at distinct times: one row each of repeated times (every_step at an
        event), the first."""
        if self.ok.all():
            return self
        keep = np.concatenate([[True], self.ok])
        return _Rows(self.t[keep], self.x[:, keep], self.v[:, keep], self.dt[self.ok])


def _resolved(rows: _Rows) -> np.ndarray:
    """Whether an output grid resolves each body's motion (`rows` at distinct times): at least
    MIN_INTERVALS intervals, and v reversing its direction between fewer than CHATTER_FRACTION
    of them (as stickslip.batch counts a row's reversals); one bool a body."""
    dv = rows.dv
    if dv.shape[1] < MIN_INTERVALS:
        return np.zeros(dv.shape[0], dtype=bool)
    big = rows.adv > ROUNDING * np.finfo(float).eps * rows.vmax[:, None]
    reversals = np.count_nonzero((dv[:, 1:] * dv[:, :-1] < 0.0) & big[:, 1:] & big[:, :-1], axis=1)
    return reversals < CHATTER_FRACTION * (dv.shape[1] - 1)


def _kinematic(rows: _Rows, method: Mapping[str, Any], h: float | None, tol_x: np.ndarray, nstep: int,
               kinks: np.ndarray | None, resolved: np.ndarray) -> tuple[int, str] | None:
    """The change of x against the trapezoid integral of v on the output grid, per interval
    and from t = 0, for each body (`rows` at distinct times; see the results guide; `resolved`: the bodies whose motion the grid resolves, `_resolved`, the others not
    checked): the first body whose defect is beyond SAFETY times its allowance and its failure
    as a sentence, or None. tol_x: atol + rtol max|x| of an adaptive method's error test on
    each body's x [m]; nstep: its steps; kinks: the times of the run's events (stick, slip,
    reversal, a normal force through 0) [s]: an interval that holds one strictly inside has a
    corner of a that its neighbours do not show (on a grid that samples once a period, every
    interval may), and it and the sums over it are not checked."""
    t, x, v, dt, dx, dv, change, vmax = rows.t, rows.x, rows.v, rows.dt, rows.dx, rows.dv, rows.adv, rows.vmax
    bodies = None                             # all of them
    if not resolved.all():
        if not resolved.any():
            return None
        bodies = np.flatnonzero(resolved)
        x, v, dx, dv, change, vmax, tol_x = (a[bodies] for a in (x, v, dx, dv, change, vmax, tol_x))
    tol_x = tol_x[:, None]
    d = dx - dt * 0.5 * (v[:, 1:] + v[:, :-1])
    s = dv / dt                               # mean acceleration of each interval
    jump = np.abs(np.diff(s, axis=1))
    # the variation of a on each interval, from its neighbours' mean accelerations (the first
    # and last intervals, with one neighbour, count its difference twice)
    tv = np.concatenate([2.0 * jump[:, :1], jump], axis=1) + np.concatenate([jump, 2.0 * jump[:, -1:]], axis=1)
    step = np.maximum(dt, h or 0.0)
    span = max(float(t[-1] - t[0]), 1e-300)
    if h and span < h * dt.size:
        # an output grid finer than the fixed step: its points interpolate within a step, and an
        # interval is allowed what the step that holds it is (the variations over the intervals
        # within a step of either side)
        w = int(math.ceil(h * dt.size / span))
        tv, change = _window_sum(tv, w), _window_sum(change, w)
    # |int v - trapezoid| <= dt^2/8 TV(a) on the interval (Peano kernel t (dt - t)/2 <= dt^2/8);
    # a fixed step h straddling a corner of a errs like a trapezoid of width h
    q = step * step / 8.0 * tv
    if kinks is not None and kinks.size:
        # intervals with an event strictly inside: a corner of a between the samples
        k = np.searchsorted(t, kinks, side="right") - 1
        inside = (k >= 0) & (k < dt.size)
        k, tk = k[inside], kinks[inside]
        q[:, k[(tk > t[k]) & (tk < t[k + 1])]] = np.inf
    if h and (method["order"] == 1 or method["implicit"]):
        # x1 = x0 + h v1 (backward Euler; moreau's theta; galpha's steps across transitions):
        # a defect of h |dv| / 2 a step
        q = q + 0.5 * h * change
    if method["adaptive"]:                    # each step's error test lets x err by tol_x
        q = q + tol_x * nstep * dt / span
    # rounding: each step rounds x, of size up to max|x| + dt max|v|
    steps = np.maximum(nstep * dt / span, dt / h if h else 1.0) + 1.0
    q = q + ROUNDING / SAFETY * np.finfo(float).eps * steps \
        * (np.max(np.abs(x), axis=1, keepdims=True) + dt * vmax[:, None]) + TINY / SAFETY
    # an adaptive method's x at the two ends of an interval (or of the run) may each be off by
    # what its error test allows: once per interval, once for the whole run
    ends = 2.0 * tol_x if method["adaptive"] else 0.0
    local = np.abs(d) > SAFETY * (q + ends)
    big_d, big_q = np.cumsum(d, axis=1), np.cumsum(q, axis=1) + ends
    total = np.abs(big_d) > SAFETY * big_q
    if not (local.any() or total.any()):
        return None
    r = int(np.flatnonzero(local.any(axis=1) | total.any(axis=1))[0])
    body = r if bodies is None else int(bodies[r])
    x, d, q, big_d, big_q = x[r], d[r], q[r], big_d[r], big_q[r]
    ends = float(ends[r, 0]) if method["adaptive"] else 0.0
    if total[r].any():
        j = int(np.flatnonzero(total[r])[0])
        return body, (
            f"x changed by {x[j + 1] - x[0]:.6g} m from t = {t[0]:.6g} to {t[j + 1]:.6g} s while the "
            f"integral of v over that time is {x[j + 1] - x[0] - big_d[j]:.6g} m: a defect of "
            f"{big_d[j]:.3g} m, more than {SAFETY:g} x its allowance {big_q[j]:.3g} m (the output grid's "
            f"quadrature and the method's error; {abs(big_d[-1]):.3g} m at t = {t[-1]:.6g} s)")
    j = int(np.flatnonzero(local[r])[0])
    return body, (
        f"x changed by {x[j + 1] - x[j]:.6g} m from t = {t[j]:.6g} to {t[j + 1]:.6g} s while the "
        f"integral of v over that interval is {x[j + 1] - x[j] - d[j]:.6g} m: a defect of {d[j]:.3g} m, "
        f"more than {SAFETY:g} x its allowance {q[j] + ends:.3g} m")


def _window_sum(a: np.ndarray, w: int) -> np.ndarray:
    """a[..., i - w] + ... + a[..., i + w] for each i (the terms that exist), along the last
    axis: c[min(i + w + 1, n)] - c[max(i - w, 0)] of the partial sums c (c[0] = 0)."""
    n = a.shape[-1]
    c = np.zeros(a.shape[:-1] + (n + 1,))
    np.cumsum(a, axis=-1, out=c[..., 1:])
    m = max(n - w, 0)                         # the i whose window ends inside: i + w + 1 <= n
    hi = np.empty_like(a)
    hi[..., :m] = c[..., w + 1:]
    hi[..., m:] = c[..., -1:]
    lo = np.zeros_like(a)                     # c[0] for i < w
    lo[..., w:] = c[..., :m]
    return hi - lo


def _tolerances(method: Mapping[str, Any], controls: Mapping[str, Any], n_bodies: int,
                x: np.ndarray) -> np.ndarray:
    """atol + rtol max|x| of each body's position in an adaptive method's error test [m]
    (zeros for the fixed-step methods); controls' rtol and atol: one value, or one per state
    component (positions first)."""
    if not method["adaptive"]:
        return np.zeros(n_bodies)
    return _tolerance_of(controls, "atol", 0, n_bodies) + _tolerance_of(controls, "rtol", 0, n_bodies) \
        * np.max(np.abs(x), axis=1)


def _tolerance_of(controls: Mapping[str, Any], name: str, start: int, n: int) -> np.ndarray:
    """Components start .. start + n - 1 of the tolerance `name` (rtol or atol: one value for
    every component, or one per component) [-] or [state units]."""
    a = np.atleast_1d(np.asarray(controls.get(name, CONTROL_DEFAULTS[name]), dtype=np.float64))
    return a[start:start + n] if a.size >= start + n else np.full(n, a[0])


def _velocity_allowance(method: Mapping[str, Any], controls: Mapping[str, Any], rows: _Rows,
                        nstep: int) -> np.ndarray:
    """How far each body's velocity may be off without the run being wrong [m/s]: an adaptive
    method's error test summed over its steps (nstep (atol + rtol max|v|)), a fixed step's
    velocity change at the largest mean acceleration of the output grid (h max|dv/dt|)."""
    nb = rows.v.shape[0]
    if method["adaptive"]:
        return nstep * (_tolerance_of(controls, "atol", nb, nb)
                        + _tolerance_of(controls, "rtol", nb, nb) * rows.vmax)
    ok = rows.ok
    if not ok.any():
        return np.zeros(nb)
    s = rows.adv / rows.dt if ok.all() else rows.adv[:, ok] / rows.dt[ok]
    return float(controls.get("h", 0.0)) * np.max(s, axis=1)


def _energy_rise(plan: _Plan, t: np.ndarray, e: np.ndarray, vmax: np.ndarray, dv: np.ndarray) -> str | None:
    """Where the model (its `plan`) is conservative apart from friction and dampers (no force,
    drive or moving surface), its energy E [J] cannot rise: E(t) against its smallest earlier
    value, allowing SAFETY sum m |v|max dv + m dv^2 / 2 (vmax: each body's |v|max [m/s]; dv:
    `_velocity_allowance`). A sentence, or None."""
    if not plan.closed:
        return None
    allow = SAFETY * float(np.sum(plan.mass * (vmax * dv + 0.5 * dv * dv))) \
        + ROUNDING * np.finfo(float).eps * float(np.max(e))
    low = np.minimum.accumulate(e)
    rise = e - low
    j = int(np.argmax(rise))
    if not rise[j] > allow:
        return None
    i = int(np.flatnonzero(e[:j + 1] == low[j])[0])
    return (f"the mechanical energy rose from {e[i]:.6g} J at t = {t[i]:.6g} s to {e[j]:.6g} J at "
            f"t = {t[j]:.6g} s, more than the {allow:.3g} J its error allowance admits, although only "
            "friction and dampers act (they only take energy out)")


def _friction_terms(model: Any, t: np.ndarray, n_bodies: int
                    ) -> tuple[list[tuple[int, np.ndarray, np.ndarray]], np.ndarray] | None:
    """What `_friction_excess` reads of the model's signals on the grid t (its _Plan keeps
    it): each force's body, its trapezoid mean over each output interval and that mean's
    allowance (half its change) [N]; and each body's sum of mu_max N+ over its contacts (N+ at
    its largest in each interval, `_interval_max`) [N], shape (n_bodies, n_t - 1). None when a
    contact's law has no bound (`_mu_max`): the friction is not checked."""
    mus = [_mu_max(c.law, dict(c.params)) for c in model.contacts]
    if any(mu is None for mu in mus):
        return None
    forces = []
    for i, sig in model.forces:
        f = _value(sig, t)
        forces.append((i, 0.5 * (f[1:] + f[:-1]), 0.5 * np.abs(np.diff(f))))
    limit = np.zeros((n_bodies, t.size - 1))            # sum of mu_max N+ [N]
    for c, mu in zip(model.contacts, mus):
        cap = mu * np.maximum(_interval_max(c.normal_force, t), 0.0)   # N+ at its largest in the interval
        for body in (c.a, c.b):
            if body is not None:
                limit[body] += cap
    return forces, limit


def _friction_excess(model: Any, plan: _Plan, rows: _Rows, dv: np.ndarray, resolved: np.ndarray) -> str | None:
    """Each body's mean friction force over each output interval, m dv/dt minus the mean of its
    springs, dampers and forces (trapezoids), against the sum of mu_max N+ of its contacts
    (laws without internal states whose mu has a bound; others not checked): the first excess
    beyond SAFETY times the allowance (the trapezoids' error for a monotone quantity, half its
    change, and m dv over the interval), as a sentence, or None. `plan`: the model's on the
    grid of `rows` (the run's output); `resolved`: the bodies whose motion the grid resolves (`_resolved`), the others and
    the driven bodies (whose force includes their drive's) not checked."""
    t, x, v = rows.t, rows.x, rows.v
    if t.size < 2 or not plan.checked:
        return None
    resolved = resolved & ~plan.driven
    if not resolved.any():
        return None
    terms = plan.friction(model)
    if terms is None:
        return None
    forces, limit = terms
    dt, ok = rows.dt, rows.ok
    mass = plan.mass
    mean_f = np.zeros((mass.size, dt.size))             # mean non-friction force [N]
    slack = np.zeros((mass.size, dt.size))              # its trapezoid's allowance [N]
    springs, dampers = plan.springs, plan.dampers
    if springs.count:
        springs.add_means(-springs.coef[:, None] * (springs.stretch(x) - springs.rest[:, None]), mean_f, slack)
    if dampers.count:
        dampers.add_means(-dampers.coef[:, None] * dampers.stretch(v), mean_f, slack)
    for i, mean, half in forces:
        mean_f[i] += mean
        slack[i] += half
    with np.errstate(divide="ignore", invalid="ignore"):
        friction = mass[:, None] * rows.dv / dt - mean_f
        allow = SAFETY * (slack + mass[:, None] * dv[:, None] / dt) \
            + ROUNDING * np.finfo(float).eps * (np.abs(mean_f) + limit)
        excess = (np.abs(friction) - limit - allow) * ok * resolved[:, None]
    bad = excess > 0.0
    if not bad.any():
        return None
    j, i = (int(u) for u in np.argwhere(bad)[0])
    return (f"{model.label(j)}: its mean friction force from t = {t[i]:.6g} to {t[i + 1]:.6g} s is "
            f"{friction[j, i]:.6g} N (m dv/dt minus its other forces), beyond the {limit[j, i]:.6g} N its "
            f"contacts' laws can give (mu_max N) and the {allow[j, i]:.3g} N of error allowance")


def check_result(result: Any, method: str, controls: Mapping[str, Any], model: Any = None,
                 arrays: Mapping[str, Any] | None = None, stacklevel: int = 2,
                 memo: list[Any] | None = None) -> list[str]:
    """The consistency check of a run that reached t_end (docs/guide/results.md): x against
    the integral of v for every body, and for a `model` the energy bound (`energy_bound`), the
    energy of a model conservative apart from friction against its friction's work (it cannot
    rise) and each body's friction within its laws' bound. Each failure is a sentence naming
    the run, warned (ConsistencyWarning, EnergyBoundWarning for the bound) and appended to
    ``result.stats["notes"]``; the list of them is returned (empty: the run passed).

    Parameters
    ----------
    result : Result
        The run's result (t from 0).
    method : str
        Its method (a name of `stickslip.METHODS`).
    controls : mapping
        Its controls as passed to the library (h; rtol and atol as arrays or numbers).
    model : Model, optional
        The model run (None: a built-in scene; the kinematic part only).
    arrays : mapping, optional
        ``model.arrays()`` where the caller has it.
    stacklevel : int
        The warnings' stacklevel, counted from this function's caller.
    memo : list, optional
        A list kept with the model's content (simulate's cache keeps one with each run of a
        model): what the check reads of the model and its output grid, not of the motion, is
        computed once and kept there (`_plan`). An empty list to start.
    """
    info = REGISTRY["method"][method]
    t = np.asarray(result.t, dtype=np.float64)
    # each body's row contiguous (a Result's rows are strided views of the state's columns)
    x, v = np.ascontiguousarray(np.atleast_2d(result.x)), np.ascontiguousarray(np.atleast_2d(result.v))
    if t.size < 2:
        return []
    nstep = int(result.stats.get("nstep", 0))
    h = float(controls["h"]) if "h" in controls and not info["adaptive"] else None
    where = f"{'model' if model is not None else result.scene} ({result.law or 'no contact'}, {method})"
    found: list[tuple[str, type[Warning]]] = []
    tol_x = _tolerances(info, controls, x.shape[0], x)
    events = getattr(result, "events", None)
    kinks = np.asarray(events["t"], dtype=np.float64) if events is not None and len(events) else None
    rows = _Rows(t, x, v)
    distinct = rows.distinct()
    resolved = _resolved(distinct)
    said = _kinematic(distinct, info, h, tol_x, nstep, kinks, resolved)
    if said is not None:
        j, sentence = said
        who = model.label(j) if model is not None else ("" if x.shape[0] == 1 else f"block {j}")
        found.append((f"{where}: {who + ': ' if who else ''}{sentence}", ConsistencyWarning))
    if model is not None:
        plan = _plan(model, t, arrays, memo)
        dv = _velocity_allowance(info, controls, rows, nstep)
        checked = _energy_and_bound(model, plan, x, v) if _bounded(model, t) else None
        if checked is not None:
            e, bound = checked
            over = np.flatnonzero(~(e <= bound))
            if over.size:
                i = int(over[0])
                found.append((f"{where}: the mechanical energy {e[i]:.6g} J at t = {t[i]:.6g} s exceeds "
                              f"{bound[i]:.6g} J, the most its forces and moving surfaces can have put in "
                              "(stickslip.energy): the result is wrong; take a smaller step or tolerance",
                              EnergyBoundWarning))
            else:
                rise = _energy_rise(plan, t, e, rows.vmax, dv)
                if rise is not None:
                    found.append((f"{where}: {rise}", ConsistencyWarning))
        excess = _friction_excess(model, plan, rows, dv, resolved)
        if excess is not None:
            found.append((f"{where}: {excess}", ConsistencyWarning))
    notes = result.stats.setdefault("notes", [])
    for message, category in found:
        warnings.warn(message, category, stacklevel=stacklevel + 1)
        notes.append(message)
    return [m for m, _ in found]


core._CHECK_RESULT = check_result            # simulate's scene runs are checked by it too
