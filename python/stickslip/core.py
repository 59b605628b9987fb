"""The Python facade over the Fortran core: validate names and numbers, call the
compiled wrapper once per simulation, and turn status codes into exceptions.

Units are SI throughout: m, s, kg, m/s; angles in degrees.
"""
from __future__ import annotations

import functools
import math
import os
import re
import threading
import warnings
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any, Callable, Mapping, NoReturn

import numpy as np

from . import _runner
from . import _stickslip as _ext



def _read_registry() -> dict[str, Any]:
    """The core's registry (stickslip_registry::registry_text): laws, scenes, methods,
    parameters, counters, status codes, event kinds and shared constants, one '|'-separated
    record per line."""
    text = _ext.registry().decode().rstrip("\x00 \n")
    reg: dict[str, Any] = {"law": {}, "scene": {}, "method": {}, "param": {}, "status": {}, "event": {},
                           "const": {}}
    for line in text.splitlines():
        kind, *f = line.split("|")
        if kind == "law":
            reg["law"][f[1]] = {"code": int(f[0]), "params": tuple(f[2].split()), "n_states": int(f[3]),
                                # > 0: a law with jumps, solved over its modes (implicit_euler, galpha)
                                "modes": int(f[4]),
                                "states": tuple(x for x in f[5].split(";") if x), "doc": "|".join(f[6:])}
        elif kind == "scene":
            reg["scene"][f[1]] = {"code": int(f[0]), "params": tuple(f[2].split()), "doc": "|".join(f[3:])}
        elif kind == "method":
            reg["method"][f[1]] = {"code": int(f[0]), "order": int(f[2]), "adaptive": f[3] == "1",
                                   "implicit": f[4] == "1", "controls": tuple(f[5].split()), "doc": f[6],
                                   # the laws the method takes (None: every law)
                                   "laws": tuple(f[7].split()) or None}
        elif kind == "param":
            reg["param"][f[0]] = {"code": int(f[1]), "default": float(f[2]), "unit": f[3],
                                  "default_of": f[4] or None, "scale": float(f[5]), "rule": f[6],
                                  "doc": "|".join(f[7:])}
        elif kind == "stats":
            reg["stats_int"], reg["stats_real"] = tuple(f[0].split()), tuple(f[1].split())
        elif kind == "status":
            reg["status"][f[0]] = int(f[1])
        elif kind == "event":
            reg["event"][f[1]] = {"code": int(f[0]), "doc": "|".join(f[2:])}
        elif kind == "const":
            reg["const"][f[0]] = {"value": float(f[1]), "unit": f[2], "doc": "|".join(f[3:])}
    return reg


#: Everything the core lists by name, read from the library at import (one source of truth).
REGISTRY: dict[str, Any] = _read_registry()
LAWS: tuple[str, ...] = tuple(REGISTRY["law"])
SCENES: tuple[str, ...] = tuple(REGISTRY["scene"])
METHODS: tuple[str, ...] = tuple(REGISTRY["method"])
_PARAM_ORDER: tuple[str, ...] = tuple(REGISTRY["param"])
#: Every parameter of a friction law, in the registry's order.
LAW_PARAMS: tuple[str, ...] = tuple(n for n in _PARAM_ORDER
                                    if any(n in info["params"] for info in REGISTRY["law"].values()))
#: Every control some method reads (rtol and atol included).
CONTROLS: tuple[str, ...] = tuple(dict.fromkeys(c for m in REGISTRY["method"].values() for c in m["controls"]))

#: Defaults of the physical parameters (the paper's Table 1 and ours where it is silent).
#: None means "derived": v_d defaults to 1.5 v_s (REGISTRY["param"]["v_d"]).
DEFAULTS: dict[str, float | None] = {
    n: (None if info["default_of"] else info["default"]) for n, info in REGISTRY["param"].items()}

#: Status codes of the library.
_STATUS: dict[str, int] = REGISTRY["status"]
STATUS_OK = _STATUS["OK"]
STATUS_STEP_BUDGET = _STATUS["STEP_BUDGET"]
STATUS_STEP_TOO_SMALL = _STATUS["STEP_TOO_SMALL"]
STATUS_STIFF = _STATUS["STIFF"]
STATUS_NONFINITE = _STATUS["NONFINITE"]
STATUS_OUTPUT_FULL = _STATUS["OUTPUT_FULL"]
_FIRST_INPUT_CODE = -100          # codes <= this name one bad input

#: The facade's defaults of the shared controls; each is passed only to the methods that read
#: it. hmin is the library's HMIN_DEFAULT (1e-6 s, stickslip_registry: the same default in
#: Fortran, C and Python). hmax = 0 lets a step span the whole run [0, t_end] (Hairer's
#: default): the step is then limited by the error test alone. The paper's "automatic" range [hmin, hmax] = [1e-6, 1e-2] s
#: is what its drivers (cases/) pass explicitly. Read-only: simulate reads them once per method
#: (_plan).
CONTROL_DEFAULTS: Mapping[str, Any] = MappingProxyType(
    {"rtol": 1e-6, "atol": 1e-9, "hmin": REGISTRY["const"]["hmin"]["value"], "hmax": 0.0, "h0": 0.0,
     "allow_forced": True, "stop_on_stiff": False})

#: Smallest nonzero relative tolerance the adaptive methods accept (the library's RTOL_MIN,
#: 100 units of round-off).
RTOL_MIN: float = REGISTRY["const"]["rtol_min"]["value"]

#: A grid on which the velocity reverses its direction between at least this fraction of the
#: intervals chattered at the grid's scale, which a motion the grid resolves does not do (the
#: batches' chattered flag, the consistency check's resolved grids).
CHATTER_FRACTION = 0.25

#: Largest every-step output the facade allocates [rows]: 3 arrays of 8-byte floats.
MAX_ROWS = 50_000_000


@functools.lru_cache(maxsize=256)
def status_message(status: int) -> str:
    """The library's message for a status code.

    Parameters
    ----------
    status : int
        A status code of the library (0: success; negative: an error, see `REGISTRY["status"]`).

    Returns
    -------
    str
        Its message (a constant per code, read from the library once).

    Examples
    --------
    >>> import stickslip as ss
    >>> ss.status_message(0)
    'success'
    """
    return _ext.message(status).decode().strip()


class IntegrationError(RuntimeError):
    """An integration that ended before t_end.

    Attributes
    ----------
    status : int
        The library's status code (negative).
    result : Result
        The output up to ``result.stats["t_reached"]``, with the run's counters.
    """

    def __init__(self, status: int, result: "Result") -> None:
        self.status = status
        self.result = result
        # event_driven runs DOPRI5 in each mode and a contact solver at each event: its
        # failure says that it is event_driven's, whichever of them ended it
        who = "event_driven: " if getattr(result, "method", None) == "event_driven" else ""
        super().__init__(
            f"{who}{status_message(status)} (status {status}; reached t = {result.stats['t_reached']:.6g} s "
            f"of {result.t_end:.6g} s after {result.stats['nstep']} steps)")

    def __reduce__(self):
        # picklable (process pools re-raise it in the parent) despite the 2-argument __init__
        return (type(self), (self.status, self.result))


class StepBudgetExhausted(IntegrationError):
    """max_steps attempted steps did not reach t_end."""


class StepSizeTooSmall(IntegrationError):
    """The error test failed at h_min with forced steps disabled, or h underflowed."""


class StiffnessDetected(IntegrationError):
    """DOPRI5's stiffness test fired and stop_on_stiff was set."""


class NonFiniteSolution(IntegrationError):
    """The solution became NaN or infinite."""


class DivergedSolution(NonFiniteSolution):
    """The solution diverged: the state left the bound that no motion of the system reaches
    (the scene's energy bound with a margin of 1000; see the integrators guide). A subclass of
    `NonFiniteSolution`: such a run would overflow, and is stopped before it does."""


class OutputBufferFull(IntegrationError):
    """Every-step output ran out of rows."""


class NewtonFailure(IntegrationError):
    """An implicit method's Newton iteration did not converge, its matrix was singular, or the
    Jacobian was not finite."""


class UnstableStepWarning(UserWarning):
    """A fixed step beyond the method's linear stability bound (`rk4_stability_bound`), or
    longer than the system's shortest period of oscillation (`shortest_period`): the run may
    chatter, settle on a wrong state, blow up, or (moreau, the implicit methods) damp or skip
    the oscillation."""


class ContactSolverFailure(IntegrationError):
    """The contact solver found no solution of a step's (moreau) or an event's (event_driven)
    friction problem within contact_tol; the message names the time and the contact
    (``result.stats["contact_worst"]``, 0-based there as in the message)."""

    def __init__(self, status: int, result: "Result") -> None:
        super().__init__(status, result)
        worst = int(result.stats.get("contact_worst", -1))
        if worst >= 0:
            self.args = (f"{self.args[0]}; contact {worst} had the largest residual "
                         f"(t = {result.stats['t_reached']:.9g} s)",)


class EventAccumulation(IntegrationError):
    """event_driven: stick/slip events accumulate (Zeno or chatter): 10 instants with events
    in a row closer than zeno_gap, or more events at one instant than 4 n_c + 8."""


class EventBudgetExhausted(IntegrationError):
    """event_driven: more than max_events stick/slip transitions (a budget, not a sign of
    accumulation: raise max_events to go on)."""


_ERRORS: dict[int, type[IntegrationError]] = {
    STATUS_STEP_BUDGET: StepBudgetExhausted,
    STATUS_STEP_TOO_SMALL: StepSizeTooSmall,
    STATUS_STIFF: StiffnessDetected,
    STATUS_NONFINITE: NonFiniteSolution,
    _STATUS["DIVERGED"]: DivergedSolution,
    STATUS_OUTPUT_FULL: OutputBufferFull,
    _STATUS["NEWTON_FAILED"]: NewtonFailure,
    _STATUS["SINGULAR"]: NewtonFailure,
    _STATUS["JAC_NONFINITE"]: NewtonFailure,
    _STATUS["CONTACT_FAILED"]: ContactSolverFailure,
    _STATUS["EVENT_ZENO"]: EventAccumulation,
    _STATUS["EVENT_BUDGET"]: EventBudgetExhausted,
}

#: The dtype of Result.events: time [s], kind ("stick": slip -> stick, "slip": stick -> slip,
#: "reversal": the relative velocity reached 0 and the contact could not be held), position x
#: of the contact's body [m], contact index (0-based).
EVENT_DTYPE = np.dtype([("t", "f8"), ("kind", "U8"), ("x", "f8"), ("contact", "i4")])
_EVENT_KINDS = tuple(sorted(REGISTRY["event"], key=lambda k: REGISTRY["event"][k]["code"]))
#: Events the facade makes room for when max_events is not given (the library's default).
_DEFAULT_MAX_EVENTS = int(REGISTRY["const"]["max_events"]["value"])
#: Most events Result.events holds (32 MB of rows); a run may count more (stats["nevents"]).
_EVENT_ROOM = 1_000_000
#: The events of a run without any (read-only, shared), and the library's empty event buffer.
_NO_EVENTS = np.zeros(0, dtype=EVENT_DTYPE)
_NO_EVENTS.setflags(write=False)
_NO_EVENT_ROWS = np.zeros((4, 0), order="F")


def _events(raw: np.ndarray, count: int) -> np.ndarray:
    """The library's (4, room) event rows as a structured array of EVENT_DTYPE."""
    rows = raw[:, :min(count, raw.shape[1])]
    out = np.zeros(rows.shape[1], dtype=EVENT_DTYPE)
    out["t"], out["x"] = rows[0], rows[2]
    out["kind"] = [_EVENT_KINDS[int(k) - 1] for k in rows[1]]
    out["contact"] = rows[3].astype(np.int32) - 1
    return out


def _unpack(raw: tuple) -> tuple:
    """A Result's raw library output as (istats, rstats, status, cpu, resolved, used): simulate
    keeps the wrapper's one vector of counters and real counters (rstats None) and its setting's
    resolved parameters, the model path its two arrays of counters."""
    if raw[1] is not None:
        return raw
    out, ni = raw[0], len(_STATS_INT)
    return (out[:ni], out[ni:], *raw[2:])


class Result:
    """A simulation on its output grid (returned by `simulate`).

    Attributes
    ----------
    scene, law, method : str
        What was simulated and how.
    t_end : float
        The requested end time [s].
    params : dict of str to float
        Every parameter the scene and the law read, as used (defaults and derived values
        resolved, e.g. v_d = 1.5 v_s).
    t : numpy.ndarray, shape (n_t,)
        Output times [s]: the uniform grid, every accepted step (``every_step=True``), or the
        part of either that was reached when the run ended early.
    x : numpy.ndarray, shape (n_t,)
        Displacement [m].
    v : numpy.ndarray, shape (n_t,)
        Velocity [m/s].
    z : numpy.ndarray
        The law's internal states: shape (n_t,) (like `x`) for a law with one state,
        (n_states, n_t) for several, (0, n_t) for a law without states; named with units in
        `state_labels`.
    state_labels : tuple of str
        Name and unit of each internal state, e.g. ``("z [m]",)``.
    stats : dict
        Counters and outcome of the run; its keys are listed under `simulate` (Returns).
    y : numpy.ndarray, shape (2 + n_states, n_t)
        The whole state (x, v, then the internal states), one row per component.
    events : numpy.ndarray of EVENT_DTYPE
        ``event_driven``'s stick/slip transitions (time, kind, position, contact; at most the
        first 1,000,000, while ``stats["nevents"]`` counts them all); empty for the other
        methods.
    drive_force : numpy.ndarray, shape (n_t, n_drives)
        A model's drives' forces on their bodies [N] (`Model.add_drive`); (n_t, 0) otherwise.

    Notes
    -----
    The arrays of a Result are its own: no later call writes into them. `x`, `v` and `z` are
    rows of one array the library filled (views, not copies).
    """

    __slots__ = ("scene", "law", "method", "t_end", "t", "x", "v", "z", "state_labels",
                 "events", "_drive_force", "_params", "_stats", "_raw")

    def __init__(self, scene: str, law: str, method: str, t_end: float, params: dict[str, float],
                 t: np.ndarray, x: np.ndarray, v: np.ndarray, stats: dict[str, Any] | None = None,
                 z: np.ndarray | None = None, state_labels: tuple[str, ...] = (),
                 events: np.ndarray | None = None) -> None:
        self.scene, self.law, self.method, self.t_end = scene, law, method, t_end
        self.t, self.x, self.v = t, x, v
        self.z = np.zeros((0, np.size(t))) if z is None else z
        self.state_labels = state_labels
        self.events = _NO_EVENTS if events is None else events
        self._drive_force = None
        self._params, self._stats, self._raw = params, ({} if stats is None else stats), None

    @property
    def drive_force(self) -> np.ndarray:
        """A model's drives' forces on their bodies [N], shape (n_t, n_drives); (n_t, 0)
        without drives (made on first use)."""
        if self._drive_force is None:
            self._drive_force = np.zeros((np.size(self.t), 0))
        return self._drive_force

    @drive_force.setter
    def drive_force(self, value: np.ndarray) -> None:
        self._drive_force = value

    @property
    def params(self) -> dict[str, float]:
        """Every parameter the scene and the law read, as used [SI units]."""
        if self._params is None:                  # built on first use (simulate's lean path)
            resolved, used = _unpack(self._raw)[4], self._raw[5]
            values = resolved.tolist()
            self._params = {k: values[i] for k, i in used}
        return self._params

    @property
    def stats(self) -> dict[str, Any]:
        """Counters and outcome of the run (keys: see `simulate`, Returns)."""
        if self._stats is None:                   # built on first use (simulate's lean path)
            istats, rstats, status, cpu = _unpack(self._raw)[:4]
            stats: dict[str, Any] = dict(zip(_STATS_INT, istats.astype(np.int64).tolist()))  # exact: < 2**53
            stats.update(zip(_STATS_REAL, rstats.tolist()))
            stats["stiff"] = bool(stats["stiff"])
            stats["contact_worst"] -= 1           # 0-based, as Result.events; -1: none
            stats["message"] = status_message(status)
            stats["cpu_seconds"] = cpu
            stats["notes"] = []                   # what the run's warnings and checks said
            del stats["n_written"]
            self._stats = stats
        return self._stats

    @property
    def y(self) -> np.ndarray:
        """The whole state (x, v, then the internal states), shape (2 + n_states, n_t)."""
        return np.vstack([self.x, self.v, self.z.reshape(-1, self.t.size)])

    def __getstate__(self) -> dict[str, Any]:
        return {"scene": self.scene, "law": self.law, "method": self.method, "t_end": self.t_end,
                "params": self.params, "t": self.t, "x": self.x, "v": self.v, "stats": self.stats,
                "z": self.z, "state_labels": self.state_labels, "events": self.events,
                "drive_force": self._drive_force}

    def __setstate__(self, state: dict[str, Any]) -> None:
        state = dict(state)
        drive_force = state.pop("drive_force", None)    # absent from a state pickled before
        self.__init__(**state)
        self._drive_force = drive_force

    def __repr__(self) -> str:
        return (f"Result(scene={self.scene!r}, law={self.law!r}, method={self.method!r}, "
                f"t_end={self.t_end!r}, n_t={self.t.size}, message={self.stats['message']!r})")


_KINDS = {"law": LAWS, "scene": SCENES, "method": METHODS}


def _shown(value: Any) -> str:
    """`value` as an error message shows it: numpy scalars and arrays as plain numbers
    (``nan``, ``2.5``, ``[1.0, nan]``), not ``np.float64(nan)``; anything else by repr."""
    if isinstance(value, np.generic):
        value = value.item()
    elif isinstance(value, np.ndarray):
        value = value.tolist()
    return repr(value)


def _choice(name: str, value: Any, accepted: tuple[str, ...]) -> int:
    """The registry code of a law, scene or method name, or ValueError naming `name`."""
    if not isinstance(value, str) or value not in accepted:
        raise ValueError(f"{name}: unknown value {_shown(value)} (accepted: {', '.join(accepted)})")
    return REGISTRY[name][value]["code"]


def _is_real(value: Any) -> bool:
    """A real number given as such (not a string, not a bool)."""
    kind = type(value)
    if kind is float or kind is int:          # the common case, answered without isinstance
        return True
    return isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, (bool, np.bool_))


def _finite(name: str, value: Any, accepted: str) -> float:
    if not _is_real(value):
        raise ValueError(f"{name}: must be a real number ({accepted}), got {_shown(value)}")
    x = float(value)
    if not math.isfinite(x):
        raise ValueError(f"{name}: must be finite ({accepted}), got {_shown(x)}")
    return x


def _end_time(value: Any) -> float:
    """t_end as given: a finite number > 0 [s] (every run starts at t = 0), or ValueError
    with the value given."""
    t_end = _finite("t_end", value, "> 0 [s]: the run starts at t = 0")
    if not t_end > 0.0:
        raise ValueError(f"t_end: must be > 0 [s] (the run starts at t = 0), got t_end = {_show(t_end)}")
    return t_end


def _count(name: str, value: Any, low: int = 1, high: int | None = None) -> int:
    """An integer in [low, high] (not a bool), or ValueError naming the parameter."""
    ok = _is_real(value) and math.isfinite(value) and int(value) == value and value >= low \
        and (high is None or value <= high)
    if not ok:
        bounds = f"in [{low}, {high}]" if high is not None else f">= {low}"
        raise ValueError(f"{name}: must be an integer {bounds}, got {_shown(value)}")
    return int(value)


def _check_names(params: Mapping[str, Any], allowed: tuple[str, ...]) -> None:
    """ValueError naming the parameters that are not in `allowed`."""
    unknown = [k for k in params if k not in allowed]
    if unknown:
        raise ValueError(f"unknown parameter(s) {', '.join(sorted(unknown))} (accepted: {', '.join(allowed)})")


def accepted_range(name: str) -> str:
    """What the library accepts for a physical parameter.

    Parameters
    ----------
    name : str
        A physical parameter of `DEFAULTS`.

    Returns
    -------
    str
        Its rule from the registry, e.g. ``'must be finite and > 0 [m/s]'`` for v_s.
    """
    return _ACCEPTED[name]


_ACCEPTED: dict[str, str] = {n: info["rule"].split(": ", 1)[-1] for n, info in REGISTRY["param"].items()}


def _physical(params: Mapping[str, Any]) -> dict[str, float]:
    """The given physical parameters, names known and values real numbers (None for a
    derived default means "not given"); ranges are checked by the library."""
    _check_names(params, _PARAM_ORDER)
    return {k: _finite(k, v, accepted_range(k))
            for k, v in params.items() if v is not None}


def _keys(d: Mapping[str, Any]) -> tuple[str, np.ndarray]:
    """Names as the comma-separated string the wrapper takes, and their values."""
    return ",".join(d), np.fromiter(d.values(), dtype=np.float64, count=len(d))


def interruptible(call: Callable[[np.ndarray], Any]) -> Any:
    """Run ``call(stop)`` so that Ctrl-C stops it promptly.

    In the main thread the wrapper arms a SIGINT handler for the length of the Fortran call
    (stop[0] = -1 asks for it; _interrupt.c) that sets stop[0] = 1, which the integrators look
    at every 4096 steps (they then end with status INTERRUPTED). Elsewhere (worker threads)
    Python's own handling stays in place.

    Parameters
    ----------
    call : callable
        Makes the library call with the stop flag it is given (an int32 array of one element).

    Returns
    -------
    object
        What `call` returned.

    Raises
    ------
    KeyboardInterrupt
        Once the call has returned, if Ctrl-C was pressed during it.
    """
    stop = np.array([-1 if threading.current_thread() is threading.main_thread() else 0], dtype=np.int32)
    out = call(stop)
    if stop[0] == 1:
        raise KeyboardInterrupt
    return out


#: RK4's stability interval on the negative real axis: |h lambda| < 2.785 (docs/guide/choosing-h.md).
RK4_LIMIT = 2.785293563405282


@functools.lru_cache(maxsize=1024)
def rk4_stability_bound(law: str, params: tuple[tuple[str, float], ...] = (), scene: str = "slope",
                        v0: float = 0.0) -> float | None:
    """RK4's linear stability bound on the step [s] for `law` in `scene`.

    Parameters
    ----------
    law : str
        A friction law of `LAWS`.
    params : tuple of (str, float) pairs
        Physical parameters as for `simulate` (the others at their defaults).
    scene : str
        "slope": the bound 2.785/|lambda| at the creep speed v*, where mu(v*) = tan(theta) and
        lambda = -g cos(theta) mu'(v*), the state the box settles in. "belt": the bound at the
        start (relative velocity w = v_b - v0), from the eigenvalues of the Jacobian
        [[0, 1], [-k/m, -g mu'(w)]]: the largest h with |R(h lambda)| <= 1 for both, where R is
        RK4's amplification factor (2.785/|lambda| for a real lambda, 2.828/|lambda| for an
        imaginary one).
    v0 : float
        Initial velocity [m/s] (belt only).

    Returns
    -------
    float or None
        The bound [s]; None where no linear bound exists: mu jumps at that velocity (Coulomb's
        at rest), the linearised motion grows by itself (mu falling with the relative speed),
        the box slides on the slope without creeping, or the law has internal states (their
        Jacobian is not derived here).
    """
    if REGISTRY["law"][law]["n_states"] > 0:
        return None
    d = dict(params)

    def value(name: str) -> float:
        return float(d.get(name, REGISTRY["param"][name]["default"]))

    p = {k: v for k, v in params if k in REGISTRY["law"][law]["params"]}
    if scene == "belt":
        w = value("v_b") - v0
        dv = 1e-6 * max(abs(w), value("v_s"))
        m = friction_coefficient(law, [w - dv, w + dv, w - 0.1 * dv, w + 0.1 * dv], **p)
        wide, narrow = m[1] - m[0], m[3] - m[2]
        if abs(wide) > 1e-12 and abs(wide) < 3.0 * abs(narrow):
            return None                 # the difference does not shrink with dv: a jump or an unbounded slope
        jac = np.array([[0.0, 1.0], [-value("k") / value("m"), -value("g") * wide / (2.0 * dv)]])
        bounds = [_rk4_ray_bound(complex(lam)) for lam in np.linalg.eigvals(jac) if lam != 0.0]
        return None if not bounds or None in bounds else min(bounds)
    theta = math.radians(value("theta_deg"))
    g = value("g")
    target = math.tan(theta)
    v_s = value("v_s")
    if not (0.0 < target and g > 0.0):
        return None
    grid = np.concatenate([[0.0], np.geomspace(1e-8, 1e2, 400) * v_s])
    mu = friction_coefficient(law, grid, **p)
    above = np.flatnonzero(mu >= target)
    if above.size == 0 or above[0] == 0:
        return None
    lo, hi = grid[above[0] - 1], grid[above[0]]
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if friction_coefficient(law, mid, **p) >= target else (mid, hi)
    dv = 1e-6 * hi
    m_lo, m_hi = friction_coefficient(law, [hi - dv, hi + dv], **p)
    if m_hi - m_lo > 1e-6:          # a jump across tan(theta): no linear bound
        return None
    lam = g * math.cos(theta) * (m_hi - m_lo) / (2.0 * dv)
    return RK4_LIMIT / lam if lam > 0.0 else None


def _rk4_ray_bound(lam: complex) -> float | None:
    """The largest h with |R(s lam)| <= 1 for every s in (0, h], R(z) = 1 + z + z^2/2 + z^3/6
    + z^4/24 (RK4's amplification factor); None when |R| > 1 already for small h (Re lam > 0)."""
    def grows(h: float) -> bool:
        z = h * lam
        return abs(1.0 + z * (1.0 + z * (0.5 + z * (1.0 / 6.0 + z / 24.0)))) > 1.0 + 1e-12
    scale = 1.0 / abs(lam)
    steps = np.linspace(0.0, 4.0, 4001)[1:] * scale        # RK4's region lies within |z| < 3
    first = next((h for h in steps if grows(h)), None)
    if first is None:
        return None
    if first == steps[0]:
        return None
    lo, hi = first - steps[0], first
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if not grows(mid) else (lo, mid)
    return lo


def _fixed_steps(t_end: float, h: float) -> float:
    """Steps a fixed-step method takes from 0 to t_end (inf when uncountable; 0 for bad input,
    which the library rejects by name)."""
    if not (h > 0.0 and t_end > 0.0):
        return 0.0
    q = t_end / h * (1.0 - 1e-12)
    return float(math.ceil(q)) if math.isfinite(q) else math.inf


def friction_coefficient(law: str, v: Any, **params: float) -> np.ndarray:
    """Friction coefficient mu(v) [-] of `law` at relative velocities v [m/s].

    Parameters
    ----------
    law : str
        A friction law of `LAWS`.
    v : float or array_like
        Relative sliding velocities [m/s], finite.
    **params : float
        Parameters of the law (``REGISTRY["law"][law]["params"]``; defaults in `DEFAULTS`); any
        parameter of another law or of a scene is range-checked too.

    Returns
    -------
    numpy.ndarray
        mu(v) [-], of the shape of `v`; for a law with internal states, its steady-state curve.

    Raises
    ------
    ValueError
        An unknown law or parameter, a value out of its range (the message names it, its range
        and the values), a non-finite v, or a mu that overflows.

    Examples
    --------
    >>> import stickslip as ss
    >>> ss.friction_coefficient("coulomb", [-1.0, 1.0]).tolist()
    [-0.3, 0.3]
    """
    code = _choice("law", law, LAWS)
    given = _physical(params)
    try:
        vv = np.asarray(v, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"v: must be real numbers [m/s], got {v!r}") from None
    if not np.isfinite(vv).all():
        raise ValueError("v: must be finite [m/s]")
    keys, vals = _keys(given)
    mu, status = _ext.friction(code, keys, vals, np.ascontiguousarray(vv.ravel()))
    _check_code(status, given)
    mu = np.asarray(mu).reshape(vv.shape)
    if not np.isfinite(mu).all():
        bad = vv.reshape(-1)[int(np.flatnonzero(~np.isfinite(mu.reshape(-1)))[0])]
        raise ValueError(f"v: mu({bad!r}) overflows with these parameters (a viscous term times a huge "
                         "velocity); use velocities and parameters whose product stays finite")
    return mu


@dataclass(frozen=True)
class _Plan:
    """What simulate reads from the registry for one (scene, law, method): worked out once
    (_plan), so that a call only looks it up."""

    codes: tuple[int, int, int]             # scene, law, method
    n: int                                  # state components: x, v and the law's internal states
    reads: frozenset[str]                   # the controls the method reads
    defaults: Mapping[str, float]           # CONTROL_DEFAULTS of those, flags as 0/1, in that order
    adaptive: bool
    needs_h: bool
    used: tuple[tuple[str, int], ...]       # parameters the scene and law read: (name, registry index)
    state_labels: tuple[str, ...]
    sized_by: tuple[str, ...] = ()          # the law's parameters that set its number of states


#: Parameters that set a law's number of internal states (the generalized Maxwell-slip model's
#: n_elements): for such a law simulate asks the library (_states).
STATE_COUNT_PARAMS: tuple[str, ...] = ("n_elements",)


_PLANS: dict[tuple[str, str, str], _Plan] = {}


def _plan(scene: Any, law: Any, method: Any) -> _Plan:
    """The plan of a scene, law and method, or ValueError naming the first unknown one."""
    try:
        plan = _PLANS.get((scene, law, method))
    except TypeError:                       # an unhashable "name": _choice says what is accepted
        plan = None
    if plan is None:
        codes = (_choice("scene", scene, SCENES), _choice("law", law, LAWS), _choice("method", method, METHODS))
        info = REGISTRY["method"][method]
        used = set(REGISTRY["law"][law]["params"]) | set(REGISTRY["scene"][scene]["params"])
        plan = _Plan(
            codes=codes, n=2 + REGISTRY["law"][law]["n_states"], reads=frozenset(info["controls"]),
            defaults={k: _flag(v) for k, v in CONTROL_DEFAULTS.items() if k in info["controls"]},
            adaptive=info["adaptive"], needs_h="h" in info["controls"],
            used=tuple((k, i) for i, k in enumerate(_PARAM_ORDER) if k in used),
            state_labels=REGISTRY["law"][law]["states"],
            sized_by=tuple(k for k in STATE_COUNT_PARAMS if k in REGISTRY["law"][law]["params"]))
        _PLANS[scene, law, method] = plan   # only names that passed _choice get here
    return plan


def _flag(value: Any) -> Any:
    """A flag (bool) as the 0.0/1.0 the library reads; anything else unchanged."""
    return float(bool(value)) if isinstance(value, (bool, np.bool_)) else value


def _controls(method: str, plan: _Plan, given: dict[str, Any]) -> dict[str, Any]:
    """The controls of `method`: those given (each must be one the method reads) over the
    facade's defaults of those it reads. Flags become 0/1."""
    out = dict(plan.defaults)
    for name, value in given.items():
        if name not in plan.reads:
            raise ValueError(f"{name}: not a control of method {method!r} "
                             f"(its controls: {', '.join(REGISTRY['method'][method]['controls'])})")
        out[name] = _flag(value)
    return out


def _tolerance(name: str, value: Any, n: int) -> np.ndarray:
    """rtol or atol as float64: a real number or n of them (one per state component)."""
    if _is_real(value):
        return np.array([value], dtype=np.float64)
    items = np.atleast_1d(np.asarray(value, dtype=object))
    if items.ndim != 1 or items.size not in (1, n) or not all(_is_real(x) for x in items):
        raise ValueError(f"{name}: must be a real number or {n} of them (one per state component), "
                         f"got {_shown(value)}")
    return items.astype(np.float64)


#: Output grids up to this many points are kept with their setting (_Call): numpy.linspace
#: costs microseconds.
_GRID_CACHE_ROWS = 4096


def _linspace(t_end: float, n_out: int) -> np.ndarray:
    """The output grid numpy.linspace(0, t_end, n_out) (just t_end for one point)."""
    return np.linspace(0.0, t_end, n_out) if n_out > 1 else np.array([t_end])


_PARAM_SET = frozenset(_PARAM_ORDER)
_CONTROL_SET = frozenset(CONTROLS)
_STATS_INT: tuple[str, ...] = REGISTRY["stats_int"]
_STATS_REAL: tuple[str, ...] = REGISTRY["stats_real"]
_I_WRITTEN = _STATS_INT.index("n_written")
_I_NEVENTS = _STATS_INT.index("nevents")
#: The sizes run_simulation checks against the registry: counters, reals, parameters.
_SIZES = (len(_STATS_INT), len(_STATS_REAL), len(_PARAM_ORDER))
#: The size of run_prepared's counters: the integer ones, then the real ones.
_N_COUNTERS = len(_STATS_INT) + len(_STATS_REAL)


class UnusedParameterWarning(UserWarning):
    """A physical parameter was given that the scene and the law do not read (it is
    range-checked, then ignored)."""


def _show(value: Any) -> str:
    """A value for an error message: 0.35, 1e-06, [1e-06, 0.99]."""
    if isinstance(value, np.ndarray):
        return _show(float(value[0])) if value.size == 1 else "[" + ", ".join(_show(float(x)) for x in value) + "]"
    return f"{value:g}" if isinstance(value, float) else repr(value)


def _known(given: Mapping[str, float]) -> dict[str, float]:
    """Every physical parameter as the library resolves it: given, else its default (a derived
    one, v_d, from its registry rule)."""
    known = {k: v for k, v in DEFAULTS.items() if v is not None} | dict(given)
    for k, info in REGISTRY["param"].items():
        if k not in given and info["default_of"]:
            known[k] = info["scale"] * known[info["default_of"]]
    return known


@functools.lru_cache(maxsize=1024)
def _states(law: str, params: tuple[tuple[str, float], ...]) -> tuple[int, tuple[str, ...]]:
    """The number of internal states of `law` and their labels, for the given (name, value)
    parameters (a law such as gms has as many as its n_elements), as the library reports them."""
    code = _choice("law", law, LAWS)
    keys, vals = _keys(dict(params))
    nz, labels, status = _ext.law_states(code, keys, vals)
    _check_code(int(status), dict(params))
    text = labels.decode().rstrip("\x00 ")
    return int(nz), tuple(s for s in text.split(";") if s)


#: Most bodies whose natural frequencies are computed exactly (one dense symmetric eigenvalue
#: problem, about 10 ms at 200 bodies); a larger system takes Gershgorin's bound.
_EXACT_PERIOD_BODIES = 200


@dataclass(frozen=True)
class _Oscillators:
    """A system (a scene with its parameters, or a Model) as the checks of a fixed step see it:
    its bodies' masses [kg], its springs as rows (a, b, k [N/m]) with b = -1 the ground, and,
    where it is a box on a slope (one body, no spring, constant forces), the law and the
    parameters of RK4's creep bound (`rk4_stability_bound`), else None."""

    masses: np.ndarray
    springs: np.ndarray
    slope: tuple[str, tuple[tuple[str, float], ...]] | None = None


def _scene_oscillators(scene: str, law: str, given: Mapping[str, Any]) -> _Oscillators:
    """A scene's bodies and springs, read from the model its preset builds in the library (the
    one `Model.from_scene` returns: `preset_arrays`), seen as `_model_oscillators` sees a
    Model's. A bad parameter: ValueError naming it."""
    mass, springs, _dampers, forces, contacts = preset_arrays(scene, law, given)
    rows = np.column_stack([springs[0] - 1.0, springs[1] - 1.0, springs[2]]) if springs.size else np.zeros((0, 3))
    one_contact = contacts.shape[1] == 1 and not springs.size and not _dampers.size
    law_params = {k: v for k, v in given.items() if k in REGISTRY["law"][law]["params"]}
    slope = _slope(law, law_params, mass, forces[1].tolist(),
                   (bool(contacts[1, 0] == 0.0), float(contacts[2, 0]), float(contacts[3, 0])) if one_contact else None)
    return _Oscillators(mass, rows, slope)


def preset_arrays(scene: str, law: str, given: Mapping[str, Any]) -> tuple[np.ndarray, ...]:
    """The model of `scene` with `law` as its preset builds it (stickslip_presets, per unit
    mass): (mass (nb,) [kg], springs (4, ns) = (a, b, k, rest length), dampers (3, nd), forces
    (2, nf) = (body, force [N]), contacts (4, nc) = (a, b, normal force [N], surface velocity
    [m/s])), body indices from 1, 0 the ground. ValueError naming a bad parameter."""
    pkeys, pvals = _keys(given)
    codes = _choice("scene", scene, SCENES), _choice("law", law, LAWS)
    sizes, status = _ext.preset_sizes(*codes, pkeys, pvals)
    if status == STATUS_OK:
        *arrays, status = _ext.preset_arrays(*codes, pkeys, pvals, *sizes)
    _check_code(int(status), given)
    return tuple(arrays)


def _constant(signal: Any) -> float | None:
    """The value of a constant signal (stickslip.signal), else None."""
    return float(signal.args[0]) if signal.kind == "constant" else None


def _slope(law: str, params: Mapping[str, Any], masses: np.ndarray, forces: list[float | None],
           contact: tuple[bool, float | None, float | None] | None) -> tuple[str, tuple[tuple[str, float], ...]] | None:
    """RK4's creep-bound setting (`rk4_stability_bound`) of a box on a slope: one body, no
    spring or damper (the caller checks), constant forces F and one contact (ground on side b,
    normal force N, surface velocity) with the still ground under N > 0: theta = atan(F / N),
    g = |(F, N)| / m; else None."""
    if len(masses) != 1 or contact is None:
        return None
    ground_b, normal, surface = contact
    if ground_b and surface == 0.0 and normal is not None and normal > 0.0 and None not in forces:
        f = math.fsum(forces)
        return (law, tuple(sorted({**params, "theta_deg": math.degrees(math.atan2(f, normal)),
                                   "g": math.hypot(f, normal) / masses[0]}.items())))
    return None


def _model_oscillators(model: Any) -> _Oscillators:
    """A Model's bodies and springs, and its slope setting (`_slope`) where it is a box on a
    slope, as `Model.from_scene("slope", ...)` builds it."""
    masses = np.array([b.mass for b in model.bodies], dtype=np.float64)
    springs = np.array([(a, -1 if b is None else b, k) for a, b, k, *_ in model.springs],
                       dtype=np.float64).reshape(-1, 3)
    contact = None
    if not model.springs and not model.dampers and len(model.contacts) == 1:
        c = model.contacts[0]
        contact = (c.b is None, _constant(c.normal_force),
                   0.0 if c.surface_velocity is None else _constant(c.surface_velocity))
    law = "+".join(dict.fromkeys(c.law for c in model.contacts))
    params = model.contacts[0].params if len(model.contacts) == 1 else {}
    return _Oscillators(masses, springs, _slope(law, params, masses, [_constant(s) for _, s in model.forces], contact))


@functools.lru_cache(maxsize=256)
def _period_of(masses: bytes, springs: bytes) -> tuple[float, bool] | None:
    """(the shortest period of free oscillation [s], exact) of bodies of `masses` (float64
    bytes) on `springs` (rows a, b, k; b = -1 the ground): 2 pi / sqrt of the largest
    eigenvalue of K x = w^2 M x, exactly up to _EXACT_PERIOD_BODIES bodies, else from
    Gershgorin's bound on it (exact False: the period is at least that). None without a spring.
    Dampers are left out (the undamped frequencies), and so are the contacts: sticking a
    contact constrains the motion to a subspace, where the largest w^2 (a maximum of the
    Rayleigh quotient) can only be lower, so the free system has the shortest period."""
    m = np.frombuffer(masses)
    s = np.frombuffer(springs).reshape(-1, 3)
    s = s[s[:, 2] > 0.0]
    if not s.size or not m.size:
        return None
    a, b, k = s[:, 0].astype(np.intp), s[:, 1].astype(np.intp), s[:, 2]
    inv = 1.0 / np.sqrt(m)
    pair = b >= 0
    if m.size <= _EXACT_PERIOD_BODIES:
        stiff = np.zeros((m.size, m.size))
        np.add.at(stiff, (a, a), k)
        ab, kb = (a[pair], b[pair]), k[pair]
        np.add.at(stiff, (ab[1], ab[1]), kb)
        np.add.at(stiff, ab, -kb)
        np.add.at(stiff, ab[::-1], -kb)
        lam, exact = float(np.linalg.eigvalsh(inv[:, None] * stiff * inv[None, :])[-1]), True
    else:
        row = np.zeros(m.size)
        np.add.at(row, a, k * inv[a] ** 2)
        ap, bp, kp = a[pair], b[pair], k[pair]
        np.add.at(row, bp, kp * inv[bp] ** 2)
        np.add.at(row, ap, kp * inv[ap] * inv[bp])
        np.add.at(row, bp, kp * inv[ap] * inv[bp])
        lam, exact = float(row.max()), False
    return (2.0 * math.pi / math.sqrt(lam), exact) if lam > 0.0 else None


def _system_period(system: _Oscillators) -> tuple[float, bool] | None:
    """`_period_of` the system, computed once per distinct set of masses and springs."""
    return _period_of(np.ascontiguousarray(system.masses, dtype=np.float64).tobytes(),
                      np.ascontiguousarray(system.springs, dtype=np.float64).tobytes())


def shortest_period(system: Any, law: str = "coulomb", **params: Any) -> float | None:
    """The shortest period of free oscillation of a system [s], from its springs and masses.

    Parameters
    ----------
    system : str or Model
        A scene of `SCENES` (with its physical parameters in `params`, the others at their
        defaults) or a `Model`.
    law : str
        The scene's friction law (it does not change the period).
    **params : float
        The scene's physical parameters (n_blocks on the chain); others are ignored.

    Returns
    -------
    float or None
        2 pi / w_max, w_max^2 the largest eigenvalue of K x = w^2 M x (exact up to 200 bodies,
        Gershgorin's lower bound on the period beyond); None without a spring (the slope).
        Simulate warns where a fixed step h is longer (UnstableStepWarning).
    """
    if isinstance(system, str):
        _choice("scene", system, SCENES)
        given = {k: v for k, v in params.items() if k in _PARAM_SET}
        osc = _scene_oscillators(system, law, given)
    else:
        osc = _model_oscillators(system)
    found = _system_period(osc)
    return None if found is None else found[0]


def _step_warnings(system: _Oscillators, method: str, h: float, t_end: float) -> list[tuple[str, type[Warning]]]:
    """The warnings of a fixed step h [s] on `system` until t_end [s], the same for a scene and
    a Model: h longer than the run, longer than the system's shortest period of oscillation, or
    (RK4 on a box on a slope) beyond RK4's stability bound at the creep speed."""
    said: list[tuple[str, type[Warning]]] = []
    if h > t_end > 0.0:
        said.append((f"h = {h:g} s is longer than the whole run (t_end = {t_end:g} s): one step, "
                     "shortened to t_end; the result is that single step (docs/guide/choosing-h.md)", UserWarning))
    found = _system_period(system)
    if found is not None and h > found[0]:
        period, exact = found
        how = ("2 pi / the largest natural frequency of its springs and masses" if exact else
               "at least: Gershgorin's bound on the largest natural frequency of its springs and masses")
        said.append((f"h = {h:g} s is longer than the system's shortest period of oscillation {period:.3g} s "
                     f"({how}): {method} cannot follow the oscillation; take h below a tenth of it "
                     "(docs/guide/choosing-h.md)", UnstableStepWarning))
    if method == "rk4" and system.slope is not None and h > 0.0:
        law, params = system.slope
        bound = rk4_stability_bound(law, params)
        if bound is not None and h > bound:
            said.append((f"h = {h:g} s is beyond RK4's stability bound 2.785/|lambda| = {bound:.3g} s "
                         f"at the creep speed of {law!r} on this slope: RK4 may chatter or settle on a "
                         "wrong creep speed (docs/guide/choosing-h.md)", UnstableStepWarning))
    return said


def _warn_model_steps(model: Any, method: Any, t_end: Any, controls: Mapping[str, Any],
                      stacklevel: int = 3) -> list[tuple[str, type[Warning]]]:
    """Issue `_step_warnings` for a Model run with a fixed-step method, as simulate issues them
    for a scene (before the run, after the law's notes as for a scene; input that is not a
    positive finite h and t_end is left to the model's own validation). stacklevel: that of
    the warnings, counted from this function. Returns them (message, category), in order."""
    info = REGISTRY["method"].get(method) if isinstance(method, str) else None
    if info is None or "h" not in info["controls"]:
        return []
    try:
        h, t = float(controls.get("h")), float(t_end)
    except (TypeError, ValueError):
        return []
    if not (math.isfinite(h) and math.isfinite(t) and h > 0.0 and t > 0.0):
        return []
    said = _step_warnings(_model_oscillators(model), method, h, t)
    for message, category in said:
        warnings.warn(message, category, stacklevel=stacklevel)
    return said


def _check_code(status: int, given: Mapping[str, Any] | None = None) -> None:
    """Raise ValueError for a bad-input status: the library's message, which names the parameter
    and its accepted range, with the values of the parameters it names (`given` over the
    defaults)."""
    if status <= _FIRST_INPUT_CODE:
        raise ValueError(_with_values(status_message(status), _known(given or {})))


def _with_values(message: str, known: Mapping[str, Any]) -> str:
    """A library message about bad input, with the values of the parameters it names: the
    one(s) before the colon and those it compares with, e.g. 'mu_k: must be finite and >= 0
    and <= mu_s (got mu_k = 0.5, mu_s = 0.35)'."""
    # the facade's runs start at t0 = 0, a name its users never set: its messages say t_end
    message = message.replace("t_end - t0", "t_end").replace("[t0, t_end]", "[0, t_end]").replace("> t0", "> 0")
    head, sep, rule = message.partition(":")
    if not sep:
        return message
    names = [n.strip() for n in head.split(",")] + re.findall(r"[<>]=?\s*([A-Za-z_]\w*)", rule)
    shown = [f"{n} = {_show(known[n])}" for n in dict.fromkeys(names) if n in known]
    return f"{message} (got {', '.join(shown)})" if shown else message


class RegularisedLawWarning(UserWarning):
    """``coulomb``, or ``stribeck`` with mu_s > mu_k, under a method without stick/slip events:
    the run computes the regularised law (its band), not the set-valued one (`regularised_note`)."""


#: The laws with a static level above the kinetic one that the set-valued methods solve exactly.
_SET_VALUED = ("coulomb", "stribeck")


def regularised_note(law: str, params: Mapping[str, float], method: str) -> str | None:
    """What a run of `law` under `method` computes when the method has no stick/slip events and
    the law's stick is a regularisation: ``coulomb``, or ``stribeck`` with mu_s > mu_k, under
    any method but ``event_driven`` and ``moreau`` (None for any other law and method). The
    sentence of the warning (`RegularisedLawWarning`) and of ``Result.stats["notes"]``.

    Parameters
    ----------
    law : str
        A friction law of `LAWS`.
    params : mapping
        Its parameters as used (mu_s, mu_k, v_s, v_eps; defaults where not given).
    method : str
        A method of `METHODS`.
    """
    if law not in _SET_VALUED or REGISTRY["method"][method]["laws"] is not None:
        return None
    p = _known(params)
    if law == "stribeck" and not p["mu_s"] > p["mu_k"]:
        return None
    exact = "event_driven or moreau give the set-valued answer (exact stick at v = 0, docs/guide/exact-stick.md)"
    if law == "coulomb" and method in _MODAL_METHODS:
        return (f"coulomb under {method}: the paper's Coulomb law with its band, mu = mu_s = {p['mu_s']:g} for "
                f"0 < |v| < v_s = {p['v_s']:g} m/s and mu_k = {p['mu_k']:g} beyond, solved over its modes "
                "(stick at v = 0 is exact): a slip slower than v_s meets mu_s instead of mu_k, which "
                f"shifts a stick-slip cycle by O(v_s); {exact}")
    if law == "coulomb":
        cost = ("its steps are forced at h_min at every crossing of v = 0 (tens of millions of evaluations "
                "for seconds of stick) and the body creeps" if REGISTRY["method"][method]["adaptive"] else
                "the velocity chatters across 0 by about |a| h a step, and the body creeps or stays with x "
                "and v inconsistent")
        return (f"coulomb under {method}: the paper's discontinuous Coulomb law (mu = 0 at v = 0 exactly, "
                f"mu_s = {p['mu_s']:g} for 0 < |v| < v_s = {p['v_s']:g} m/s, mu_k = {p['mu_k']:g} beyond), not "
                f"stick: near rest {cost}; " + exact)
    return (f"stribeck under {method}: the regularised curve mu(v) tanh(v/v_eps), v_eps = {p['v_eps']:g} m/s, "
            f"not stick: below break-away (mu_s = {p['mu_s']:g}) the body creeps at about v_eps "
            "atanh(mu_hold/mu_s), and the steps must resolve the band (cost growing as 1/v_eps); " + exact)


#: implicit_euler and galpha solve the laws with jumps over their modes on a model and on
#: one contact (stickslip_modal_contacts, stickslip_fixed_implicit).
_MODAL_METHODS = ("implicit_euler", "galpha")


def model_notes(model: Any, method: str, stacklevel: int = 2) -> list[str]:
    """`regularised_note` for each contact of a `stickslip.Model` under `method` (one per law and
    parameter set, prefixed with the first contact that has it), each warned once
    (RegularisedLawWarning); the list of them, for ``Result.stats["notes"]``."""
    notes: dict[str, str] = {}
    for i, c in enumerate(model.contacts):
        note = regularised_note(c.law, c.params, method)
        if note is not None and note not in notes:
            notes[note] = f"{model.contact_label(i)}: {note}"
    for message in notes.values():
        warnings.warn(message, RegularisedLawWarning, stacklevel=stacklevel + 1)
    return list(notes.values())


def _checked(law: str, method: str) -> bool:
    """Whether runs of `law` under `method` take simulate's Python path for the consistency
    check (`_after_run`): the laws that jump or stick in a band (those with a set-valued
    counterpart, which the registry gives event_driven: coulomb, stribeck, karnopp) under the
    methods without stick/slip events, whose output can leave x and v inconsistent (RK4's
    frozen states). The others keep the fast path, unchecked."""
    return law in REGISTRY["method"]["event_driven"]["laws"] and REGISTRY["method"][method]["laws"] is None


#: The consistency check of a result, `stickslip.energy.check_result`: energy, which imports
#: this module, sets it as it is imported (the package imports it).
_CHECK_RESULT: Callable[..., list[str]] | None = None


def _after_run(call: "_Call", result: Result) -> None:
    """A run of `call` that reached t_end, on simulate's Python path: its warnings into
    ``result.stats["notes"]`` (all but UnusedParameterWarning), then the consistency check
    (`stickslip.energy.check_result`), whose failures are warned and noted there too."""
    result.stats["notes"].extend(m for m, c in call.warnings if not issubclass(c, UnusedParameterWarning))
    if _CHECK_RESULT is not None and _checked(call.law, call.method):
        _CHECK_RESULT(result, call.method, call.known, stacklevel=3)


class _Call:
    """One distinct setting of `simulate`, validated once (_prepare): the library's handle of
    the setting it built (prepare_run: the scene, its law and the method's options, run by
    run_prepared on a copy, so that threads may run one setting at once), its size `n` and
    resolved parameters, and what its Result needs (a Model's: `n_drives`, the rows of its
    drives' forces); `fast` when _runner's fast path may run it without Python (no warnings
    to repeat; a kept grid or output every step). Never changed
    after _prepare; the handle is released with the _Call (never copied: a copy would release
    it twice)."""

    __slots__ = ("scene", "law", "method", "t_end", "grid", "n_out", "rows", "warnings",
                 "n_states", "state_labels", "used", "known", "events_room", "n_blocks", "arm",
                 "handle", "n", "resolved", "fast", "model", "n_drives")

    def __init__(self, **kw: Any) -> None:
        for k, v in kw.items():
            setattr(self, k, v)

    def __del__(self, _free: Callable[[int], None] = _ext.free_prepared) -> None:
        handle = getattr(self, "handle", 0)
        if handle:
            self.handle = 0
            _free(handle)

    def __reduce__(self) -> Any:
        raise TypeError("a _Call holds a library handle: it cannot be copied or pickled")


#: Settings simulate has validated (keyed on its arguments and their types), at most
#: _CALLS_MAX; cleared when full. Only settings the library accepted are kept.
_CALLS: dict[tuple, _Call] = {}
_CALLS_MAX = 512


def _keep(key: tuple, call: _Call) -> None:
    """Keep a validated setting in _CALLS (a scene's or a Model's), clearing it when full."""
    if len(_CALLS) >= _CALLS_MAX:
        _CALLS.clear()
    _CALLS[key] = call


#: Most output values (state components x rows) a run may fill: 2 GB of float64.
_MAX_OUTPUT_VALUES = 250_000_000
#: Most state components for an implicit method told to factor dense n x n matrices
#: (banded=False): 4000 components are 256 MB for RADAU5's complex matrix.
_MAX_DENSE_STATES = 4000


#: Most blocks of the chain (the library's MAX_BLOCKS in stickslip_presets).
_MAX_BLOCKS = int(REGISTRY["const"]["max_blocks"]["value"])


def _n_blocks(given: Mapping[str, float], method: str, n_per_block: int, dense: bool) -> int:
    """The chain's number of blocks (parameter n_blocks), checked: an integer in range, and
    small enough when the method is told to factor dense matrices (banded=False)."""
    nb = given.get("n_blocks", DEFAULTS["n_blocks"])
    if not (float(nb).is_integer() and 1 <= nb <= _MAX_BLOCKS):
        raise ValueError(f"n_blocks: must be an integer in [1, {_MAX_BLOCKS}], got {_shown(nb)}")
    if dense and nb * n_per_block > _MAX_DENSE_STATES:
        raise ValueError(f"n_blocks: {method} with banded=False factors dense matrices of the whole state, "
                         f"at most {_MAX_DENSE_STATES} components ({_MAX_DENSE_STATES // n_per_block} blocks "
                         f"with this law), got {int(nb)} blocks; leave banded on")
    return int(nb)


def _chain_state(n_blocks: int, nz: int, x0: Any, v0: Any, z0: Any, law: str) -> np.ndarray:
    """The chain's initial state (x_1..x_N, v_1..v_N, z block by block): x0 and v0 are one
    value for every block or N values, z0 None (0), nz values for every block or N nz values."""
    def per_block(name: str, value: Any, size: int, unit: str) -> np.ndarray:
        a = np.atleast_1d(np.asarray(value, dtype=np.float64))
        if a.ndim != 1 or a.size not in (1, size) or not np.isfinite(a).all():
            raise ValueError(f"{name}: must be one finite value or {size} of them (one per block) {unit}, "
                             f"got an array of shape {a.shape}")
        return np.broadcast_to(a, (size,)) if a.size == 1 else a

    y0 = np.zeros(n_blocks * (2 + nz))
    y0[:n_blocks] = per_block("x0", x0, n_blocks, "[m]")
    y0[n_blocks:2 * n_blocks] = per_block("v0", v0, n_blocks, "[m/s]")
    if z0 is not None:
        z = np.atleast_1d(np.asarray(z0, dtype=np.float64))
        if z.ndim != 1 or z.size not in (nz, nz * n_blocks) or not np.isfinite(z).all():
            raise ValueError(f"z0: must be {nz} finite value(s) (every block) or {nz * n_blocks} (block by "
                             f"block), the initial internal states of {law!r}")
        y0[2 * n_blocks:] = np.tile(z, n_blocks) if z.size == nz else z
    return y0


def simulate(scene: Any, law: str | None = None, *, method: str, t_end: float, n_out: int | None = None,
             every_step: bool = False, max_steps: int | None = None, x0: Any = 0.0,
             v0: Any = None, z0: Any = None, ignore_unused: bool = False, **kwargs: Any) -> Result:
    """Simulate `scene` with friction `law` (or a `Model`) from t = 0 to `t_end` with `method`.

    Parameters
    ----------
    scene : str or Model
        What is simulated, one of `SCENES`: "slope" (a box on a plane inclined theta_deg, x
        down the slope), "belt" (a mass m on a belt moving at v_b, tied to a wall by a
        spring k) or "chain" (n_blocks such blocks on the belt, block i tied to block i - 1 by
        k_c; docs/guide/chain.md); or your own system, a `Model` (docs/guide/models.md), which
        carries its laws, parameters and initial state: then only `method`, `t_end`, `n_out`,
        `every_step`, `max_steps` and the method's controls are given, and the Result's `x`
        and `v` have shape (n_bodies, n_t) and its `events` name the contact.
    law : str
        The friction law, one of `LAWS` (parameters and defaults: `REGISTRY["law"][law]`,
        `DEFAULTS`); not with a Model.
    method : str
        The integrator, one of `METHODS`; the controls it reads are
        `REGISTRY["method"][method]["controls"]`.
    t_end : float
        End time [s], > 0.
    n_out : int, optional
        Points of the uniform output grid on [0, t_end] (default 1001); not with `every_step`.
    every_step : bool, optional
        Output every accepted step instead of a grid (default False).
    max_steps : int, optional
        Budget of attempted steps (default 10**8; 10**6 for an adaptive method with
        `every_step`). A fixed-step run that needs more is refused before it starts.
    x0, v0 : float or sequence of float, optional
        Initial displacement [m] (default 0) and velocity [m/s] (default 0; v_b on the chain:
        every block stuck on the belt). On the chain either is one value for every block or
        n_blocks values.
    z0 : float or sequence of float, optional
        Initial internal states of the law (default all 0), one per state; on the chain the
        law's states for every block or block by block.
    ignore_unused : bool, optional
        False (default): a physical parameter that the scene and the law do not read is
        range-checked, then ignored with an `UnusedParameterWarning`. True: ignored silently
        (for one parameter set shared across laws and scenes).
    **kwargs : float
        Physical parameters (names in `DEFAULTS`, SI units; each value given is range-checked
        whatever the scene and law) and controls of the method (every control, its default and
        meaning: docs/guide/controls.md). The fixed-step methods ("rk4", "implicit_euler",
        "galpha") need ``h`` [s]. The adaptive ones ("dopri5", "dop853", "radau5") take ``rtol`` (default
        1e-6; DOPRI5 accepts 0, a purely absolute error test, RADAU5 needs rtol >= 2.2e-14),
        ``atol`` (1e-9; either may be one value or one per state component), ``hmin`` (1e-6 s:
        where the error test fails at hmin the step is taken anyway and counted in
        ``stats["nforced"]``; ``allow_forced=False`` raises StepSizeTooSmall instead),
        ``hmax`` (0: the whole interval, so that only the error test limits the step; the
        paper's drivers pass 1e-2 s), ``h0`` (0: automatic) and their own.
        A control the method does not read is an error.
        The set-valued (exact-stick) methods take the laws "coulomb" and "stribeck" only:
        "moreau" (Moreau-Jean time-stepping; ``h``, ``theta`` = 0.5, ``contact_tol``,
        ``contact_max_iter``) and "event_driven" (stick/slip switching with DOPRI5 in each
        mode; ``rtol``, ``atol``, ``max_events``, ``zeno_gap``), whose transitions are in
        ``Result.events`` (docs/guide/exact-stick.md).

    Returns
    -------
    Result
        The output: ``t`` [s], ``x`` [m], ``v`` [m/s] of shape (n_t,) (on the chain with
        n_blocks > 1: (n_blocks, n_t), and ``z`` (n_blocks n_states, n_t), block by block);
        ``z``, the internal states, of shape (n_t,) for a law with one state and
        (n_states, n_t) for several;
        ``y`` (2 + n_states, n_t); ``params`` (every parameter the scene and law read, as
        used); ``state_labels``; and ``stats``, a dict with the keys:

        - ``nfev``: right-hand-side evaluations (Hairer's NFCN; finite-difference Jacobians
          included).
        - ``nstep``: attempted steps (NSTEP).
        - ``naccept``: accepted steps, forced ones included (NACCPT).
        - ``nreject``: rejected steps after the first accepted one (NREJCT).
        - ``nforced``: steps taken at hmin although the error test failed there.
        - ``nstiff``: DOPRI5's stiffness tests with h |lambda| > 3.25.
        - ``stiff``: True once 15 such tests came in a row (the problem is probably stiff).
        - ``njac``, ``ndec``, ``nsol``: Jacobian evaluations, LU decompositions and
          forward-backward substitutions of the implicit methods (NJAC, NDEC, NSOL).
        - ``nevents``: stick/slip transitions of event_driven (``Result.events`` holds them;
          0 for the other methods).
        - ``ncontact_iter``: work of moreau's contact solver, summed over the steps (sweeps of
          the chain's Gauss-Seidel, or linear solves of the coupled solver).
        - ``nonunique``: the steps (moreau, implicit_euler, galpha) or mode decisions
          (event_driven) whose contact problem had another solution (moreau, event_driven: one
          with as many stuck contacts; event_driven also a mode consistent to first order only,
          a slip from the limit at zero relative acceleration, where a mode with fewer stuck
          contacts is consistent strictly; implicit_euler, galpha: another consistent mode of a
          contact's law); the contact solver's rule chose one, and a RuntimeWarning names the
          count and the first one's time.
        - ``t_nonunique``: the time of the first of them [s] (0 where ``nonunique`` is 0).
        - ``contact_residual``: the largest residual of moreau's contact solve [m/s], measured
          on each step's friction problem (its complementarity conditions).
        - ``contact_worst``: the contact (0-based) whose friction problem had no solution
          (ContactSolverFailure), else -1.
        - ``status``: the library's status code (0: t_end reached).
        - ``message``: the library's message for that status.
        - ``t_reached``: the time the run reached [s] (t_end on success).
        - ``h_last``: the last step size tried [s].
        - ``notes``: a list of sentences (str) about the run: its warnings (the law it computes
          under this method, RegularisedLawWarning; a step beyond a stability bound) and the
          failures of its consistency check (ConsistencyWarning, EnergyBoundWarning; see
          docs/guide/results.md); empty for a run that needed none.
        - ``cpu_seconds``: CPU time of the library call [s]: the process's CPU clock (that of
          time.process_time), read by the compiled wrapper before and after the run; for a
          fixed-step run of fewer than 2048 steps the monotonic clock (time.perf_counter's)
          instead, since two reads of the CPU clock are system calls that cost more than such
          a run (the two agree unless the thread waited for a core during the call).

        All values of a returned Result are finite.

    Raises
    ------
    ValueError
        Bad input, before anything runs: an unknown name, a non-number, a value out of its
        range (the message names the parameter, its accepted range and the values given), a
        control the method does not read, a fixed-step run needing more than max_steps steps.
    IntegrationError
        The run ended before t_end; one of its subclasses StepBudgetExhausted,
        StepSizeTooSmall, StiffnessDetected, NonFiniteSolution (and its subclass
        DivergedSolution: the state left the scene's energy bound), OutputBufferFull,
        NewtonFailure, ContactSolverFailure (moreau, event_driven), EventAccumulation and
        EventBudgetExhausted (event_driven). Its ``result`` holds the output up to
        ``stats["t_reached"]`` and its
        ``status`` the library's code.
    KeyboardInterrupt
        Ctrl-C during the run (the integrators look at a stop flag every 4096 steps).

    Warns
    -----
    UnusedParameterWarning
        A physical parameter the scene and the law do not read (unless ignore_unused).
    UnstableStepWarning
        A fixed step h longer than the system's shortest period of oscillation
        (`shortest_period`: from its springs and masses), or RK4 with h beyond its stability
        bound at the creep speed on the slope (`rk4_stability_bound`).
    UserWarning
        A fixed step h longer than the whole run.
    RegularisedLawWarning
        ``coulomb``, or ``stribeck`` with mu_s > mu_k, under a method without stick/slip events:
        what the run computes instead of the set-valued law (`regularised_note`).
    ConsistencyWarning, EnergyBoundWarning
        A run that reached t_end but fails the consistency check (x against the integral of
        v; on a model its energy and its friction forces too): the numbers are in the message
        and in ``stats["notes"]`` (docs/guide/results.md).

    The checks of a fixed step are the same for a scene and a `Model` (a model from
    `Model.from_scene` warns as its scene).

    Examples
    --------
    >>> import stickslip as ss
    >>> r = ss.simulate("belt", "proposed", method="dopri5", t_end=20.0, rtol=1e-6, atol=1e-6)
    >>> r.x.shape, r.stats["status"], r.stats["nfev"]
    ((1001,), 0, 2822)
    >>> ss.simulate("slope", "lugre", method="radau5", t_end=1.0, n_out=11).z.shape
    (11,)
    >>> r = ss.simulate("belt", "recurdyn", method="rk4", h=1e-3, t_end=0.01, n_out=2)
    >>> r.stats["nstep"]
    10
    """
    # a stickslip.Model (which runs itself: no import cycle); a name, the common case, is no Model
    if type(scene) is not str and hasattr(scene, "run_model"):
        extra = [k for k, v in (("law", law), ("x0", x0 if x0 != 0.0 else None), ("v0", v0), ("z0", z0))
                 if v is not None] + [k for k in kwargs if k in _PARAM_SET]
        if extra:
            raise ValueError(f"{', '.join(extra)}: a Model carries its own laws, parameters and initial "
                             "state (give them to add_body and add_contact)")
        result = scene.run_model(method=method, t_end=t_end, n_out=n_out, every_step=every_step,
                                 max_steps=max_steps, **kwargs)
        _warn_nonunique(result)
        return result
    # Reached when _runner's fast path (the FastPath standing for this function, below) has not
    # finished the call: a new setting, one with warnings to repeat or a grid too long to keep,
    # a Model, or bad arguments. A setting seen before (equal arguments of equal types) is not
    # validated again.
    key, call = _lookup(_CALLS, kwargs, scene, law, method, t_end, n_out, every_step, max_steps, x0, v0, z0,
                        ignore_unused)
    if call is not None:
        key = None                           # kept already
        for message, category in call.warnings:
            warnings.warn(message, category, stacklevel=2)
    else:
        call = _prepare(scene, law, method, t_end, n_out, every_step, max_steps, x0, v0, z0, ignore_unused,
                        kwargs)
        if key is not None and any(isinstance(v, tuple) for v in (x0, v0, z0, *kwargs.values())):
            key = None                       # tuples may hide bools: validated each time
    result = _run(call)
    status = result._raw[2]
    if status == STATUS_OK:
        _warn_nonunique(result)
    if key is not None and status > _FIRST_INPUT_CODE:     # new, and the library named no bad input
        _keep(key, call)
    if status != STATUS_OK:
        _failed(call, result)
    if not call.fast:
        _after_run(call, result)
    return result


def _warn_nonunique(result: Result) -> None:
    """One RuntimeWarning for a run in which some contact problem had another solution
    (``stats["nonunique"]`` counts them; the contact solver's rule chose one)."""
    count = int(result.stats.get("nonunique", 0))
    if count:
        what = {"moreau": "with as many stuck contacts",
                "event_driven": "(as many stuck contacts, or a mode consistent to first order only "
                                "where one with fewer holds strictly)"}.get(
            result.method, "(another consistent mode of a contact's law)")
        warnings.warn(f"{count} contact problem(s) of this {result.method} run had another solution {what}, "
                      f"the first at t = {result.stats['t_nonunique']:.6g} s; the solver's rule chose one "
                      "(stats['nonunique'], stats['t_nonunique']; see the exact-stick guide, 'When a step "
                      "has several solutions')", RuntimeWarning, stacklevel=3)


def _failed(call: _Call, result: Result) -> NoReturn:
    """Raise for a run of `call` that did not reach t_end (`_raise_failure`)."""
    _raise_failure(result, call.known)


def _raise_failure(result: Result, known: Mapping[str, Any]) -> NoReturn:
    """Raise for a run that did not reach t_end, a scene's or a Model's: ValueError for a bad
    input the library named (with the values of `known` it names), else the IntegrationError
    of its status, holding `result` (the motion up to where it stopped)."""
    status = result._raw[2]
    if status <= _FIRST_INPUT_CODE:
        raise ValueError(_with_values(status_message(status), known))
    raise _ERRORS.get(status, IntegrationError)(status, result)


def _run(call: _Call) -> Result:
    """One run of a validated setting (its Result, whatever its status) by _runner: on the grid
    its _Call keeps or with room for every step, else on a new grid; a long run on the main
    thread arms the SIGINT handler (a Ctrl-C raises KeyboardInterrupt once it returns)."""
    return _execute(call, None if call.grid is not None or call.rows else _linspace(call.t_end, call.n_out))


def _prepare(scene: Any, law: Any, method: Any, t_end: Any, n_out: Any, every_step: Any, max_steps: Any,
             x0: Any, v0: Any, z0: Any, ignore_unused: bool, kwargs: Mapping[str, Any]) -> _Call:
    """Validate one setting of simulate (ValueError naming the parameter and its range) and
    issue its warnings; the _Call holds the arguments of its Fortran call."""
    plan = _plan(scene, law, method)
    unknown = kwargs.keys() - _PARAM_SET - _CONTROL_SET
    if unknown:
        raise ValueError(f"unknown parameter(s) {', '.join(sorted(unknown))} (physical parameters: "
                         f"{', '.join(_PARAM_ORDER)}; controls: {', '.join(CONTROLS)})")
    given = _physical({k: v for k, v in kwargs.items() if k in _PARAM_SET})
    ctl = _controls(method, plan, {k: v for k, v in kwargs.items() if k in _CONTROL_SET})
    t_end = _end_time(t_end)
    n_states, state_labels = plan.n - 2, plan.state_labels
    if plan.sized_by:                        # a law whose number of states is a parameter (gms)
        n_states, state_labels = _states(law, tuple((k, given[k]) for k in plan.sized_by if k in given))
    n = 2 + n_states
    n_blocks = 1
    if scene == "chain":
        n_blocks = _n_blocks(given, method, n, "banded" in plan.reads and not ctl.get("banded", 1.0))
        n *= n_blocks
    # 1.0: a placeholder the fixed-step methods never read
    rtol = _tolerance("rtol", ctl.pop("rtol", 1.0), n)
    atol = _tolerance("atol", ctl.pop("atol", 1.0), n)
    for name, value in ctl.items():
        ctl[name] = _finite(name, value, "see simulate()")
    said: list[tuple[str, type[Warning]]] = []

    def warn(message: str, category: type[Warning] = UserWarning) -> None:
        warnings.warn(message, category, stacklevel=4)      # the caller of simulate
        said.append((message, category))

    used = {k for k, _ in plan.used}
    unused = [k for k in given if k not in used]
    if unused and not ignore_unused:
        warn(f"{', '.join(unused)}: not read by scene {scene!r} with law {law!r}, ignored (range-checked "
             "only; ignore_unused=True silences this for parameter sets shared across laws)",
             UnusedParameterWarning)
    note = regularised_note(law, _known(given), method)
    if note is not None:
        warn(note, RegularisedLawWarning)
    if plan.needs_h:
        if "h" not in ctl:
            raise ValueError(f"h: required for method {method!r} (finite, > 0 [s])")
        for message, category in _step_warnings(_scene_oscillators(scene, law, given), method,
                                                ctl["h"], t_end):
            warn(message, category)
    if scene == "chain":
        if v0 is None:   # every block stuck on the belt
            v0 = given.get("v_b", DEFAULTS["v_b"])
        y0 = _chain_state(n_blocks, n_states, x0, v0, z0, law)
    else:
        x0 = _finite("x0", x0, "[m]")
        v0 = _finite("v0", 0.0 if v0 is None else v0, "[m/s]")
        if z0 is None:
            y0 = np.zeros(n)
            y0[0], y0[1] = x0, v0
        else:
            z = np.atleast_1d(np.asarray(z0, dtype=np.float64))
            if z.shape != (n_states,) or not np.isfinite(z).all():
                raise ValueError(f"z0: must be {n_states} finite value(s), the initial internal states of {law!r}")
            y0 = np.concatenate([np.array([x0, v0]), z])

    if max_steps is None:
        max_steps = 10**6 if (every_step and plan.adaptive) else 10**8
    max_steps = _count("max_steps", max_steps)
    needed = _fixed_steps(t_end, ctl["h"]) if not plan.adaptive else 0.0
    if needed > max_steps:
        raise ValueError(f"max_steps: {method} with h = {ctl['h']:g} s needs {needed:.4g} steps to reach "
                         f"t_end = {t_end:g} s, more than max_steps = {max_steps} (raise max_steps or h)")
    ctl["max_steps"] = float(max_steps)

    grid, rows = None, 0
    if every_step:
        if n_out is not None:
            raise ValueError("n_out: give either n_out or every_step, not both")
        rows = max_steps
        if needed > 0.0:
            rows = min(rows, int(needed))
        rows = max(rows, 1) + 1
        if rows > MAX_ROWS:
            raise ValueError(f"max_steps: every_step would allocate {rows} rows (limit {MAX_ROWS}); "
                             "lower max_steps or use n_out")
        ctl["every_step"] = 1.0
    else:
        n_out = _count("n_out", 1001 if n_out is None else n_out, 1, MAX_ROWS)
        if n_out <= _GRID_CACHE_ROWS:
            grid = _linspace(t_end, n_out)
            grid.setflags(write=False)       # copied for each call (simulate)

    n_rows = rows if every_step else n_out
    if scene == "chain" and n * n_rows > _MAX_OUTPUT_VALUES:
        raise ValueError(f"n_blocks: {n_blocks} blocks ({n} state components) on {n_rows} output rows "
                         f"need {8 * n * n_rows / 1e9:.3g} GB of output (limit "
                         f"{8 * _MAX_OUTPUT_VALUES / 1e9:.3g} GB); lower n_blocks or n_out")
    pkeys, pvals = _keys(given)
    ckeys, cvals = _keys(ctl)
    # the wrapper's one string of names and one array of values (run_simulation in _wrap.f90)
    vals = np.concatenate((pvals, y0, rtol, atol, cvals))
    known = {**_known(given), **CONTROL_DEFAULTS, **ctl, "rtol": rtol, "atol": atol, "t_end": t_end}
    # room for event_driven's events (max_events of them, range-checked by the library)
    room = int(min(max(ctl.get("max_events", _DEFAULT_MAX_EVENTS), 0), _EVENT_ROOM)) \
        if "max_events" in plan.reads else 0
    args = (*plan.codes, f"{pkeys}|{ckeys}", vals, pvals.size, y0.size, rtol.size, atol.size, t_end)
    # the library builds the setting once (its scene, law and the method's options); a bad
    # input it names is raised here, before anything runs
    resolved, handle, status = _ext.prepare_run(*args, len(_PARAM_ORDER))
    arm = plan.adaptive or needed >= _STOP_CHECK_STEPS // 2
    if status != STATUS_OK:
        raise ValueError(_with_values(status_message(status), known))
    return _Call(scene=scene, law=law, method=method, t_end=t_end, handle=int(handle), n=y0.size,
                 resolved=resolved, grid=grid, n_out=n_out, rows=rows, warnings=tuple(said), n_states=n_states,
                 state_labels=state_labels, used=plan.used, known=known, events_room=room,
                 n_blocks=n_blocks, arm=arm, model=False, n_drives=0,
                 fast=not said and (rows > 0 or grid is not None) and not _checked(law, method))


#: The integrators look at the stop flag as a run starts, then every 4096 steps
#: (stickslip_ode's STOP_CHECK_MASK + 1): a fixed-step run of fewer steps never looks again,
#: and the facade does not arm a SIGINT handler for it (two system calls saved per call; a
#: Ctrl-C during such a run is Python's own, raised as KeyboardInterrupt once the call returns).
#: Runs of half as many steps or more, and every adaptive run, are armed. The same line decides
#: how the wrapper times the call (stats["cpu_seconds"]): a long run with the CPU clock, a
#: short one with the monotonic clock (two reads of the CPU clock are system calls costing more
#: than such a run: about 2 us each on a virtual machine).
_STOP_CHECK_STEPS = 4096
#: What simulate's call path looks up on every call, bound once.
_lookup, _execute = _runner.lookup, _runner.execute
_runner.setup(_ext.run_prepared._cpointer, Result, _Call, _NO_EVENTS, _NO_EVENT_ROWS, _events, _N_COUNTERS,
              _I_WRITTEN, _I_NEVENTS)


# simulate as called: _runner's FastPath runs a setting kept in _CALLS that needs nothing of
# Python in C (binding the arguments, the key, the library call, the Result); any other call
# goes on, unchanged, to the function above (its name, docstring and signature are this one's).
# (A plain comment: Sphinx would take a "#:" comment for simulate's documentation.)
simulate = functools.update_wrapper(_runner.FastPath(simulate, _CALLS, _failed), simulate)


def _set_main_thread() -> None:
    """Tell _runner which thread is the main one (its long runs arm the SIGINT handler)."""
    _runner.set_main_thread(threading.main_thread().ident)


_set_main_thread()
os.register_at_fork(after_in_child=_set_main_thread)


def bare_call(scene: str, law: str, **kwargs: Any) -> Callable[[], Any]:
    """The library call that ``simulate(scene, law, **kwargs)`` makes (run_prepared on the
    setting's handle), through f2py's wrapper of it, as a function that makes it with the same
    arguments and does nothing else (the benchmarks' overhead table: simulate reaches the same
    routine through its pointer, _runner). Main thread only (it arms the SIGINT handler when
    simulate does)."""
    call = _prepare(scene, law, kwargs.pop("method"), kwargs.pop("t_end"), kwargs.pop("n_out", None),
                    kwargs.pop("every_step", False), kwargs.pop("max_steps", None), kwargs.pop("x0", 0.0),
                    kwargs.pop("v0", None), kwargs.pop("z0", None), kwargs.pop("ignore_unused", False), kwargs)
    t_grid = np.zeros(call.rows) if call.rows else _linspace(call.t_end, call.n_out)
    stop = np.zeros(1, dtype=np.int32)
    flag = memoryview(stop)
    run, handle, n = _ext.run_prepared, call.handle, call.n
    events = np.zeros((4, call.events_room), order="F")

    arm = -1 if call.arm else 0

    def bare(_owner: _Call = call) -> Any:            # _owner: the handle lives as long as bare
        flag[0] = arm
        return run(handle, t_grid, n, _N_COUNTERS, stop, events)
    return bare
