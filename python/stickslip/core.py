"""The Python facade over the Fortran core: validate names and numbers, call the
compiled wrapper once per simulation, and turn status codes into exceptions.

Units are SI throughout: m, s, kg, m/s; angles in degrees.
"""
from __future__ import annotations

import functools
import math
import threading
import time
import warnings
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any, Callable, Mapping

import numpy as np

from . import _stickslip as _ext



def _read_registry() -> dict[str, Any]:
    """The core's registry (stickslip_registry::registry_text): laws, scenes, methods,
    parameters, counters and status codes, one '|'-separated record per line."""
    text = _ext.registry().decode().rstrip("\x00 \n")
    reg: dict[str, Any] = {"law": {}, "scene": {}, "method": {}, "param": {}, "status": {}}
    for line in text.splitlines():
        kind, *f = line.split("|")
        if kind == "law":
            reg["law"][f[1]] = {"code": int(f[0]), "params": tuple(f[2].split()), "n_states": int(f[3]),
                                "states": tuple(x for x in f[4].split(";") if x), "doc": f[5]}
        elif kind == "scene":
            reg["scene"][f[1]] = {"code": int(f[0]), "params": tuple(f[2].split()), "doc": f[3]}
        elif kind == "method":
            reg["method"][f[1]] = {"code": int(f[0]), "order": int(f[2]), "adaptive": f[3] == "1",
                                   "implicit": f[4] == "1", "controls": tuple(f[5].split()), "doc": f[6]}
        elif kind == "param":
            reg["param"][f[0]] = {"code": int(f[1]), "default": float(f[2]), "unit": f[3],
                                  "default_of": f[4] or None, "scale": float(f[5]), "rule": f[6],
                                  "doc": f[7]}
        elif kind == "stats":
            reg["stats_int"], reg["stats_real"] = tuple(f[0].split()), tuple(f[1].split())
        elif kind == "status":
            reg["status"][f[0]] = int(f[1])
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

#: The facade's defaults of the shared controls (the paper's "automatic" step range
#: [hmin, hmax] = [1e-6, 1e-2] s); each is passed only to the methods that read it. Read-only:
#: simulate reads them once per method (_plan).
CONTROL_DEFAULTS: Mapping[str, Any] = MappingProxyType(
    {"rtol": 1e-6, "atol": 1e-9, "hmin": 1e-6, "hmax": 1e-2, "h0": 0.0, "allow_forced": True,
     "stop_on_stiff": False})

#: Largest every-step output the facade allocates [rows]: 3 arrays of 8-byte floats.
MAX_ROWS = 50_000_000


@functools.lru_cache(maxsize=256)
def status_message(status: int) -> str:
    """The library's message for a status code (a constant per code: read once)."""
    return _ext.message(status).decode().strip()


class IntegrationError(RuntimeError):
    """An integration that ended before t_end. `result` holds the output up to
    `result.stats["t_reached"]`, `status` the library's code."""

    def __init__(self, status: int, result: "Result") -> None:
        self.status = status
        self.result = result
        super().__init__(
            f"{status_message(status)} (status {status}; reached t = {result.stats['t_reached']:.6g} s "
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


class OutputBufferFull(IntegrationError):
    """Every-step output ran out of rows."""


class NewtonFailure(IntegrationError):
    """An implicit method's Newton iteration did not converge, its matrix was singular, or the
    Jacobian was not finite."""


_ERRORS: dict[int, type[IntegrationError]] = {
    STATUS_STEP_BUDGET: StepBudgetExhausted,
    STATUS_STEP_TOO_SMALL: StepSizeTooSmall,
    STATUS_STIFF: StiffnessDetected,
    STATUS_NONFINITE: NonFiniteSolution,
    STATUS_OUTPUT_FULL: OutputBufferFull,
    _STATUS["NEWTON_FAILED"]: NewtonFailure,
    _STATUS["SINGULAR"]: NewtonFailure,
    _STATUS["JAC_NONFINITE"]: NewtonFailure,
}


@dataclass
class Result:
    """A simulation on its output grid: time t [s], displacement x [m], velocity v [m/s],
    and the law's internal states z (shape (n_states, len(t)), named in `state_labels`
    with units; empty for a law without states)."""

    scene: str
    law: str
    method: str
    t_end: float
    params: dict[str, float]
    t: np.ndarray
    x: np.ndarray
    v: np.ndarray
    stats: dict[str, Any] = field(default_factory=dict)
    z: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    state_labels: tuple[str, ...] = ()

    @property
    def y(self) -> np.ndarray:
        """The whole state (x, v, z...) as an array of shape (2 + n_states, len(t))."""
        return np.vstack([self.x, self.v, self.z.reshape(-1, self.t.size)])


_KINDS = {"law": LAWS, "scene": SCENES, "method": METHODS}


def _choice(name: str, value: Any, accepted: tuple[str, ...]) -> int:
    """The registry code of a law, scene or method name, or ValueError naming `name`."""
    if not isinstance(value, str) or value not in accepted:
        raise ValueError(f"{name}: unknown value {value!r} (accepted: {', '.join(accepted)})")
    return REGISTRY[name][value]["code"]


def _is_real(value: Any) -> bool:
    """A real number given as such (not a string, not a bool)."""
    kind = type(value)
    if kind is float or kind is int:          # the common case, answered without isinstance
        return True
    return isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, (bool, np.bool_))


def _finite(name: str, value: Any, accepted: str) -> float:
    if not _is_real(value):
        raise ValueError(f"{name}: must be a real number ({accepted}), got {value!r}")
    x = float(value)
    if not math.isfinite(x):
        raise ValueError(f"{name}: must be finite ({accepted}), got {x!r}")
    return x


def _count(name: str, value: Any, low: int = 1, high: int | None = None) -> int:
    """An integer in [low, high] (not a bool), or ValueError naming the parameter."""
    ok = _is_real(value) and math.isfinite(value) and int(value) == value and value >= low \
        and (high is None or value <= high)
    if not ok:
        bounds = f"in [{low}, {high}]" if high is not None else f">= {low}"
        raise ValueError(f"{name}: must be an integer {bounds}, got {value!r}")
    return int(value)


def _check_names(params: Mapping[str, Any], allowed: tuple[str, ...]) -> None:
    """ValueError naming the parameters that are not in `allowed`."""
    unknown = [k for k in params if k not in allowed]
    if unknown:
        raise ValueError(f"unknown parameter(s) {', '.join(sorted(unknown))} (accepted: {', '.join(allowed)})")


def _check_code(status: int) -> None:
    """Raise ValueError for a bad-input status: the message names the parameter and range."""
    if status <= _FIRST_INPUT_CODE:
        raise ValueError(status_message(status))


def accepted_range(name: str) -> str:
    """What the registry accepts for parameter `name`, e.g. 'must be finite and > 0 [m/s]'."""
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
    """Run call(stop) so that Ctrl-C stops it promptly. In the main thread the wrapper arms a
    SIGINT handler for the length of the Fortran call (stop[0] = -1 asks for it; _interrupt.c)
    that sets stop[0] = 1, which the integrators look at every 4096 steps (they then end with
    status INTERRUPTED); KeyboardInterrupt is raised once the call has returned. Elsewhere
    (worker threads) Python's own handling stays in place."""
    stop = np.array([-1 if threading.current_thread() is threading.main_thread() else 0], dtype=np.int32)
    out = call(stop)
    if stop[0] == 1:
        raise KeyboardInterrupt
    return out


#: RK4's stability interval on the negative real axis: |h lambda| < 2.785 (README).
RK4_LIMIT = 2.785293563405282


@functools.lru_cache(maxsize=256)
def rk4_stability_bound(law: str, params: tuple[tuple[str, float], ...] = ()) -> float | None:
    """RK4's stability bound 2.785/|lambda| [s] for the box on the slope creeping at v*, where
    mu(v*) = tan(theta) and lambda = -g cos(theta) mu'(v*) (README, "How to choose h"); None
    where no such bound exists (the box slides, or mu jumps across tan(theta) as Coulomb's does,
    or the law has internal states). `params` are (name, value) pairs as for simulate."""
    if REGISTRY["law"][law]["n_states"] > 0:
        return None
    p = {k: v for k, v in params if k in REGISTRY["law"][law]["params"]}
    theta = math.radians(dict(params).get("theta_deg", REGISTRY["param"]["theta_deg"]["default"]))
    g = dict(params).get("g", REGISTRY["param"]["g"]["default"])
    target = math.tan(theta)
    v_s = float(dict(params).get("v_s", REGISTRY["param"]["v_s"]["default"]))
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


def _fixed_steps(t_end: float, h: float) -> float:
    """Steps a fixed-step method takes from 0 to t_end (inf when uncountable; 0 for bad input,
    which the library rejects by name)."""
    if not (h > 0.0 and t_end > 0.0):
        return 0.0
    q = t_end / h * (1.0 - 1e-12)
    return float(math.ceil(q)) if math.isfinite(q) else math.inf


def friction_coefficient(law: str, v: Any, **params: float) -> np.ndarray:
    """Friction coefficient mu(v) [-] of `law` at relative velocities v [m/s] (scalar or array);
    for a law with internal states, its steady-state curve.

    Parameters: those of REGISTRY["law"][law]["params"] (defaults in DEFAULTS); any parameter of
    another law or scene is range-checked too.
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
    _check_code(int(status))
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
#: n_elements): for such a law simulate asks the library (prescribed._states).
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
                         f"got {value!r}")
    return items.astype(np.float64)


#: Output grids up to this many points are kept (_grid): numpy.linspace costs microseconds.
_GRID_CACHE_ROWS = 4096


def _linspace(t_end: float, n_out: int) -> np.ndarray:
    """The output grid numpy.linspace(0, t_end, n_out) (just t_end for one point)."""
    return np.linspace(0.0, t_end, n_out) if n_out > 1 else np.array([t_end])


@functools.lru_cache(maxsize=32)
def _cached_linspace(t_end: float, n_out: int) -> np.ndarray:
    grid = _linspace(t_end, n_out)
    grid.setflags(write=False)
    return grid


def _grid(t_end: float, n_out: int) -> np.ndarray:
    """A new array holding the output grid _linspace(t_end, n_out); small ones are copied
    from a cache."""
    return _cached_linspace(t_end, n_out).copy() if n_out <= _GRID_CACHE_ROWS else _linspace(t_end, n_out)


_PARAM_SET = frozenset(_PARAM_ORDER)
_CONTROL_SET = frozenset(CONTROLS)
_STATS_INT: tuple[str, ...] = REGISTRY["stats_int"]
_STATS_REAL: tuple[str, ...] = REGISTRY["stats_real"]


def simulate(scene: str, law: str, *, method: str, t_end: float, n_out: int | None = None,
             every_step: bool = False, max_steps: int | None = None, x0: float = 0.0,
             v0: float = 0.0, z0: Any = None, **kwargs: Any) -> Result:
    """Simulate `scene` (SCENES: "slope", "belt") with friction `law` (LAWS) from
    (x0 [m], v0 [m/s], z0 = the law's internal states, default 0) at t = 0 to t_end [s] with
    `method` (METHODS).

    Keyword arguments are physical parameters (DEFAULTS; each given value is range-checked
    whatever the scene and law) or controls of the method (REGISTRY["method"][method]
    ["controls"]): the fixed-step methods ("rk4", "implicit_euler", "galpha") need h [s]; the
    adaptive ones ("dopri5", "radau5") take rtol (1e-6), atol (1e-9; scalars or one per state
    component), hmin (1e-6 s), hmax (1e-2 s), h0 (0 = automatic), allow_forced and their own
    (README, "Python"; after a forced step the step is held for calm_steps = 2 steps, then
    grows by at most fac_forced = 2 a step).
    A control the method does not read is an error.

    Output: a uniform grid of n_out points on [0, t_end] (default 1001), or every step when
    every_step is set. max_steps bounds attempted steps (default 10**8; 10**6 for an adaptive
    method with every_step). When DOPRI5's error test fails at hmin the step is taken anyway and
    counted in stats["nforced"]; allow_forced=False raises StepSizeTooSmall instead.

    Raises ValueError for bad input (naming the parameter and its accepted range) and an
    IntegrationError subclass when the run ends early (its `.result` holds the partial output).
    Every value of a result returned is finite: an overflow of the state, or of the dense output
    or interpolant between steps, ends the run with NonFiniteSolution.
    """
    plan = _plan(scene, law, method)
    unknown = kwargs.keys() - _PARAM_SET - _CONTROL_SET
    if unknown:
        raise ValueError(f"unknown parameter(s) {', '.join(sorted(unknown))} (physical parameters: "
                         f"{', '.join(_PARAM_ORDER)}; controls: {', '.join(CONTROLS)})")
    given = _physical({k: v for k, v in kwargs.items() if k in _PARAM_SET})
    ctl = _controls(method, plan, {k: v for k, v in kwargs.items() if k in _CONTROL_SET})
    t_end = _finite("t_end", t_end, "> 0 [s]")
    n, state_labels = plan.n, plan.state_labels
    if plan.sized_by:
        from .prescribed import _states     # (prescribed imports this module)
        nz, state_labels = _states(law, tuple((k, given[k]) for k in plan.sized_by if k in given))
        n = 2 + nz
    # 1.0: a placeholder the fixed-step methods never read
    rtol = _tolerance("rtol", ctl.pop("rtol", 1.0), n)
    atol = _tolerance("atol", ctl.pop("atol", 1.0), n)
    for name, value in ctl.items():
        ctl[name] = _finite(name, value, "see simulate()")
    if plan.needs_h:
        if "h" not in ctl:
            raise ValueError(f"h: required for method {method!r} (finite, > 0 [s])")
        h = ctl["h"]
        if h > t_end > 0.0:
            warnings.warn(f"h = {h:g} s is longer than the whole run (t_end = {t_end:g} s): one step, "
                          "shortened to t_end; the result is that single step (README: How to choose h)",
                          stacklevel=2)
        if method == "rk4" and scene == "slope" and h > 0.0:
            bound = rk4_stability_bound(law, tuple(sorted(given.items())))
            if bound is not None and h > bound:
                warnings.warn(f"h = {h:g} s is beyond RK4's stability bound 2.785/|lambda| = {bound:.3g} s "
                              f"at the creep speed of {law!r} on this slope: RK4 may chatter or settle on a "
                              "wrong creep speed (README: How to choose h)", stacklevel=2)
    x0 = _finite("x0", x0, "[m]")
    v0 = _finite("v0", v0, "[m/s]")
    if z0 is None:
        y0 = np.zeros(n)
        y0[0], y0[1] = x0, v0
    else:
        z = np.atleast_1d(np.asarray(z0, dtype=np.float64))
        if z.shape != (n - 2,) or not np.isfinite(z).all():
            raise ValueError(f"z0: must be {n - 2} finite value(s), the initial internal states of {law!r}")
        y0 = np.concatenate([np.array([x0, v0]), z])

    if max_steps is None:
        max_steps = 10**6 if (every_step and plan.adaptive) else 10**8
    max_steps = _count("max_steps", max_steps)
    needed = _fixed_steps(t_end, ctl["h"]) if not plan.adaptive else 0.0
    if needed > max_steps:
        raise ValueError(f"max_steps: {method} with h = {ctl['h']:g} s needs {needed:.4g} steps to reach "
                         f"t_end = {t_end:g} s, more than max_steps = {max_steps} (raise max_steps or h)")
    ctl["max_steps"] = float(max_steps)

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
        t_grid = np.zeros(rows)
        ctl["every_step"] = 1.0
    else:
        n_out = _count("n_out", 1001 if n_out is None else n_out, 1, MAX_ROWS)
        t_grid = _grid(t_end, n_out)

    pkeys, pvals = _keys(given)
    ckeys, cvals = _keys(ctl)
    scene_code, law_code, method_code = plan.codes
    cpu0 = time.process_time()
    y, istats, rstats, resolved, status = interruptible(lambda stop: _ext.run_simulation(
        scene_code, law_code, method_code, pkeys, pvals, y0, t_end, rtol, atol, ckeys, cvals,
        t_grid, len(_STATS_INT), len(_STATS_REAL), len(_PARAM_ORDER), stop))
    cpu = time.process_time() - cpu0
    status = int(status)
    _check_code(status)

    stats: dict[str, Any] = dict(zip(_STATS_INT, istats.astype(np.int64).tolist()))   # exact: < 2**53
    stats.update(zip(_STATS_REAL, rstats.tolist()))
    stats["stiff"] = bool(stats["stiff"])
    stats["message"] = status_message(status)
    stats["cpu_seconds"] = cpu
    rows_written = stats.pop("n_written")
    resolved = resolved.tolist()
    params = {k: resolved[i] for k, i in plan.used}
    y = y[:, :rows_written]
    result = Result(scene=scene, law=law, method=method, t_end=t_end, params=params,
                    t=t_grid if rows_written == t_grid.size else t_grid[:rows_written].copy(),
                    x=np.array(y[0]), v=np.array(y[1]), stats=stats, z=np.array(y[2:]),
                    state_labels=state_labels)
    if status != STATUS_OK:
        raise _ERRORS.get(status, IntegrationError)(status, result)
    return result
