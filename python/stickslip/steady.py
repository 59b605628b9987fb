"""Steady states directly: periodic orbits with their Floquet multipliers, equilibria with their
eigenvalues, continuation of either in a parameter (folds, branch points, period doubling,
Neimark-Sacker and Hopf points located), and forced-response curves, on a `Model` with any
method.

A periodic orbit is found by single shooting: Newton's method on the state at a section,
each residual one run of `stickslip.simulate` over a period. When the model is autonomous
(no time signal, ``period=None``) the period is an unknown too and a phase condition fixes the
section (the start state is orthogonal to the flow at the reference state, as AUTO and COCO
do); when it is forced the period is the forcing period and the section is t = 0. The
Jacobian of the shooting residual is taken by forward differences of the flow.

The monodromy matrix (the flow's derivative over one period at the start state) gives the
Floquet multipliers. Two routes, named in `Orbit.monodromy_method`:

* ``"saltation"`` (``event_driven`` on a model whose contacts all use ``coulomb`` or
  ``stribeck``): between events the variational equation of the mode; with Coulomb every mode
  is affine in the state, its matrix constant, and a matrix exponential solves it exactly;
  with Stribeck it is integrated with the state by scipy's DOP853 (rtol 1e-11, the mode's
  Jacobian by central differences of step 1e-6). At every stick, slip and reversal event the
  saltation matrix S = I + (f+ - f-) n^T / (dh/dt) (Leine & Nijmeijer, "Dynamics and
  bifurcations of non-smooth mechanical systems", 2004, ch. 7) maps the variations across
  it. A stick phase collapses directions: its multipliers are 0 to rounding.
* ``"finite differences"`` (every other case): central differences of the chosen method's
  flow over the period at the orbit's tolerances, step 1e-4 of each component's scale (an
  adaptive method's flow jitters with its step-size choices at smaller steps: on a forced
  oscillator with the `proposed` law, steps of 1e-5 and 1e-6 moved the multipliers by 3e-4
  where 1e-4 was within 1e-5 of scipy's variational equations), so multipliers are good to
  about 1e-5, and a stick phase's zero multipliers appear as numbers of that size. On this
  route single shooting (Newton's iteration, the differences and the eigenvalues) runs in the
  library's Fortran solver, stickslip_orbit, the one Fortran and C programs call.

Laws with internal states (LuGre, Dahl, elasto-plastic, GMS, ...) are handled: their states
are unknowns of the shooting with the positions and velocities (each run started from them),
their rows of the residual weighted by the positions' scale over theirs (a bristle deflection
of 1e-5 m counts relative to itself), and the monodromy is taken by finite differences over the
whole state. `equilibrium` and harmonic balance refuse them (`LawStatesUnsupported`).

Examples
--------
>>> import stickslip as ss
>>> belt = ss.Model.from_scene("belt", "coulomb", mu_s=0.4, mu_k=0.3, v_b=0.5, v0=0.5)
>>> orb = ss.periodic_orbit(belt)          # started stuck: the stick-slip cycle
>>> round(orb.period, 6), orb.monodromy_method, orb.stable
(1.152347, 'saltation', True)
"""
from __future__ import annotations

import copy
import dataclasses
import math
import sys
import warnings
from dataclasses import dataclass, field
from typing import Any, Callable, Sequence

import numpy as np

from .core import REGISTRY, STATUS_OK, Result, _count, _finite, _known, friction_coefficient, simulate, \
    status_message
from .model import Model, check_method, orbit_model
from .signal import Signal

__all__ = ["Orbit", "Branch", "Equilibrium", "SteadyStateError", "NoConvergence", "NonPeriodicForcing",
           "GuessShapeError", "LawStatesUnsupported", "retuned", "MonodromyWarning",
           "periodic_orbit", "equilibrium", "continuation", "frequency_response"]

#: Tolerances of the runs when the method is adaptive and none are given.
DEFAULT_RTOL = 1e-12
DEFAULT_ATOL = 1e-14
#: Forward-difference step of the shooting Jacobian and central-difference step of the
#: finite-difference monodromy, relative to each component's scale.
_FD_NEWTON = 1e-5
_FD_MONODROMY = 1e-4
#: The orbit solver's own failures (stickslip_orbit).
_NO_ORBIT = REGISTRY["status"]["NO_ORBIT"]
_ORBIT_COLLAPSED = REGISTRY["status"]["ORBIT_COLLAPSED"]


# ------------------------------------------------------------------------------------------
# Failures
# ------------------------------------------------------------------------------------------
class SteadyStateError(RuntimeError):
    """A periodic orbit or branch that could not be found (base class of this module's
    failures)."""


class NoConvergence(SteadyStateError):
    """Newton's method did not reach the tolerance: `residual` is the last residual's
    infinity norm [state units], `iterations` the iterations made."""

    def __init__(self, message: str, residual: float = math.nan, iterations: int = 0) -> None:
        super().__init__(message)
        self.residual, self.iterations = residual, iterations


class NonPeriodicForcing(SteadyStateError, ValueError):
    """The model's time signals are not periodic with the given period (a step, a ramp or a
    table that changes after t = 0, or a sine whose frequency is not a multiple of 1/period)."""


class GuessShapeError(SteadyStateError, ValueError):
    """A guess of the wrong shape or kind."""


class LawStatesUnsupported(SteadyStateError, ValueError):
    """A contact whose law has internal states (LuGre, Dahl, elasto-plastic, GMS, ...) given to
    a solver that does not handle them (`equilibrium`, harmonic balance); refused before any
    run. `periodic_orbit` and `continuation` of orbits handle them."""


class MonodromyWarning(UserWarning):
    """An autonomous orbit's monodromy has no multiplier within 1e-3 of 1 (the flow direction's
    multiplier): its multipliers and `stable` are not to be trusted (e.g. a fixed-step method
    whose stick-slip transitions fall inside steps makes the flow map jump)."""


# ------------------------------------------------------------------------------------------
# Time signals in Python: value, derivative and frequencies
# ------------------------------------------------------------------------------------------
def _signal(s: Signal, t: Any) -> tuple[np.ndarray, np.ndarray]:
    """Value and time derivative of signal `s` at times `t` (the definitions of
    stickslip.signal; a step's derivative is 0, a table's the slope of its segment)."""
    t = np.asarray(t, dtype=np.float64)
    k, a = s.kind, s.args
    if k == "constant":
        return np.full(t.shape, a[0]), np.zeros(t.shape)
    if k == "step":
        return np.where(t < a[0], a[1], a[2]), np.zeros(t.shape)
    if k == "ramp":
        start, dur, height = a
        u = np.clip((t - start) / dur, 0.0, 1.0)
        return height * u, np.where((t > start) & (t < start + dur), height / dur, 0.0)
    if k == "sine":
        amp, f, ph, off = a
        w = 2.0 * math.pi * f
        return amp * np.sin(w * t + ph) + off, amp * w * np.cos(w * t + ph)
    if k == "table":
        tt, vv = (np.asarray(x) for x in a)
        slope = np.zeros(t.shape)
        if tt.size > 1:
            i = np.clip(np.searchsorted(tt, t, side="right") - 1, 0, tt.size - 2)
            inside = (t >= tt[0]) & (t < tt[-1])
            slope = np.where(inside, (vv[i + 1] - vv[i]) / (tt[i + 1] - tt[i]), 0.0)
        return np.interp(t, tt, vv), slope
    (u, du), (v, dv) = (_signal(c, t) for c in s.children)
    if k == "add":
        return u + v, du + dv
    if k == "sub":
        return u - v, du - dv
    return u * v, du * v + u * dv


def _frequencies(s: Signal, where: str) -> set[float]:
    """The sine frequencies [Hz] of `s` (products give sums and differences, which a common
    period of the factors keeps periodic); NonPeriodicForcing for a part that changes after
    t = 0 and does not repeat (a step, ramp or table)."""
    k, a = s.kind, s.args
    if k == "constant":
        return set()
    if k == "sine":
        return {abs(a[1])} if a[0] != 0.0 and a[1] != 0.0 else set()
    if k == "step" and a[0] <= 0.0 or k == "ramp" and a[0] + a[1] <= 0.0 \
            or k == "table" and (a[0][-1] <= 0.0 or len(set(a[1])) == 1):
        return set()
    if k in ("step", "ramp", "table"):
        raise NonPeriodicForcing(f"{where}: a {k} that changes after t = 0 is not periodic; an orbit needs "
                                 "forcing made of constants and sines")
    return _frequencies(s.children[0], where) | _frequencies(s.children[1], where)


def _model_signals(model: Model) -> list[tuple[str, Signal]]:
    out = [(f"force {i}", s) for i, (_, s) in enumerate(model.forces)]
    for i, c in enumerate(model.contacts):
        out.append((f"{model.contact_label(i)}: normal_force", c.normal_force))
        if c.surface_velocity is not None:
            out.append((f"{model.contact_label(i)}: surface_velocity", c.surface_velocity))
    return out


def forcing_period(model: Model, period: float | None = None) -> float | None:
    """The period [s] of `model`'s forcing: None when autonomous (every signal constant),
    `period` when given and every sine frequency is a multiple of 1/period, else
    1/(lowest frequency) when every frequency is a multiple of it. NonPeriodicForcing
    otherwise, naming the signal and the frequency."""
    freqs: list[tuple[str, float]] = []
    for where, s in _model_signals(model):
        freqs.extend((where, f) for f in sorted(_frequencies(s, where)))
    if not freqs:
        return period
    if period is None:
        base = min(f for _, f in freqs)
        for where, f in freqs:
            if abs(f / base - round(f / base)) > 1e-9:
                raise NonPeriodicForcing(f"{where}: frequency {f!r} Hz is not a multiple of the lowest, {base!r} Hz; "
                                         "give period= (a common period of every sine)")
        return 1.0 / base
    for where, f in freqs:
        if abs(f * period - round(f * period)) > 1e-9 * max(1.0, f * period):
            raise NonPeriodicForcing(f"{where}: frequency {f!r} Hz does not repeat with period {period!r} s "
                                     f"(f * period = {f * period!r}, not an integer)")
    return period


# ------------------------------------------------------------------------------------------
# The model's forces in Python (modes of set-valued contacts; saltation matrices)
# ------------------------------------------------------------------------------------------
class _System:
    """A Model's equations of motion, M a = F(x, v, t) + friction, with each contact's mode
    given: +1 / -1 slipping with that sign of s = v_a - v_b - w(t), 0 stuck (a set-valued
    law; its force then holds s' = 0)."""

    def __init__(self, model: Model) -> None:
        n = model.n_bodies
        self.n = n
        self.mass = np.array([b.mass for b in model.bodies])
        self.K = np.zeros((n, n))
        self.C = np.zeros((n, n))
        self.f0 = np.zeros(n)
        for a, b, k, l0 in model.springs:
            self._pair(self.K, a, b, k)
            self.f0[a] += k * l0
            if b is not None:
                self.f0[b] -= k * l0
        for a, b, c in model.dampers:
            self._pair(self.C, a, b, c)
        self.forces = model.forces
        self.contacts = model.contacts
        self.G = np.zeros((len(model.contacts), n))
        #: every mode affine in the state (Coulomb: mu_k in slip): exact unit-difference Jacobians
        self.affine = all(c.law == "coulomb" for c in model.contacts)
        self.params = []
        for i, c in enumerate(model.contacts):
            if c.a is not None:                 # side a the ground: a scene's belt (Model.from_scene)
                self.G[i, c.a] = 1.0
            if c.b is not None:
                self.G[i, c.b] = -1.0
            self.params.append(_known(c.params))

    @staticmethod
    def _pair(mat: np.ndarray, a: int, b: int | None, k: float) -> None:
        mat[a, a] += k
        if b is not None:
            mat[b, b] += k
            mat[a, b] -= k
            mat[b, a] -= k

    def surface(self, i: int, t: float) -> tuple[float, float]:
        w = self.contacts[i].surface_velocity
        if w is None:
            return 0.0, 0.0
        val, der = _signal(w, t)
        return float(val), float(der)

    def slip(self, y: np.ndarray, t: Any) -> np.ndarray:
        """Each contact's slip velocity s [m/s] at state y (shape (2n,) or (2n, n_t)), time(s) t."""
        w = [np.zeros(np.shape(t)) if c.surface_velocity is None else _signal(c.surface_velocity, t)[0]
             for c in self.contacts]
        return self.G @ y[self.n:] - np.array(w).reshape((len(self.contacts),) + np.shape(t))

    def _free(self, y: np.ndarray, t: Any, modes: Sequence[int] | None,
              given: dict[int, np.ndarray] | None = None) -> np.ndarray:
        """Every force but the holding forces of stuck contacts [N], at state y (shape (2n,)
        or (2n, n_t)) and time(s) t; `modes` None: every contact's law regularised (its
        friction at the signed slip); else every law set-valued, Coulomb (mu_k N in slip) or
        Stribeck (its curve, the tanh ramp at rest narrowed to 1e-100 m/s, as event_driven's
        slip modes have it). `given`: the friction coefficients of some contacts at t (laws
        with states, evaluated along the motion by the caller)."""
        x, v = y[:self.n], y[self.n:]
        col = (slice(None),) + (None,) * (y.ndim - 1)
        f = -self.K @ x - self.C @ v + self.f0[col]
        for body, s in self.forces:
            f[body] = f[body] + _signal(s, t)[0]
        s = self.slip(y, t)
        for i, c in enumerate(self.contacts):
            normal = np.maximum(_signal(c.normal_force, t)[0], 0.0)
            if given is not None and i in given:
                mu = given[i]
            elif modes is None:
                mu = friction_coefficient(c.law, s[i], **c.params)
            elif modes[i] == 0:
                continue
            elif c.law == "coulomb":     # set-valued Coulomb in slip: mu_k
                mu = modes[i] * self.params[i]["mu_k"]
            else:                        # set-valued Stribeck in slip: its curve without the tanh ramp
                mu = friction_coefficient(c.law, modes[i] * np.maximum(np.abs(s[i]), 1e-80),
                                          **{**c.params, "v_eps": 1e-100})
            f = f - self.G[i][col] * (mu * normal)
        return f

    def rates(self, y: np.ndarray, t: float, modes: Sequence[int]) -> tuple[np.ndarray, np.ndarray]:
        """dy/dt in the given modes, and the stuck contacts' holding forces [N] (on a; NaN
        for the others)."""
        f = self._free(y, t, modes)
        stuck = [i for i, m in enumerate(modes) if m == 0]
        lam = np.full(len(self.contacts), np.nan)
        if stuck:
            g = self.G[stuck]
            minv = g / self.mass
            rhs = np.array([self.surface(i, t)[1] for i in stuck]) - minv @ f
            lam[stuck] = np.linalg.solve(minv @ g.T, rhs)
            f = f + g.T @ lam[stuck]
        return np.concatenate([y[self.n:], f / self.mass]), lam

    def jacobian(self, y: np.ndarray, t: float, modes: Sequence[int]) -> tuple[np.ndarray, np.ndarray]:
        """d(dy/dt)/dy and d(holding force)/dy in a mode: by unit differences when every mode
        is affine in the state (Coulomb friction; exact), else by central differences of step
        1e-6 max(1, |y_j|)."""
        jf = np.empty((y.size, y.size))
        jl = np.empty((len(self.contacts), y.size))
        base = self.rates(y, t, modes) if self.affine else None
        for j in range(y.size):
            h = 1.0 if self.affine else 1e-6 * max(1.0, abs(float(y[j])))
            e = y.copy()
            e[j] += h
            fp, lp = self.rates(e, t, modes)
            if base is None:
                e[j] -= 2 * h
                fm, lm = self.rates(e, t, modes)
            else:
                fm, lm = base
                h = 0.5
            jf[:, j], jl[:, j] = (fp - fm) / (2 * h), (lp - lm) / (2 * h)
        return jf, jl

    def propagator(self, y: np.ndarray, t0: float, t1: float, modes: Sequence[int]) -> np.ndarray:
        """The variational equation's solution over [t0, t1] in one mode from state y at t0:
        exp(J (t1 - t0)) for affine modes (J constant), else the state and its variations
        integrated together by scipy's DOP853 (rtol 1e-11, atol 1e-13)."""
        if self.affine:
            return _expm(self.jacobian(y, t0, modes)[0] * (t1 - t0))
        if t1 <= t0:
            return np.eye(y.size)
        from scipy.integrate import solve_ivp
        n2 = y.size

        def rhs(t: float, z: np.ndarray) -> np.ndarray:
            yy = z[:n2]
            return np.concatenate([self.rates(yy, t, modes)[0],
                                   (self.jacobian(yy, t, modes)[0] @ z[n2:].reshape(n2, n2)).ravel()])
        sol = solve_ivp(rhs, (t0, t1), np.concatenate([y, np.eye(n2).ravel()]), method="DOP853",
                        rtol=1e-11, atol=1e-13)
        if not sol.success:
            raise SteadyStateError(f"the variational equation between t = {t0!r} and {t1!r} s failed: {sol.message}")
        return sol.y[n2:, -1].reshape(n2, n2)


# ------------------------------------------------------------------------------------------
# Runs
# ------------------------------------------------------------------------------------------
def _with_state(model: Model, y: np.ndarray) -> Model:
    """A shallow copy of `model` starting from state y = (x, v, z), z the laws' internal states
    contact by contact (as `Model.state_labels`)."""
    m = copy.copy(model)
    n = model.n_bodies
    m.bodies = [dataclasses.replace(b, x0=float(y[i]), v0=float(y[n + i])) for i, b in enumerate(model.bodies)]
    if y.size > 2 * n:
        first, contacts = 2 * n, []
        for i, c in enumerate(model.contacts):
            nz = model._law_states(i)[0]
            contacts.append(dataclasses.replace(c, z0=tuple(float(q) for q in y[first:first + nz])) if nz else c)
            first += nz
        m.contacts = contacts
    return m


@dataclass
class _Runner:
    model: Model
    method: str
    controls: dict[str, Any]
    runs: int = 0

    shifts: dict[float, Model] = field(default_factory=dict)

    def run(self, y0: np.ndarray, t_end: float, n_out: int = 2, t_start: float = 0.0) -> Result:
        """A run of `t_end` seconds from state y0 at time `t_start` (the result's times from 0)."""
        self.runs += 1
        model = self.model
        if t_start != 0.0:
            if t_start not in self.shifts:
                self.shifts[t_start] = _shifted(self.model, t_start)
            model = self.shifts[t_start]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return simulate(_with_state(model, y0), method=self.method, t_end=t_end, n_out=n_out, **self.controls)

    def flow(self, y0: np.ndarray, t_end: float, t_start: float = 0.0) -> np.ndarray:
        r = self.run(y0, t_end, t_start=t_start)
        return _state(r, -1)


def _state(r: Result, i: int) -> np.ndarray:
    """The state (x, v, z) of run r at its output point i."""
    return r.y[:, i].copy()


def _controls(model: Model, method: str, controls: dict[str, Any]) -> dict[str, Any]:
    check_method(model, method)
    info = REGISTRY["method"][method]
    out = dict(controls)
    if "rtol" in info["controls"]:
        out.setdefault("rtol", DEFAULT_RTOL)
        out.setdefault("atol", DEFAULT_ATOL)
    return out


def _check_model(model: Any, allow_states: bool = False) -> Model:
    """`model` if it is a Model (and, unless `allow_states`, no law of it has internal states)."""
    if not isinstance(model, Model):
        raise ValueError(f"model: must be a stickslip.Model (a scene: Model.from_scene), got {type(model).__name__}")
    if model.drives:
        raise ValueError(f"model: has {len(model.drives)} drive(s); periodic orbits of models with drives are not "
                         "supported (a driven body's motion is prescribed, not part of the orbit's state)")
    for i, c in enumerate(model.contacts):
        if model._law_states(i)[0] and not allow_states:
            raise LawStatesUnsupported(f"{model.contact_label(i)}: law {c.law!r} has internal states, which "
                                       "equilibria do not handle (periodic_orbit, continuation of orbits and "
                                       "harmonic_balance do)")
    return model


# ------------------------------------------------------------------------------------------
# Orbit
# ------------------------------------------------------------------------------------------
@dataclass
class Orbit:
    """A periodic orbit (returned by `periodic_orbit`).

    Attributes
    ----------
    period : float
        The period [s].
    x0, v0 : numpy.ndarray, shape (n_bodies,)
        The state at the section (t = 0 of `result`) [m], [m/s].
    z0 : numpy.ndarray, shape (n_states - 2 n_bodies,)
        The laws' internal states at the section, contact by contact as `Model.state_labels`
        (empty when no law has states); unknowns of the shooting like x0 and v0.
    multipliers : numpy.ndarray, shape (n_states,)
        Floquet multipliers (eigenvalues of `monodromy`), largest modulus first; for an
        autonomous orbit one of them is the trivial 1 (`trivial`).
    trivial : int or None
        Index in `multipliers` of the trivial multiplier (autonomous), else None.
    trivial_error : float
        abs(trivial multiplier - 1), a check of the monodromy's accuracy (NaN when forced); above
        1e-3 a `MonodromyWarning` was issued.
    stable : bool
        Every nontrivial multiplier inside the unit circle.
    amplitude : numpy.ndarray, shape (n_bodies,)
        Half the peak-to-peak displacement of each body over a period [m].
    stick_fraction : numpy.ndarray, shape (n_contacts,)
        Fraction of the period each contact is stuck (exactly zero relative velocity; always 0
        for a regularised law).
    events : numpy.ndarray of EVENT_DTYPE
        event_driven's events over one period (empty for the other methods).
    result : Result
        A run over one period from the section, on a grid.
    monodromy : numpy.ndarray, shape (n_states, n_states)
        d(state after one period) / d(state at the section).
    monodromy_method : str
        "saltation" or "finite differences" (see the module).
    residual : float
        Infinity norm of the shooting residual at the answer [state units; the phase
        condition's row in m or m/s; the laws' states' rows weighted by the positions' scale
        over theirs].
    iterations : int
        Newton iterations made.
    autonomous : bool
        Whether the period was an unknown.
    method : str
        The integration method.
    runs : int
        Runs of the method made to find the orbit and its multipliers.
    """

    period: float
    x0: np.ndarray
    v0: np.ndarray
    z0: np.ndarray
    multipliers: np.ndarray
    trivial: int | None
    trivial_error: float
    stable: bool
    amplitude: np.ndarray
    stick_fraction: np.ndarray
    events: np.ndarray
    result: Result
    monodromy: np.ndarray
    monodromy_method: str
    residual: float
    iterations: int
    autonomous: bool
    method: str
    runs: int = 0

    @property
    def y0(self) -> np.ndarray:
        """The state (x0, v0, z0) at the section."""
        return np.concatenate([self.x0, self.v0, self.z0])

    @property
    def nontrivial(self) -> np.ndarray:
        """The multipliers without the trivial one."""
        keep = np.ones(self.multipliers.size, bool)
        if self.trivial is not None:
            keep[self.trivial] = False
        return self.multipliers[keep]


def _as_guess(guess: Any, n: int, autonomous: bool, nz: int = 0) -> tuple[np.ndarray | None, float | None]:
    """(state, period) from a guess: an Orbit, a state (x then v, 2 n_bodies values, then the
    `nz` law states when the model has any; without them they start at 0), or for an autonomous
    model the same and the period last."""
    if guess is None:
        return None, None
    if isinstance(guess, Orbit):
        return guess.y0.copy(), guess.period
    try:
        g = np.asarray(guess, dtype=np.float64)
    except (TypeError, ValueError):
        raise GuessShapeError(f"guess: must be an Orbit or real numbers, got {type(guess).__name__}") from None
    states = sorted({2 * n, 2 * n + nz})
    sizes = states + [k + 1 for k in states] if autonomous else states
    if g.ndim != 1 or g.size not in sizes or not np.isfinite(g).all():
        want = " or ".join(str(s) for s in sizes)
        raise GuessShapeError(f"guess: must be {want} finite values (x then v of the {n} bodies"
                              f"{f', optionally the {nz} law states' if nz else ''}"
                              f"{', then the period' if autonomous else ''}), got shape {g.shape}")
    period = None
    # autonomous: the last value is the period wherever it can be (x, v, T and x, v, z of one
    # law state have the same size; a state without its period is of no use there)
    if g.size not in states or autonomous and g.size - 1 in states:
        if not g[-1] > 0.0:
            raise GuessShapeError(f"guess: the period (last value) must be > 0 [s], got {g[-1]!r}")
        g, period = g[:-1], float(g[-1])
    return np.concatenate([g, np.zeros(2 * n + nz - g.size)]), period


def _natural_period(model: Model) -> float:
    """The longest undamped period 2 pi / w of the springs and masses [s] (1 s without springs)."""
    sys_ = _System(model)
    k = sys_.K / np.sqrt(np.outer(sys_.mass, sys_.mass))
    w2 = np.linalg.eigvalsh(k)
    w2 = w2[w2 > 1e-12 * max(1.0, float(np.max(np.abs(w2))))]
    return 2.0 * math.pi / math.sqrt(float(w2.min())) if w2.size else 1.0


def _transient_guess(runner: _Runner, period: float | None, periods: int) -> tuple[np.ndarray, float]:
    """A start state (and period) from a run of `periods` periods (forced) or natural periods
    (autonomous) from the model's initial state; for an autonomous model the section is where
    the most moving body's velocity is least over the last period (a slip phase on a belt)."""
    model = runner.model
    n = model.n_bodies
    y0 = np.concatenate([[b.x0 for b in model.bodies], [b.v0 for b in model.bodies], np.zeros(_n_law_states(model))])
    if period is not None:
        return runner.flow(y0, periods * period), period
    tn = _natural_period(model)
    t_end = periods * tn
    r = runner.run(y0, t_end, n_out=periods * 400 + 1)
    half = r.t >= 0.5 * t_end
    body = int(np.argmax(np.ptp(r.x[:, half], axis=1)))
    x = r.x[body, half] - np.mean(r.x[body, half])
    t = r.t[half]
    up = np.flatnonzero((x[:-1] < 0.0) & (x[1:] >= 0.0))
    if up.size < 3:
        raise NoConvergence(f"no periodic motion found in a run of {t_end:.6g} s from the model's initial state "
                            "(no oscillation in its second half): give a guess")
    tc = t[up] - x[up] * (t[up + 1] - t[up]) / (x[up + 1] - x[up])
    est = float(np.median(np.diff(tc[-5:])))
    last = (r.t >= t_end - est)
    i = np.flatnonzero(last)[int(np.argmin(r.v[body, last]))]
    return _state(r, i), est


def _newton(residual: Callable[[np.ndarray], np.ndarray], u: np.ndarray, scale: np.ndarray, tol: float,
            max_iter: int, what: str) -> tuple[np.ndarray, float, int, np.ndarray]:
    """Newton's method with a forward-difference Jacobian and step halving; (u, |R|, iterations, J).
    Converged when the residual's infinity norm is at most tol max(1, |u|_inf)."""
    r = residual(u)
    norm = float(np.max(np.abs(r)))
    jac = np.zeros((r.size, u.size))
    tol = tol * max(1.0, float(np.max(np.abs(u))))
    for it in range(max_iter + 1):
        if norm <= tol:
            return u, norm, it, jac
        if it == max_iter:
            break
        for j in range(u.size):
            h = _FD_NEWTON * scale[j]
            e = u.copy()
            e[j] += h
            jac[:, j] = (residual(e) - r) / h
        try:
            du = np.linalg.lstsq(jac, -r, rcond=None)[0]
        except np.linalg.LinAlgError:
            break
        lam = 1.0
        for _ in range(12):
            try:
                rn = residual(u + lam * du)
                nn = float(np.max(np.abs(rn)))
            except Exception:           # a trial that fails to run: a shorter step
                nn = math.inf
            if nn < norm or nn <= tol:
                break
            lam *= 0.5
        else:
            break
        u, r, norm = u + lam * du, rn, nn
    raise NoConvergence(f"{what}: Newton's method did not converge (residual {norm:.3g} after {it} iterations, "
                        f"tolerance {tol:.3g}); give a better guess or looser tolerances", norm, it)


def periodic_orbit(model: Model, period: float | None = None, guess: Any = None, method: str = "event_driven",
                   *, segments: int = 1, tol: float = 1e-9, max_iter: int = 30, transient: int = 30,
                   n_out: int = 4001, **controls: Any) -> Orbit:
    """A periodic orbit of `model` by single or multiple shooting, with its Floquet multipliers.

    Parameters
    ----------
    model : Model
        The system (a built-in scene: ``Model.from_scene``); its laws must have no internal
        states.
    period : float, optional
        The forcing period [s]; by default the period of the model's sines (1 / the lowest
        frequency) or, when nothing is forced, an unknown (autonomous orbit).
    guess : Orbit or array_like, optional
        A start: an Orbit (e.g. of a nearby parameter), the state (x then v of every body), or
        for an autonomous model the state and then the period. By default the end of a run of
        `transient` periods (natural periods 2 pi sqrt(m/k) when autonomous) from the model's
        initial state.
    method : str, optional
        The integration method (default "event_driven"); its controls as keywords (rtol and
        atol default to 1e-12 and 1e-14 for the adaptive methods; `h` is required for the
        fixed-step ones).
    segments : int, optional
        1 (default): single shooting; more: multiple shooting over that many equal segments of
        the period (for long or unstable orbits: each run is shorter, so the residual grows
        less), the unknowns the states at their starts.
    tol : float, optional
        Tolerance on the infinity norm of the shooting residual (state after a period minus
        state at the section, and the phase condition), relative to max(1, the largest
        unknown); default 1e-9 (the runs' own error at rtol = 1e-12 is about 1e-10).
    max_iter : int, optional
        Newton iterations at most (default 30).
    transient : int, optional
        Periods of the run that makes the default guess (default 30).
    n_out : int, optional
        Points of `Orbit.result`'s grid over the period (default 4001).

    Returns
    -------
    Orbit

    Raises
    ------
    NoConvergence
        Newton's method did not converge (its residual given).
    NonPeriodicForcing
        A step, ramp or table that changes after t = 0, or a sine that does not repeat with
        `period`.
    GuessShapeError
        A guess of the wrong shape.
    ValueError
        A bad model, method or control (as `simulate`).
    """
    model = _check_model(model, allow_states=True)
    if period is not None and not _finite("period", period, "> 0 [s]") > 0.0:
        raise ValueError(f"period: must be > 0 [s], got {period!r}")
    _check_options(tol, max_iter, transient, n_out)
    forced = forcing_period(model, None if period is None else float(period))
    runner = _Runner(model, method, _controls(model, method, controls))
    n = model.n_bodies
    autonomous = forced is None
    y_guess, t_guess = _as_guess(guess, n, autonomous, _n_law_states(model))
    if y_guess is None:
        y_guess, t_est = _transient_guess(runner, forced, transient)
        t_guess = t_est if t_guess is None else t_guess
    if autonomous and t_guess is None:
        raise GuessShapeError("guess: an autonomous model needs the period too (2 n_bodies + 1 values, or an Orbit)")
    return _solve(runner, y_guess, forced if not autonomous else t_guess, autonomous, tol, max_iter, n_out,
                  segments=_count("segments", segments))


def _check_options(tol: Any, max_iter: Any, transient: Any, n_out: Any) -> None:
    """ValueError naming the first of the solver's options out of its range."""
    if not _finite("tol", tol, "> 0") > 0.0:
        raise ValueError(f"tol: must be > 0, got {tol!r}")
    _count("max_iter", max_iter)
    _count("transient", transient)
    _count("n_out", n_out, 2)


def _solve(runner: _Runner, y_guess: np.ndarray, t_guess: float, autonomous: bool, tol: float, max_iter: int,
           n_out: int, ref: tuple[np.ndarray, np.ndarray] | None = None, segments: int = 1) -> Orbit:
    """Shooting from (y_guess, t_guess) over `segments` segments of the period (multiple
    shooting when > 1: the unknowns are the states at k T / segments, each segment's end
    matched to the next one's start); `ref`: the phase condition's reference state and
    direction (default: the guess and the flow there)."""
    n2 = y_guess.size
    m = segments
    if m == 1 and ref is None and _fortran_route(runner):
        # single shooting with the finite-difference monodromy: the library's solver
        # (stickslip_orbit), the same Newton iteration and differences in Fortran (its section
        # is t = 0, as here on this route: _section_phase moves only event_driven's)
        fo = _fortran_orbit(runner, y_guess, t_guess, autonomous, tol, max_iter)
        return _finish(runner, fo["y0"], fo["period"], autonomous, fo["residual"], fo["iterations"], n_out, fo)
    if autonomous and ref is None:
        eps = 1e-6 * t_guess
        ref = (y_guess, (runner.flow(y_guess, eps) - y_guess) / eps)
    # a forced orbit is shot from a time in a slip phase (a section inside a stick phase makes
    # the flow map kink there), then reported from t = 0
    t_sec = 0.0 if autonomous else _section_phase(runner, y_guess, t_guess) * t_guess
    if t_sec:
        y_guess = runner.flow(y_guess, t_sec)
    nb = runner.model.n_bodies
    sc = _scales(y_guess, nb)
    if y_guess.size > 2 * nb:       # the laws' states scaled by their extent over a period from the guess
        zs = runner.run(y_guess, t_guess, n_out=201, t_start=t_sec).y[2 * nb:]
        sc[2 * nb:] = max(float(np.max(np.abs(zs))), 1e-12)
    wts = np.tile(_weights(sc, nb), m)

    def residual(u: np.ndarray) -> np.ndarray:
        period = float(u[-1]) if autonomous else t_guess
        if not period > 0.0:
            raise NoConvergence("the period went negative")
        ys = u[:m * n2].reshape(m, n2)
        h = period / m
        # an autonomous model's signals are constant: every segment starts at t = 0
        r = wts * np.concatenate([runner.flow(ys[k], h, 0.0 if autonomous else (t_sec + k * h) % period)
                                  - ys[(k + 1) % m] for k in range(m)])
        if autonomous:
            r = np.append(r, (ys[0] - ref[0]) @ ref[1] / max(float(np.max(np.abs(ref[1]))), 1e-300))
        return r

    starts = [y_guess]
    if m > 1:
        r0 = runner.run(y_guess, t_guess, n_out=m + 1, t_start=t_sec)
        starts = [_state(r0, k) for k in range(m)]
    u0 = np.concatenate(starts + ([np.array([t_guess])] if autonomous else []))
    typ = np.tile(sc, m)
    scale = np.append(typ, t_guess) if autonomous else typ
    u, norm, it, _ = _newton(residual, u0, scale, tol, max_iter, "periodic_orbit")
    y0, period = u[:n2], (float(u[-1]) if autonomous else t_guess)
    _check_period(period, t_guess)
    if t_sec:
        y0 = runner.flow(y0, period - t_sec, t_sec)
    return _finish(runner, y0, period, autonomous, norm, it, n_out)


def _check_period(period: float, guess: float) -> None:
    """NoConvergence for a period that collapsed (below 1e-3 of its guess): Newton found an
    equilibrium or a point of the flow, not an orbit."""
    if not period > 1e-3 * guess:
        raise NoConvergence(f"periodic_orbit: the period collapsed to {period:.3g} s from a guess of {guess:.6g} s "
                            "(an equilibrium, not an orbit); give a guess on the orbit")


def _section_phase(runner: _Runner, y0: np.ndarray, period: float) -> float:
    """Where to shoot a forced orbit from, as a fraction of the period: under event_driven the
    middle of the longest stretch between events (round the period) in which no contact is
    stuck; 0 for the other methods, or when there are no events."""
    if runner.method != "event_driven" or not runner.model.contacts:
        return 0.0
    t = np.unique(runner.run(y0, period).events["t"])
    t = t[(t > 0.0) & (t < period)]
    if t.size == 0:
        return 0.0
    ends = np.append(t[1:], t[0] + period)
    sys_ = _System(runner.model)
    for i in np.argsort(-(ends - t), kind="stable"):
        mid = 0.5 * (t[i] + ends[i]) % period
        if np.all(sys_.slip(runner.flow(y0, mid), mid) != 0.0):
            return mid / period
    return 0.0


def _scales(y: np.ndarray, n: int) -> np.ndarray:
    """A scale per component: the largest |x| (positions) or |v| (velocities), at least 1e-3,
    and for the laws' states (after them) the largest |z|, at least 1e-12."""
    sx = max(float(np.max(np.abs(y[:n]))), 1e-3)
    sv = max(float(np.max(np.abs(y[n:2 * n]))), 1e-3)
    sz = max(float(np.max(np.abs(y[2 * n:]))), 1e-12) if y.size > 2 * n else 1.0
    return np.concatenate([np.full(n, sx), np.full(n, sv), np.full(y.size - 2 * n, sz)])


def _weights(scale: np.ndarray, n: int) -> np.ndarray:
    """Weights of the shooting residual's rows: 1 for x and v, (x's scale / z's scale) for the
    laws' states, so that a state's mismatch counts relative to its own size."""
    w = np.ones(scale.size)
    w[2 * n:] = scale[0] / scale[2 * n:]
    return w


def _n_law_states(model: Model) -> int:
    return model.n_states() - 2 * model.n_bodies


def _finish(runner: _Runner, y0: np.ndarray, period: float, autonomous: bool, norm: float, it: int,
            n_out: int, fortran: dict[str, Any] | None = None) -> Orbit:
    """The Orbit at (y0, period): a run over the period on the grid, the monodromy (the one
    `fortran`, the Fortran solver's answer, brings, or the route's) and its multipliers."""
    model = runner.model
    n = model.n_bodies
    res = runner.run(y0, period, n_out=n_out)
    events = res.events
    if not _fortran_route(runner):
        mono, how = _saltation_monodromy(runner, y0, period, events), "saltation"
        mult = np.linalg.eigvals(mono)
        mult = mult[np.argsort(-np.abs(mult), kind="stable")]
    else:
        fortran = fortran or _fortran_orbit(runner, y0, period, False, 1.0, 0)
        mono, mult, how = fortran["monodromy"], fortran["multipliers"], "finite differences"
    if np.all(np.abs(mult.imag) <= 1e-14 * np.maximum(1.0, np.abs(mult))):
        mult = mult.real
    trivial = int(np.argmin(np.abs(mult - 1.0))) if autonomous else None
    trivial_error = float(abs(mult[trivial] - 1.0)) if trivial is not None else math.nan
    if trivial_error > 1e-3:
        warnings.warn(f"periodic_orbit ({runner.method}, {how}): no multiplier within 1e-3 of 1 (closest "
                      f"{mult[trivial]:.6g}); the multipliers and `stable` are not to be trusted",
                      MonodromyWarning, stacklevel=3)
    others = np.delete(np.abs(mult), trivial) if trivial is not None else np.abs(mult)
    stable = bool(np.all(others < 1.0))
    sys_ = _System(model)
    return Orbit(period=period, x0=y0[:n].copy(), v0=y0[n:2 * n].copy(), z0=y0[2 * n:].copy(), multipliers=mult,
                 trivial=trivial, trivial_error=trivial_error, stable=stable,
                 amplitude=_amplitude(res, [c.b if c.a is None else c.a for c in model.contacts]), stick_fraction=_stick(sys_, res, period),
                 events=events, result=res, monodromy=mono, monodromy_method=how, residual=norm, iterations=it,
                 autonomous=autonomous, method=runner.method, runs=runner.runs)


def _amplitude(res: Result, contacts: Sequence[int]) -> np.ndarray:
    """Half the peak-to-peak x of each body over the run: the grid's extremes refined by the
    cubic (Hermite, from x and v) through the two grid points around each, and the positions
    at events (of body `contacts[c]`, the first body of contact c that is not the ground)."""
    t, x, v = res.t, res.x, res.v
    out = np.empty(x.shape[0])
    # an interval with an event (a kink in x'') is not refined: the event's position stands in
    kinked = set((np.searchsorted(t, res.events["t"]) - 1).tolist())
    for b in range(x.shape[0]):
        cand = [float(x[b, 0]), float(x[b, -1])]
        xb, vb = x[b], v[b]
        idx = np.flatnonzero(np.sign(vb[:-1]) != np.sign(vb[1:]))
        for i in idx:
            if i in kinked:
                continue
            h = t[i + 1] - t[i]
            p0, p1, m0, m1 = xb[i], xb[i + 1], vb[i] * h, vb[i + 1] * h
            # derivative of the Hermite cubic in s in [0, 1]: a s^2 + b s + c
            a = 6 * p0 + 3 * m0 - 6 * p1 + 3 * m1
            bq = -6 * p0 - 4 * m0 + 6 * p1 - 2 * m1
            roots = np.roots([a, bq, m0]) if abs(a) > 0 else np.array([-m0 / bq]) if bq else np.array([])
            for s in roots:
                if abs(s.imag) < 1e-12 and -1e-9 <= s.real <= 1 + 1e-9:
                    s = s.real
                    cand.append(float((2 * s**3 - 3 * s**2 + 1) * p0 + (s**3 - 2 * s**2 + s) * m0
                                      + (-2 * s**3 + 3 * s**2) * p1 + (s**3 - s**2) * m1))
        cand.extend(float(xb[i]) for i in range(xb.size) if vb[i] == 0.0)
        cand.extend(float(e["x"]) for e in res.events if contacts[int(e["contact"])] == b)
        out[b] = 0.5 * (max(cand) - min(cand))
    return out


def _stick(sys_: _System, res: Result, period: float) -> np.ndarray:
    """Fraction of the period each contact is stuck: from the events (event_driven), else the
    grid points where its slip velocity is exactly 0."""
    nc = len(sys_.contacts)
    out = np.zeros(nc)
    if res.method == "event_driven":
        y0 = np.concatenate([res.x[:, 0], res.v[:, 0]])
        s0 = sys_.slip(y0, 0.0)
        for c in range(nc):
            since = 0.0 if s0[c] == 0.0 else None
            total = 0.0
            for e in res.events[res.events["contact"] == c]:
                if e["kind"] == "stick":
                    since = e["t"]
                elif e["kind"] == "slip" and since is not None:
                    total, since = total + e["t"] - since, None
            if since is not None:
                total += period - since
            out[c] = total / period
        return out
    y = np.vstack([res.x, res.v])
    for c in range(nc):
        w = sys_.contacts[c].surface_velocity
        s = sys_.G[c] @ y[sys_.n:] - (0.0 if w is None else _signal(w, res.t)[0])
        out[c] = float(np.mean(s[:-1] == 0.0))
    return out


def _fd_monodromy(runner: _Runner, y0: np.ndarray, period: float) -> np.ndarray:
    """Central differences of the flow over the period (the Fortran solver's, at y0)."""
    return _fortran_orbit(runner, y0, period, False, 1.0, 0)["monodromy"]


def _fortran_route(runner: _Runner) -> bool:
    """Whether the orbit's monodromy is by finite differences (every case but event_driven on
    a model whose contacts all use coulomb or stribeck, where saltation matrices make it exact)."""
    model = runner.model
    return not (runner.method == "event_driven" and model.contacts
                and all(c.law in ("coulomb", "stribeck") for c in model.contacts))


def _fortran_orbit(runner: _Runner, y0: np.ndarray, period: float, autonomous: bool, tol: float,
                   max_iter: int) -> dict[str, Any]:
    """The library's orbit solver (stickslip_orbit, through `model.orbit_model`) on the
    runner's model from (y0, period): Newton's method as `_newton` (forward differences of
    step _FD_NEWTON times `_scales`, halving, the tolerance relative to max(1, |u|)) and the
    central-difference monodromy of step _FD_MONODROMY times `_scales` with its eigenvalues;
    max_iter = 0: the monodromy at (y0, period) only. Its failures as this module's."""
    with warnings.catch_warnings():        # as the runs of _Runner.run
        warnings.simplefilter("ignore")
        out = orbit_model(runner.model, runner.method, y0, period, autonomous, runner.controls, tol=tol,
                          max_iter=max_iter, fd_newton=_FD_NEWTON, fd_monodromy=_FD_MONODROMY)
    runner.runs += out["runs"]
    status = out["status"]
    if status == _NO_ORBIT:
        u = np.append(y0, period) if autonomous else y0
        tol_abs = tol * max(1.0, float(np.max(np.abs(u))))
        raise NoConvergence(f"periodic_orbit: Newton's method did not converge (residual {out['residual']:.3g} "
                            f"after {out['iterations']} iterations, tolerance {tol_abs:.3g}); give a better guess "
                            "or looser tolerances", out["residual"], out["iterations"])
    if status == _ORBIT_COLLAPSED:
        _check_period(out["period"], period)
    if status != STATUS_OK:
        raise SteadyStateError(f"periodic_orbit ({runner.method}): a run failed: {status_message(status)} "
                               f"(status {status})")
    return out


def _expm(a: np.ndarray) -> np.ndarray:
    """exp(a) by scaling and squaring of its Taylor series (18 terms on a / 2^s with
    |a / 2^s| <= 1/2: truncation below 1e-22); numpy only, for the small matrices of a mode
    (scipy's expm costs milliseconds per call here)."""
    norm = float(np.max(np.sum(np.abs(a), axis=1))) if a.size else 0.0
    s = max(0, int(math.ceil(math.log2(norm / 0.5)))) if norm > 0.5 else 0
    b = a / 2.0**s
    out = np.eye(a.shape[0])
    term = np.eye(a.shape[0])
    for k in range(1, 19):
        term = term @ b / k
        out = out + term
    for _ in range(s):
        out = out @ out
    return out


def _saltation_monodromy(runner: _Runner, y0: np.ndarray, period: float, events: np.ndarray) -> np.ndarray:
    """The monodromy of a set-valued model under event_driven: the variational equation of
    each mode between events (exact for Coulomb's affine modes, integrated for Stribeck's) and
    a saltation matrix at each event (see the module)."""
    sys_ = _System(runner.model)
    nc = len(sys_.contacts)
    s0 = sys_.slip(y0, 0.0)
    modes = [int(np.sign(s)) for s in s0]
    if any(m == 0 for m in modes):          # a contact stuck at the section: its holding force decides
        _, lam = sys_.rates(y0, 0.0, modes)
        for c in range(nc):
            normal = float(_signal(sys_.contacts[c].normal_force, 0.0)[0])
            if modes[c] == 0 and abs(lam[c]) > sys_.params[c]["mu_s"] * normal:
                modes[c] = -int(np.sign(lam[c]))
    mono = np.eye(y0.size)
    t_prev, y_prev = 0.0, y0
    for e in events:
        t, c, kind = float(e["t"]), int(e["contact"]), str(e["kind"])
        if not 0.0 < t < period:
            continue
        # the state at the event: a run that ends just before it (one ending on an event can
        # fail at h_min), then the Taylor step of the affine mode over the last delta
        delta = min(1e-9 * period, t)       # an event within delta of the section: from y0
        y = runner.flow(y0, t - delta) if t > delta else y0
        jac, _ = sys_.jacobian(y, t, modes)
        rate = sys_.rates(y, t - delta, modes)[0]
        y = y + delta * rate + 0.5 * delta**2 * (jac @ rate)
        mono = sys_.propagator(y_prev, t_prev, t, modes) @ mono
        t_prev, y_prev = t, y
        before = list(modes)
        after = list(modes)
        f_minus, lam = sys_.rates(y, t, before)
        normal, dnormal = (float(q) for q in _signal(sys_.contacts[c].normal_force, t))
        if kind in ("stick", "reversal"):
            # h = s_c = G_c v - w_c(t): n = (0, G_c), dh/dt = G_c a- - w_c'(t)
            after[c] = 0 if kind == "stick" else -before[c]
            if kind == "reversal" and before[c] == 0:
                after[c] = -int(np.sign(sys_.G[c] @ f_minus[sys_.n:] - sys_.surface(c, t)[1]))
            n_vec = np.concatenate([np.zeros(sys_.n), sys_.G[c]])
            dhdt = float(sys_.G[c] @ f_minus[sys_.n:] - sys_.surface(c, t)[1])
        else:
            # slip: h = sigma lambda_c - mu_s N_c(t), sigma = sign(lambda_c); lambda_c affine in y
            sigma = float(np.sign(lam[c]))
            after[c] = -int(sigma)
            _, jl = sys_.jacobian(y, t, before)
            n_vec = sigma * jl[c]
            dt = 1e-6 * period
            lt = (sys_.rates(y, t + dt, before)[1][c] - sys_.rates(y, t - dt, before)[1][c]) / (2 * dt)
            dhdt = float(n_vec @ f_minus + sigma * lt - sys_.params[c]["mu_s"] * dnormal)
        f_plus, _ = sys_.rates(y, t, after)
        if dhdt == 0.0:
            raise SteadyStateError(f"{runner.model.contact_label(c)}: a grazing {kind} event at t = {t!r} s "
                                   "(dh/dt = 0): the saltation matrix is undefined there")
        mono = (np.eye(y0.size) + np.outer(f_plus - f_minus, n_vec) / dhdt) @ mono
        modes = after
    return sys_.propagator(y_prev, t_prev, period, modes) @ mono


# ------------------------------------------------------------------------------------------
# Equilibria
# ------------------------------------------------------------------------------------------
@dataclass
class Equilibrium:
    """An equilibrium of an autonomous model (returned by `equilibrium`; the points of a
    ``continuation(..., kind="equilibrium")`` branch): every body at rest, each contact sliding
    at its surface's speed (steady sliding on a belt).

    Attributes
    ----------
    x0, v0 : numpy.ndarray, shape (n_bodies,)
        The position [m] and the velocity (zero) [m/s] of each body.
    eigenvalues : numpy.ndarray, shape (2 n_bodies,)
        Eigenvalues of `jacobian` [1/s], largest real part first (complex when any is).
    jacobian : numpy.ndarray, shape (2 n_bodies, 2 n_bodies)
        d(dy/dt)/dy at the equilibrium, y = (x, v): the springs' and dampers' matrices and each
        contact's friction slope N mu'(s) at its slip s, by central differences of the law's
        curve (`friction_coefficient`) of step 1e-6 max(1, abs(s)).
    stable : bool
        Every eigenvalue's real part < 0.
    residual : float
        Infinity norm of the net force on the bodies at the answer [N].
    """

    x0: np.ndarray
    v0: np.ndarray
    eigenvalues: np.ndarray
    jacobian: np.ndarray
    stable: bool
    residual: float

    @property
    def y0(self) -> np.ndarray:
        """The state (x0, v0)."""
        return np.concatenate([self.x0, self.v0])

    #: no period (the field a Branch reads from its points)
    period = math.nan

    @property
    def amplitude(self) -> np.ndarray:
        """Zero for every body: no motion."""
        return np.zeros(self.x0.size)

    @property
    def stick_fraction(self) -> np.ndarray:
        """Empty: no period to be stuck over."""
        return np.zeros(0)

    @property
    def multipliers(self) -> np.ndarray:
        """Empty: an equilibrium's stability is in `eigenvalues`."""
        return np.zeros(0)


#: laws that are set-valued at zero slip under event_driven: a contact at rest on its surface
#: holds a set of equilibria, not one
_SET_VALUED = ("coulomb", "stribeck")


def equilibrium(model: Model, guess: Any = None) -> Equilibrium:
    """The equilibrium of an autonomous `model` and its eigenvalues.

    With every body at rest each contact slips at minus its surface's speed, so its friction is
    a constant and the net force is affine in the positions (springs are linear): the
    equilibrium solves K x = f, one linear solve (no iteration). The Jacobian adds each
    contact's friction slope N mu'(s) to the damping (a falling law makes it negative: the
    onset of stick-slip is the Hopf point where the damping of a mode vanishes).

    Parameters
    ----------
    model : Model
        The system; no time signal (constants only), no drive, no law with internal states,
        and no contact of a set-valued law (coulomb, stribeck) whose surface is at rest (a
        contact stuck at rest holds a set of equilibria).
    guess : array_like, optional
        Not needed (the equilibrium is unique when the stiffness matrix is regular); accepted
        for symmetry with `periodic_orbit` and ignored.

    Returns
    -------
    Equilibrium

    Raises
    ------
    SteadyStateError
        A singular stiffness matrix (a body held by no spring: no isolated equilibrium), or a
        set-valued contact at rest on its surface.
    NonPeriodicForcing, LawStatesUnsupported, ValueError
        A forced model (no equilibrium), a law with states, a model with drives.
    """
    del guess
    model = _check_model(model)
    if model.drives:
        raise ValueError("model: has drives (prescribed motions); its equilibria are not computed")
    if forcing_period(model) is not None:
        raise NonPeriodicForcing("model: forced by sines; a forced model has no equilibrium (its steady "
                                 "state is a periodic orbit: periodic_orbit)")
    for where, s in _model_signals(model):
        if s.kind != "constant" and float(_signal(s, 0.0)[0]) != float(_signal(s, 1e6)[0]):
            raise NonPeriodicForcing(f"{where}: changes in time; an equilibrium needs constant signals")
    sys_ = _System(model)
    n = sys_.n
    zero = np.zeros(2 * n)
    for i, c in enumerate(model.contacts):
        if c.law in _SET_VALUED and sys_.slip(zero, 0.0)[i] == 0.0:
            raise SteadyStateError(f"{model.contact_label(i)}: at rest on its surface (slip 0) with the set-valued "
                                   f"law {c.law!r}: its equilibria are a set (every position where the spring "
                                   "force is within mu_s N), not one point")
    f0 = sys_._free(zero, 0.0, None)
    try:
        x = np.linalg.solve(sys_.K, f0)
    except np.linalg.LinAlgError:
        raise SteadyStateError("model: the stiffness matrix is singular (a body held by no spring): "
                               "no isolated equilibrium") from None
    if not np.all(np.isfinite(x)) or np.linalg.cond(sys_.K) > 1e14:
        raise SteadyStateError("model: the stiffness matrix is singular (a body held by no spring): "
                               "no isolated equilibrium")
    y = np.concatenate([x, np.zeros(n)])
    jac = _equilibrium_jacobian(sys_, y)
    eig = np.linalg.eigvals(jac)
    eig = eig[np.argsort(-eig.real, kind="stable")]
    if np.all(np.abs(eig.imag) == 0.0):
        eig = eig.real
    residual = float(np.max(np.abs(sys_._free(y, 0.0, None)))) if n else 0.0
    return Equilibrium(x0=x, v0=np.zeros(n), eigenvalues=eig, jacobian=jac, stable=bool(np.all(eig.real < 0.0)),
                       residual=residual)


def _equilibrium_jacobian(sys_: _System, y: np.ndarray) -> np.ndarray:
    """d(dy/dt)/dy at y: x and the springs exactly (K), v by central differences of the
    forces of step 1e-6 max(1, abs(slip)) (the dampers exactly, the laws' slopes to about 1e-10)."""
    n = sys_.n
    jac = np.zeros((2 * n, 2 * n))
    jac[:n, n:] = np.eye(n)
    jac[n:, :n] = -sys_.K / sys_.mass[:, None]
    s = sys_.slip(y, 0.0)
    h = 1e-6 * max(1.0, float(np.max(np.abs(s)))) if s.size else 1e-6
    for j in range(n):
        e = y.copy()
        e[n + j] += h
        fp = sys_._free(e, 0.0, None)
        e[n + j] -= 2 * h
        fm = sys_._free(e, 0.0, None)
        jac[n:, n + j] = (fp - fm) / (2 * h) / sys_.mass
    return jac


def _root(g: Callable[[float], float], a: float, b: float, ga: float, gb: float, xtol: float,
          max_iter: int = 60) -> float:
    """A root of g between a and b (g(a), g(b) of opposite signs) by the Illinois variant of
    regula falsi, to xtol."""
    side = 0
    for _ in range(max_iter):
        c = (a * gb - b * ga) / (gb - ga)
        if abs(b - a) <= xtol:
            break
        gc = g(c)
        if gc == 0.0:
            return c
        if (gc > 0) == (gb > 0):
            b, gb = c, gc
            if side == -1:
                ga *= 0.5
            side = -1
        else:
            a, ga = c, gc
            if side == 1:
                gb *= 0.5
            side = 1
        if abs(b - a) <= xtol:
            break
    return (a * gb - b * ga) / (gb - ga)


def _hopf_test(eq: Equilibrium) -> float:
    """The product of the real parts of the complex eigenvalues in the upper half-plane (1 when
    none is complex): changes sign where one pair crosses the imaginary axis (a Hopf point)."""
    ev = np.asarray(eq.eigenvalues)
    return float(np.prod(ev.real[ev.imag > 0.0]))


def _zero_test(eq: Equilibrium) -> float:
    """The product of the real eigenvalues (1 when none is real): changes sign where one of
    them passes 0."""
    ev = np.asarray(eq.eigenvalues)
    return float(np.prod(ev.real[ev.imag == 0.0]))


def _equilibrium_branch(build: Callable[[float], Model], start: float, stop: float, step: float,
                        max_points: int, progress: bool) -> "Branch":
    """Equilibria at equal steps of p from start to stop (a graph over p: see `equilibrium`),
    Hopf points (a complex pair crossing the imaginary axis) and real eigenvalues through 0
    ("stability change") located by regula falsi on p to 1e-12 of the range; a change of the
    number of unstable eigenvalues that neither test function follows (e.g. two crossings
    between two points) is a "stability change" at the second point, not located."""
    n_pts = min(max_points, max(2, int(math.ceil(1.0 / step)) + 1))
    ps = [float(start) + (float(stop) - float(start)) * k / (n_pts - 1) for k in range(n_pts)]
    ps[-1] = float(stop)
    bar = _Progress(progress, float(start), float(stop))
    eqs: list[Equilibrium] = []
    for p in ps:
        eqs.append(equilibrium(build(p)))
        bar.show(p)
    bar.close()
    out: list[dict[str, Any]] = []
    xtol = 1e-12 * abs(float(stop) - float(start))
    for i in range(1, len(eqs)):
        a, b = eqs[i - 1], eqs[i]
        if int(np.sum(a.eigenvalues.real > 0.0)) == int(np.sum(b.eigenvalues.real > 0.0)):
            continue
        same_kinds = int(np.sum(a.eigenvalues.imag > 0.0)) == int(np.sum(b.eigenvalues.imag > 0.0))
        found = False
        for kind, test in (("Hopf", _hopf_test), ("stability change", _zero_test)):
            ga, gb = test(a), test(b)
            if same_kinds and (ga > 0.0) != (gb > 0.0):
                p = _root(lambda q: test(equilibrium(build(q))), ps[i - 1], ps[i], ga, gb, xtol)
                entry: dict[str, Any] = {"kind": kind, "index": i, "p": p, "located": True}
                if kind == "Hopf":
                    ev = equilibrium(build(p)).eigenvalues
                    crit = ev[np.argmin(np.where(ev.imag > 0.0, np.abs(ev.real), math.inf))]
                    entry.update(frequency=float(np.imag(crit)), eigenvalues=ev)
                out.append(entry)
                found = True
        if not found:
            out.append({"kind": "stability change", "index": i, "p": ps[i], "located": False})
    return Branch.from_orbits(ps, eqs, f"reached stop = {stop!r}", out, kind="equilibrium")


# ------------------------------------------------------------------------------------------
# Continuation
# ------------------------------------------------------------------------------------------
@dataclass
class Branch:
    """A branch of periodic orbits against a parameter (returned by `continuation` and
    `frequency_response`).

    Attributes
    ----------
    p : numpy.ndarray, shape (n,)
        The parameter at each point.
    period : numpy.ndarray, shape (n,)
        Periods [s].
    amplitude : numpy.ndarray, shape (n, n_bodies), or (n,) for one body
        Half peak-to-peak displacement [m].
    stable : numpy.ndarray of bool, shape (n,)
    multipliers : numpy.ndarray, shape (n, 2 n_bodies)
        Floquet multipliers (complex when any is), largest modulus first.
    stick_fraction : numpy.ndarray, shape (n, n_contacts)
    orbits : list of Orbit
    bifurcations : list of dict
        Each with "kind" ("fold": p turns back; "Hopf": p turns back where the cycle's
        amplitude shrinks to under a tenth of its neighbours', the branch passing through
        the equilibrium it is born from; "branch point": a real multiplier passes +1 (prod(mu -
        1) changes sign) where p goes on and the events per period stay the same, another
        branch crossing this one (a pitchfork: e.g. a symmetric orbit giving birth to a pair
        of asymmetric ones), reported only where `locate_bifurcations` finds a smooth root of
        prod(mu - 1) (within 1e-3 of its values at the points, and within a quarter of the
        step of the linear interpolation's root; otherwise a "stability change", the
        multiplier jumping across +1); "period doubling": a real multiplier passes -1
        (prod(mu + 1) changes sign); "Neimark-Sacker": a complex pair leaves or enters the
        unit circle; "stability change": stability flips otherwise, e.g. a multiplier jumps
        across the circle at a nonsmooth point; "events": the number or kind of events per
        period changed, e.g. a stick phase appeared), "index" (the point at the turn, or the
        point after the change), "p" and "located" (True: p is the root of the kind's test
        function found by `continuation`'s `locate_bifurcations`; False: interpolated
        between the points, or for a "Hopf" the turning point).
    stop_reason : str
        Why the continuation ended.
    curve : Branch or None
        For `frequency_response`: the whole continued curve, folds included.
    kind : str
        "orbit" (periodic orbits; `orbits` holds `Orbit`) or "equilibrium" (``continuation(...,
        kind="equilibrium")``: `orbits` holds `Equilibrium`, `period` is NaN, `amplitude` 0,
        `multipliers` empty, and `eigenvalues` of shape (n, 2 n_bodies) the Jacobian's, largest
        real part first; its bifurcations are "Hopf" (a complex pair crossing the imaginary
        axis, with its "frequency" [rad/s]) and "stability change" (a real eigenvalue through 0),
        each located on p to 1e-12 of the range ("located" True), or, when neither test
        function follows the change (two crossings between two points), a "stability change"
        at the second point ("located" False)).
    eigenvalues : numpy.ndarray
        See `kind` (shape (n, 0) for orbits).
    """

    p: np.ndarray
    period: np.ndarray
    amplitude: np.ndarray
    stable: np.ndarray
    multipliers: np.ndarray
    stick_fraction: np.ndarray
    orbits: list[Orbit]
    bifurcations: list[dict[str, Any]]
    stop_reason: str
    curve: "Branch | None" = None
    kind: str = "orbit"
    eigenvalues: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))

    @classmethod
    def from_orbits(cls, ps: Sequence[float], orbits: Sequence[Orbit | Equilibrium], stop_reason: str,
                    bifurcations: list[dict[str, Any]] | None = None, kind: str = "orbit") -> "Branch":
        amp = np.array([o.amplitude for o in orbits]) if orbits else np.zeros((0, 1))
        if amp.ndim == 2 and amp.shape[1] == 1:
            amp = amp[:, 0]
        mult = np.array([o.multipliers for o in orbits]) if orbits else np.zeros((0, 0))
        eig = np.array([getattr(o, "eigenvalues", np.zeros(0)) for o in orbits]) if orbits else np.zeros((0, 0))
        return cls(p=np.asarray(ps, dtype=float), period=np.array([o.period for o in orbits]), amplitude=amp,
                   stable=np.array([o.stable for o in orbits], dtype=bool), multipliers=mult,
                   stick_fraction=np.array([o.stick_fraction for o in orbits]), orbits=list(orbits),
                   bifurcations=list(bifurcations or []), stop_reason=stop_reason, kind=kind, eigenvalues=eig)

    def __len__(self) -> int:
        return int(self.p.size)

    def plot(self, ax: Any = None, body: int = 0) -> Any:
        """Amplitude of `body` against p, solid where stable, dashed where not, bifurcations
        marked; returns the axes (a new figure's when `ax` is None)."""
        import matplotlib.pyplot as plt
        if ax is None:
            _, ax = plt.subplots(figsize=(6.0, 4.0))
        amp = self.amplitude if self.amplitude.ndim == 1 else self.amplitude[:, body]
        for flag, style in ((True, "-"), (False, "--")):
            ax.plot(self.p, np.where(self.stable == flag, amp, np.nan), style, color="C0",
                    label="stable" if flag else "unstable")
        for b in self.bifurcations:
            i = b["index"]
            ax.plot(b["p"], amp[i], "o", ms=4, mfc="white", color="C3")
            ax.annotate(b["kind"], (b["p"], amp[i]), fontsize="x-small", xytext=(3, 3), textcoords="offset points")
        ax.set_xlabel("parameter p")
        ax.set_ylabel("amplitude [m]")
        ax.legend(loc="best", fontsize="small")
        return ax


def _signature(o: Orbit) -> tuple[tuple[str, int], ...]:
    """The number of events of each kind at each contact over a period."""
    kinds, counts = np.unique(np.array([f"{e['kind']}@{e['contact']}" for e in o.events]), return_counts=True)
    return tuple((str(k), int(c)) for k, c in zip(kinds, counts))


def _test_plus_one(o: Orbit) -> float:
    """prod(mu - 1) over the nontrivial multipliers: changes sign where a real multiplier
    passes through +1 (a fold, or a branch point)."""
    return float(np.real(np.prod(o.nontrivial - 1.0)))


def _test_minus_one(o: Orbit) -> float:
    """prod(mu + 1) over the nontrivial multipliers: changes sign where a real multiplier
    passes through -1 (period doubling; complex pairs contribute abs(mu + 1)^2 > 0)."""
    return float(np.real(np.prod(o.nontrivial + 1.0)))


def _complex(o: Orbit) -> np.ndarray:
    m = o.nontrivial
    return m[np.abs(np.imag(m)) > 1e-9 * np.maximum(1.0, np.abs(m))]


def _test_torus(o: Orbit) -> float:
    """Largest modulus of a complex nontrivial multiplier minus 1 (NaN when none is complex):
    changes sign where a complex pair leaves the unit circle (Neimark-Sacker)."""
    c = _complex(o)
    return float(np.max(np.abs(c))) - 1.0 if c.size else math.nan


def _bifurcations(ps: list[float], orbits: list[Orbit], dps: list[float],
                  locate: Callable[[int, Callable[[Orbit], float]], tuple[float, float] | None] | None = None
                  ) -> list[dict[str, Any]]:
    """The bifurcations between the branch's points; `locate(i, g)`, when given, returns the
    p where the test function g(orbit) vanishes between points i - 1 and i and g's value at
    the orbit found there (None if it cannot)."""
    def where(i: int, g: Callable[[Orbit], float], smooth: bool = False) -> tuple[float, bool]:
        """p and whether it was located; with `smooth`, located only at a root of g that is
        smooth over the step: g there within 1e-3 of its values at the two points, and p within
        a quarter of the step of the linear interpolation's root (not a jump of g across 0)."""
        ga, gb = g(orbits[i - 1]), g(orbits[i])
        linear = ps[i - 1] + ga / (ga - gb) * (ps[i] - ps[i - 1])
        found = locate(i, g) if locate is not None else None
        if found is not None and (not smooth or (abs(found[1]) <= 1e-3 * max(abs(ga), abs(gb)) and
                                                 abs(found[0] - linear) <= 0.25 * abs(ps[i] - ps[i - 1]))):
            return found[0], True
        return linear, False

    def flips(i: int, g: Callable[[Orbit], float]) -> bool:
        ga, gb = g(orbits[i - 1]), g(orbits[i])
        return bool(np.isfinite(ga) and np.isfinite(gb) and (ga > 0.0) != (gb > 0.0))

    out: list[dict[str, Any]] = []
    folded: set[int] = set()
    for i in range(1, len(orbits)):
        a, b = orbits[i - 1], orbits[i]
        if i + 1 < len(orbits) and dps[i] * dps[i + 1] < 0.0:
            # p turns back at point i: a fold, or, where the cycle shrinks to nothing there,
            # the Hopf point of the equilibrium the branch passes through
            small = np.max(b.amplitude) < 0.1 * min(np.max(a.amplitude), np.max(orbits[i + 1].amplitude))
            entry: dict[str, Any] = {"kind": "Hopf" if small else "fold", "index": i, "p": ps[i], "located": False}
            if not small:           # the fold itself: where a multiplier passes +1, either side of point i
                for j in (i, i + 1):
                    if flips(j, _test_plus_one):
                        entry["p"], entry["located"] = where(j, _test_plus_one)
                        folded.update((j, j + 1) if j == i else (j - 1, j))
                        break
            out.append(entry)
        if _signature(a) != _signature(b) or (a.stick_fraction > 0).tolist() != (b.stick_fraction > 0).tolist():
            out.append({"kind": "events", "index": i, "p": 0.5 * (ps[i - 1] + ps[i]),
                        "before": _signature(a), "after": _signature(b)})
        explained = False
        turning = any(0 < j + 1 < len(orbits) and dps[j] * dps[j + 1] < 0.0 for j in (i - 1, i))
        if flips(i, _test_plus_one) and i not in folded and not turning and _signature(a) == _signature(b):
            # a real multiplier through +1 where p goes on: another branch crosses this one
            # (a pitchfork, e.g. where a symmetric orbit gives birth to a pair of asymmetric ones)
            # where prod(mu - 1) has a smooth root; where it jumps across 0 (a multiplier jumping
            # across the circle at a nonsmooth point, or at a steep regularisation of one), a
            # stability change below
            p, ok = where(i, _test_plus_one, smooth=True)
            if ok:
                out.append({"kind": "branch point", "index": i, "p": p, "located": ok})
                explained = True
        if flips(i, _test_minus_one):
            p, ok = where(i, _test_minus_one)
            out.append({"kind": "period doubling", "index": i, "p": p, "located": ok})
            explained = True
        ca, cb = _complex(a), _complex(b)
        if ca.size and cb.size and int(np.sum(np.abs(ca) > 1.0)) != int(np.sum(np.abs(cb) > 1.0)):
            p, ok = where(i, _test_torus)
            out.append({"kind": "Neimark-Sacker", "index": i, "p": p, "located": ok})
            explained = True
        if a.stable != b.stable and not explained and i not in folded:
            ma, mb = a.nontrivial, b.nontrivial
            big_a, big_b = ma[np.argmax(np.abs(ma))], mb[np.argmax(np.abs(mb))]
            if abs(np.imag(big_b)) > 1e-9 or abs(np.imag(big_a)) > 1e-9:
                kind = "Neimark-Sacker"
            elif np.real(big_b) < 0 or np.real(big_a) < 0:
                kind = "period doubling"
            else:
                kind = "stability change"
            ra, rb = float(np.max(np.abs(ma))), float(np.max(np.abs(mb)))
            s = (1.0 - ra) / (rb - ra) if rb != ra else 0.5
            out.append({"kind": kind, "index": i, "p": ps[i - 1] + s * (ps[i] - ps[i - 1]), "located": False})
    return out


def continuation(build: Callable[[float], Model], start: float, stop: float, guess: Any = None, *,
                 step: float | None = None, min_step: float | None = None, max_step: float | None = None,
                 max_points: int = 200, method: str = "event_driven", tol: float = 1e-9, progress: bool = False,
                 kind: str = "orbit", locate_bifurcations: bool = True, **options: Any) -> Branch:
    """Pseudo-arclength continuation of periodic orbits (or equilibria, ``kind="equilibrium"``)
    in a parameter p from `start` to `stop`.

    Parameters
    ----------
    build : callable
        ``build(p)`` returns the Model at parameter p (forced models are forced at their own
        period, which may depend on p: the period of their sines).
    start, stop : float
        The range of p; the branch begins at `start` and ends where p leaves [start, stop]
        (the last point lands on `stop` exactly), after `max_points`, or where a step fails
        at `min_step`.
    guess : optional
        The first orbit's guess, as for `periodic_orbit`.
    step, min_step, max_step : float, optional
        Arclength step control in the scaled (p, state, period) space: p is scaled by
        abs(stop - start), so the default first step 1/50 is 2 % of the range. A step is halved
        when its corrector fails, lands farther than one step from the prediction, or turns
        the branch by more than 25 degrees (a jump to another branch; on the first step, whose
        tangent is p's axis: lands on an orbit with another number of events a period than
        the first); it grows 1.5 times
        after a corrector of at most 3 iterations, up to `max_step` (default 0.1; min_step
        1e-5). The states are scaled by the first orbit's largest |x| and |v|: a response
        whose amplitude grows tenfold is a long branch in these units.
    max_points : int, optional
        Points at most (default 200).
    method, tol, **options
        As for `periodic_orbit` (controls of the method, `n_out`, `transient`).
    progress : bool, optional
        A progress bar on stderr.
    kind : str, optional
        "orbit" (default) or "equilibrium": the equilibria of the autonomous models build(p)
        (`equilibrium`) at equal steps of p, `step` the fraction of the range between points
        (default 1/50; `max_points` caps their number), with their eigenvalues and Hopf points.
        An equilibrium of a Model solves a linear system (see `equilibrium`), so its branch is
        a graph over p: no folds, and no arclength needed. `guess`, `method`, `tol`,
        `min_step`, `max_step` and `options` do not apply.
    locate_bifurcations : bool, optional
        True (default): each fold, branch point, period doubling and Neimark-Sacker point
        found between two points is located by regula falsi on its test function (prod(mu -
        1) for the first two, prod(mu + 1)
        over the nontrivial multipliers, the largest complex multiplier's modulus minus 1)
        along the arclength of that step, each trial a corrector solve (about ten per point);
        its "located" is then True. False: interpolated linearly between the two points.

    Returns
    -------
    Branch
    """
    span = float(stop) - float(start)
    if not (math.isfinite(span) and span != 0.0):
        raise ValueError(f"start, stop: must be finite and differ, got {start!r}, {stop!r}")
    if kind not in ("orbit", "equilibrium"):
        raise ValueError(f"kind: must be 'orbit' or 'equilibrium', got {kind!r}")
    if kind == "equilibrium":
        eq_step = 0.02 if step is None else _finite("step", step, "in (0, 1]")
        if not 0.0 < eq_step <= 1.0:
            raise ValueError(f"step: must be in (0, 1] (a fraction of the range) for equilibria, got {step!r}")
        return _equilibrium_branch(build, float(start), float(stop), eq_step, _count("max_points", max_points, 2),
                                   progress)
    ds = 0.02 if step is None else float(step)
    ds_min = 1e-5 if min_step is None else float(min_step)
    ds_max = 0.1 if max_step is None else float(max_step)
    if not 0.0 < ds_min <= ds <= ds_max:
        raise ValueError(f"step: need 0 < min_step <= step <= max_step, got {ds_min!r}, {ds!r}, {ds_max!r}")
    n_out = options.pop("n_out", 4001)
    transient = options.pop("transient", 30)
    first = periodic_orbit(build(float(start)), guess=guess, method=method, tol=tol, n_out=n_out,
                           transient=transient, **options)
    autonomous = first.autonomous

    phase = 0.0
    if not autonomous:                  # the section of a forced branch: a slip phase (see _solve)
        r0 = _Runner(_check_model(build(float(start)), allow_states=True), method,
                     _controls(build(float(start)), method, options))
        phase = _section_phase(r0, first.y0, first.period)

    def unknowns(o: Orbit, p: float) -> np.ndarray:
        u = o.y0 if not phase else r0.flow(o.y0, phase * o.period)
        return np.concatenate([u, [o.period] if autonomous else [], [p]])
    # the states scaled by the first orbit's largest |x| and |v| over its period (not the
    # section's values, which may be near 0)
    scale = np.append(_scales(np.concatenate([np.max(np.abs(first.result.x), axis=1),
                                              np.max(np.abs(first.result.v), axis=1),
                                              np.max(np.abs(first.result.y[2 * first.x0.size:]), axis=1,
                                                     initial=0.0)]), first.x0.size),
                      [first.period] if autonomous else [])
    scale = np.append(scale, abs(span))
    ps, orbits, dps = [float(start)], [first], [math.copysign(1.0, span)]
    # how each point was reached: (the previous point's scaled unknowns, the tangent, the step)
    steps: list[tuple[np.ndarray, np.ndarray, float] | None] = [None]
    prev_u = unknowns(first, float(start)) / scale
    tangent = np.zeros(prev_u.size)
    tangent[-1] = math.copysign(1.0, span)
    reason = f"reached stop = {stop!r}"
    bar = _Progress(progress, float(start), float(stop))
    while True:
        if len(orbits) >= max_points:
            reason = f"max_points = {max_points} reached"
            break
        ok = False
        while not ok:
            pred = prev_u + ds * tangent
            try:
                orb, u_new, its = _corrector(build, pred, tangent, scale, autonomous, method, tol, n_out, options,
                                             orbits[-1], phase)
                # a corrector that lands far from the prediction, or turns the branch sharply,
                # may have jumped to another branch: a shorter step (AUTO's and COCO's guards)
                # (not on the first step, whose tangent is p's axis, not yet the branch's: there
                # an orbit of another kind, with another number of events a period, is taken
                # for a jump, so that the step shrinks until it stays on the first orbit's kind)
                chord = u_new - prev_u
                turned = float(chord @ tangent) < 0.9 * float(np.linalg.norm(chord))
                if len(orbits) == 1:
                    ok = len(orb.events) == len(orbits[0].events)
                else:
                    ok = not (float(np.linalg.norm(u_new - pred)) > ds or turned)
                if not ok:
                    raise SteadyStateError("the step jumped")
            except (SteadyStateError, ValueError, RuntimeError):
                ds *= 0.5
                if ds < ds_min:
                    reason = f"a step failed at min_step = {ds_min!r} (p = {ps[-1]!r})"
                    break
        if not ok:
            break
        p_new = float(u_new[-1] * scale[-1])
        new_t = (u_new - prev_u) / np.linalg.norm(u_new - prev_u)
        if (p_new - float(stop)) * span > 0.0:            # beyond stop: land on it exactly,
            # from the orbits on either side interpolated to it
            frac = (float(stop) - ps[-1]) / (p_new - ps[-1])
            last = orbits[-1]
            start_y = last.y0 + frac * (orb.y0 - last.y0)
            landing = np.append(start_y, last.period + frac * (orb.period - last.period)) if autonomous else start_y
            try:
                orb = periodic_orbit(build(float(stop)), guess=landing, method=method, tol=tol, n_out=n_out,
                                     **options)
                ps.append(float(stop))
                orbits.append(orb)
                dps.append(new_t[-1])
                steps.append(None)
                bar.show(float(stop))
            except SteadyStateError as err:
                reason = f"the orbit at stop failed: {err}"
            break
        if (p_new - float(start)) * span < 0.0:
            reason = f"the branch turned back below start = {start!r}"
            break
        ps.append(p_new)
        orbits.append(orb)
        dps.append(float(new_t[-1]))
        steps.append((prev_u, tangent, ds))
        tangent, prev_u = new_t, u_new
        bar.show(p_new)
        ds = min(ds_max, ds * 1.5) if its <= 3 else max(ds_min, ds * 0.7) if its > 6 else ds
    bar.close()

    def locate(i: int, g: Callable[[Orbit], float]) -> tuple[float, float] | None:
        """p where g vanishes between points i - 1 and i, and g there: regula falsi on the
        arclength s of the step that reached point i, each trial the corrector's orbit at s (to
        1e-9 of the step; for the landing on stop, on p between the two points); None where a
        trial fails."""
        found: dict[float, tuple[float, float]] = {}
        if steps[i] is None:            # the landing on stop: natural parameter between the two points
            a, b = orbits[i - 1], orbits[i]

            def g_p(p: float) -> float:
                frac = (p - ps[i - 1]) / (ps[i] - ps[i - 1])
                y = a.y0 + frac * (b.y0 - a.y0)
                start = np.append(y, a.period + frac * (b.period - a.period)) if autonomous else y
                found[p] = (p, g(periodic_orbit(build(p), guess=start, method=method, tol=tol, n_out=n_out,
                                                **options)))
                return found[p][1]
            try:
                p = _root(g_p, ps[i - 1], ps[i], g(a), g(b), 1e-9 * abs(ps[i] - ps[i - 1]), max_iter=30)
                return p, g_p(p)
            except (SteadyStateError, ValueError, RuntimeError, ZeroDivisionError):
                return None
        u0, tan, ds_i = steps[i]

        def g_at(s: float) -> float:
            o, w, _ = _corrector(build, u0 + s * tan, tan, scale, autonomous, method, tol, n_out, options,
                                 orbits[i - 1], phase)
            found[s] = (float(w[-1] * scale[-1]), g(o))
            return found[s][1]
        try:
            s = _root(g_at, 0.0, ds_i, g(orbits[i - 1]), g(orbits[i]), 1e-9 * ds_i, max_iter=30)
            g_at(s)
        except (SteadyStateError, ValueError, RuntimeError, ZeroDivisionError):
            return None
        return found[s]
    return Branch.from_orbits(ps, orbits, reason, _bifurcations(ps, orbits, dps, locate if locate_bifurcations
                                                                 else None))


def _corrector(build: Callable[[float], Model], pred: np.ndarray, tangent: np.ndarray, scale: np.ndarray,
               autonomous: bool, method: str, tol: float, n_out: int, options: dict[str, Any],
               last: Orbit, phase: float = 0.0) -> tuple[Orbit, np.ndarray, int]:
    """Newton on (state, [period,] p) with the pseudo-arclength condition tangent . (u - pred) = 0;
    a forced branch's state is taken at `phase` of the period."""
    n2 = last.y0.size
    runners: dict[float, _Runner] = {}
    wts = _weights(scale[:n2], last.x0.size)
    ref = (last.y0, (last.result.y[:n2, 1] - last.result.y[:n2, 0]) / (last.result.t[1] - last.result.t[0]))

    def runner_at(p: float) -> tuple[_Runner, float]:
        if p not in runners:
            m = _check_model(build(p), allow_states=True)
            runners[p] = _Runner(m, method, _controls(m, method, options))
        r = runners[p]
        return r, forcing_period(r.model)  # type: ignore[return-value]

    def residual(w: np.ndarray) -> np.ndarray:
        u = w * scale
        p = float(u[-1])
        r, t_forced = runner_at(p)
        y = u[:n2]
        t = float(u[n2]) if autonomous else t_forced
        if not t > 0.0:
            raise NoConvergence("the period went negative")
        res = wts * (r.flow(y, t, phase * t) - y)
        extra = [(y - ref[0]) @ ref[1] / max(float(np.max(np.abs(ref[1]))), 1e-300)] if autonomous else []
        return np.concatenate([res, extra, [tangent @ (w - pred)]])

    w, norm, it, _ = _newton(residual, pred.copy(), np.ones(pred.size), tol, 15, "continuation")
    u = w * scale
    p = float(u[-1])
    r, t_forced = runner_at(p)
    period = float(u[n2]) if autonomous else t_forced
    _check_period(period, last.period)
    y0 = r.flow(u[:n2], period - phase * period, phase * period) if phase else u[:n2]
    orb = _finish(r, y0, period, autonomous, norm, it, n_out)
    return orb, w, it


class _Progress:
    """A one-line progress bar on stderr (p from start to stop)."""

    def __init__(self, on: bool, start: float, stop: float) -> None:
        self.on, self.start, self.stop = on, start, stop

    def show(self, p: float) -> None:
        if self.on:
            frac = min(max((p - self.start) / (self.stop - self.start), 0.0), 1.0)
            sys.stderr.write(f"\r[{'#' * int(30 * frac):<30}] p = {p:.6g}")
            sys.stderr.flush()

    def close(self) -> None:
        if self.on:
            sys.stderr.write("\n")


def frequency_response(build: Callable[[float], Model], frequencies: Sequence[float], *, follow: bool = True,
                       method: str = "event_driven", tol: float = 1e-9, guess: Any = None, progress: bool = False,
                       **options: Any) -> Branch:
    """The forced response curve: the periodic orbit at each of `frequencies` [Hz].

    Parameters
    ----------
    build : callable
        ``build(f)`` returns the Model forced at f Hz (period 1 / f).
    frequencies : sequence of float
        The frequencies [Hz] of the rows, > 0, in any order (solved from the lowest up).
    follow : bool, optional
        True (default): also continue the curve by pseudo-arclength from the lowest to the
        highest frequency, folds and both branches of a hysteresis included (`.curve`), and
        start each row from the first point of that curve at its frequency. False: each row
        from the previous frequency's orbit (natural-parameter continuation: faster, blind to
        folds).
    method, tol, guess, progress, **options
        As for `continuation` / `periodic_orbit`.

    Returns
    -------
    Branch
        Rows in the order of `frequencies`: `p` the frequency [Hz], `amplitude`, `stable`,
        ...; `curve` the continued curve (when `follow`).
    """
    f = np.asarray(frequencies, dtype=np.float64)
    if f.ndim != 1 or f.size < 1 or not np.all(np.isfinite(f)) or not np.all(f > 0.0):
        raise ValueError(f"frequencies: must be a 1-D sequence of finite values > 0 [Hz], got {frequencies!r}")
    order = np.argsort(f, kind="stable")
    n_out = options.pop("n_out", 1001)
    curve = None
    if follow and f.size > 1 and f[order[-1]] > f[order[0]]:
        curve = continuation(build, float(f[order[0]]), float(f[order[-1]]), guess=guess, method=method, tol=tol,
                             progress=progress, n_out=n_out, **options)
    solved: dict[int, Orbit] = {}
    prev: Any = guess
    for k in order:
        fk = float(f[k])
        start = prev
        on_curve = None if curve is None else _first_on_curve(curve, fk)
        if on_curve is not None:
            start = on_curve
        orb = periodic_orbit(build(fk), period=1.0 / fk, guess=start, method=method, tol=tol, n_out=n_out,
                             **options)
        solved[int(k)] = orb
        prev = orb
    rows = [solved[k] for k in range(f.size)]
    br = Branch.from_orbits(f, rows, "every frequency solved")
    br.curve = curve
    return br


def _first_on_curve(curve: Branch, f: float) -> np.ndarray | None:
    """The start state at frequency f interpolated on the first segment of `curve` that
    crosses it (None if none does)."""
    for i in range(1, len(curve)):
        a, b = curve.p[i - 1], curve.p[i]
        if min(a, b) <= f <= max(a, b) and a != b:
            s = (f - a) / (b - a)
            return (1 - s) * curve.orbits[i - 1].y0 + s * curve.orbits[i].y0
    return None


def _map_signals(model: Model, leaf: Callable[[Signal], Signal]) -> Model:
    """A copy of `model` whose every signal has each primitive replaced by leaf(primitive)."""
    def tune(s: Signal) -> Signal:
        if s.children:
            return Signal(s.kind, s.args, tuple(tune(c) for c in s.children))
        return leaf(s)
    m = copy.copy(model)
    m.forces = [(b, tune(s)) for b, s in model.forces]
    m.contacts = [dataclasses.replace(c, normal_force=tune(c.normal_force),
                                      surface_velocity=None if c.surface_velocity is None else tune(c.surface_velocity))
                  for c in model.contacts]
    return m


def retuned(model: Model, frequency: float) -> Model:
    """A copy of `model` with every sine of its signals at `frequency` [Hz] (the `build` of
    ``python -m stickslip response``: a model file forced at one frequency, retuned)."""
    if not (isinstance(frequency, (int, float)) and math.isfinite(frequency) and frequency > 0.0):
        raise ValueError(f"frequency: must be a finite number > 0 [Hz], got {frequency!r}")
    return _map_signals(model, lambda s: Signal("sine", (s.args[0], float(frequency)) + tuple(s.args[2:]))
                        if s.kind == "sine" else s)


def _shifted(model: Model, t0: float) -> Model:
    """A copy of `model` whose signals are those of `model` advanced by t0 [s]: s'(t) = s(t + t0)."""
    def leaf(s: Signal) -> Signal:
        a = s.args
        if s.kind == "sine":
            return Signal("sine", (a[0], a[1], a[2] + 2.0 * math.pi * a[1] * t0, a[3]))
        if s.kind == "step":
            return Signal("step", (a[0] - t0, a[1], a[2]))
        if s.kind == "ramp":
            return Signal("ramp", (a[0] - t0, a[1], a[2]))
        if s.kind == "table":
            return Signal("table", (tuple(t - t0 for t in a[0]), a[1]))
        return s
    return _map_signals(model, leaf)
