"""The Python facade over the Fortran core: validate names and numbers, call the
compiled wrapper once per simulation, and turn status codes into exceptions.

Units are SI throughout: m, s, kg, m/s; angles in degrees.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Any, Mapping

import numpy as np

from . import _stickslip as _ext

LAWS: tuple[str, ...] = ("coulomb", "recurdyn", "proposed")
SCENES: tuple[str, ...] = ("slope", "belt")
METHODS: tuple[str, ...] = ("rk4", "dopri5")

_CODES: dict[str, int] = dict(zip(LAWS + SCENES + METHODS, (int(c) for c in _ext.codes())))

#: The paper's parameters (Table 1) and our defaults where it is silent.
#: v_d = None means 1.5 v_s (RecurDyn's threshold ratio).
DEFAULTS: dict[str, float | None] = {
    "mu_s": 0.35,        # static coefficient [-]
    "mu_k": 0.30,        # kinetic coefficient [-]
    "v_s": 0.01,         # static threshold velocity [m/s]
    "v_d": None,         # dynamic threshold velocity of the recurdyn law [m/s]
    "beta": 1.0 / 3.0,   # exponent of the proposed law [-]
    "a": 1.5,            # base of the proposed law [-]
    "m": 10.0,           # mass (belt) [kg]
    "g": 9.81,           # gravity [m/s^2]
    "theta_deg": 10.0,   # slope inclination [deg]
    "k": 300.0,          # spring stiffness (belt) [N/m]
    "v_b": 1.5,          # belt speed [m/s]
}
LAW_PARAMS: tuple[str, ...] = ("mu_s", "mu_k", "v_s", "v_d", "beta", "a")
_PARAM_ORDER: tuple[str, ...] = LAW_PARAMS + ("m", "g", "theta_deg", "k", "v_b")

#: Status codes of the library (stickslip_kinds.f90).
STATUS_OK = 0
STATUS_STEP_BUDGET = -2
STATUS_STEP_TOO_SMALL = -3
STATUS_STIFF = -4
STATUS_NONFINITE = -5
STATUS_OUTPUT_FULL = -6
_FIRST_INPUT_CODE = -100          # codes <= this name one bad input parameter

#: Largest every-step output the facade allocates [rows]: 3 arrays of 8-byte floats.
MAX_ROWS = 50_000_000


def status_message(status: int) -> str:
    """The library's message for a status code."""
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


_ERRORS: dict[int, type[IntegrationError]] = {
    STATUS_STEP_BUDGET: StepBudgetExhausted,
    STATUS_STEP_TOO_SMALL: StepSizeTooSmall,
    STATUS_STIFF: StiffnessDetected,
    STATUS_NONFINITE: NonFiniteSolution,
    STATUS_OUTPUT_FULL: OutputBufferFull,
}


@dataclass
class Result:
    """A simulation on its output grid: time t [s], displacement x [m], velocity v [m/s]."""

    scene: str
    law: str
    method: str
    t_end: float
    params: dict[str, float]
    t: np.ndarray
    x: np.ndarray
    v: np.ndarray
    stats: dict[str, Any] = field(default_factory=dict)


def _choice(name: str, value: str, accepted: tuple[str, ...]) -> int:
    if value not in accepted:
        raise ValueError(f"{name}: unknown value {value!r} (accepted: {', '.join(accepted)})")
    return _CODES[value]


def _finite(name: str, value: Any, accepted: str) -> float:
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name}: must be a real number ({accepted}), got {value!r}") from None
    if not math.isfinite(x):
        raise ValueError(f"{name}: must be finite ({accepted}), got {x!r}")
    return x


def _count(name: str, value: Any, low: int = 1, high: int | None = None) -> int:
    """An integer in [low, high] (not a bool), or ValueError naming the parameter."""
    ok = not isinstance(value, bool) and isinstance(value, (int, float, np.integer, np.floating)) \
        and math.isfinite(value) and int(value) == value and value >= low \
        and (high is None or value <= high)
    if not ok:
        bounds = f"in [{low}, {high}]" if high is not None else f">= {low}"
        raise ValueError(f"{name}: must be an integer {bounds}, got {value!r}")
    return int(value)


def _check_names(params: Mapping[str, Any], allowed: tuple[str, ...]) -> None:
    """ValueError naming the parameters that are not in `allowed`."""
    unknown = sorted(set(params) - set(allowed))
    if unknown:
        raise ValueError(f"unknown parameter(s) {', '.join(unknown)} (accepted: {', '.join(allowed)})")


def _check_code(status: int) -> None:
    """Raise ValueError for a bad-input status: the message names the parameter and range."""
    if status <= _FIRST_INPUT_CODE:
        raise ValueError(status_message(status))


def resolve_params(params: Mapping[str, Any], allowed: tuple[str, ...] = _PARAM_ORDER) -> dict[str, float]:
    """Merge user parameters over DEFAULTS, reject unknown names, check finiteness.
    Range checks are the library's (it names the parameter and the accepted range)."""
    _check_names(params, allowed)
    merged = {name: DEFAULTS[name] for name in allowed}
    merged.update(params)
    if merged.get("v_d", 0.0) is None:
        merged["v_d"] = 1.5 * _finite("v_s", merged["v_s"], "> 0 [m/s]")
    return {name: _finite(name, value, "see DEFAULTS for units") for name, value in merged.items()}


def friction_coefficient(law: str, v: Any, **params: float) -> np.ndarray:
    """Friction coefficient mu(v) [-] of `law` at relative velocities v [m/s] (scalar or array).

    Parameters (defaults in DEFAULTS): mu_s, mu_k, v_s, v_d (recurdyn), beta, a (proposed).
    """
    code = _choice("law", law, LAWS)
    p = resolve_params(params, LAW_PARAMS)
    vv = np.asarray(v, dtype=np.float64)
    if not np.all(np.isfinite(vv)):
        raise ValueError("v: must be finite [m/s]")
    mu, status = _ext.friction(code, np.ascontiguousarray(vv.ravel()), *(p[k] for k in LAW_PARAMS))
    _check_code(int(status))
    return np.asarray(mu).reshape(vv.shape)


def simulate(scene: str, law: str, *, method: str, t_end: float, h: float | None = None,
             rtol: float = 1e-6, atol: float = 1e-9, hmin: float = 1e-6, hmax: float = 1e-2,
             h0: float = 0.0, n_out: int | None = None, every_step: bool = False,
             max_steps: int | None = None, allow_forced: bool = True, stop_on_stiff: bool = False,
             x0: float = 0.0, v0: float = 0.0, **params: float) -> Result:
    """Simulate `scene` ("slope" or "belt") with friction `law` from (x0 [m], v0 [m/s]) at t = 0
    to t_end [s], with `method` "rk4" (fixed step h [s]) or "dopri5" (adaptive: rtol, atol,
    hmin, hmax [s], initial step h0 [s], 0 = automatic).

    Output: a uniform grid of n_out points on [0, t_end] (default 1001), or every step when
    every_step is set. max_steps bounds attempted steps (default 10**8; 10**6 for DOPRI5 with
    every_step). When DOPRI5's error test fails at hmin the step is taken anyway and counted in
    stats["nforced"]; allow_forced=False raises StepSizeTooSmall instead.

    Raises ValueError for bad input (naming the parameter and its accepted range) and an
    IntegrationError subclass when the run ends early (its `.result` holds the partial output).
    """
    scene_code = _choice("scene", scene, SCENES)
    law_code = _choice("law", law, LAWS)
    method_code = _choice("method", method, METHODS)
    p = resolve_params(params)
    t_end = _finite("t_end", t_end, "> 0 [s]")
    if method == "rk4":
        if h is None:
            raise ValueError("h: required for method 'rk4' (finite, > 0 [s])")
        h = _finite("h", h, "> 0 [s]")
    elif h is not None:
        raise ValueError("h: only for method 'rk4'; DOPRI5 takes h0 (initial step), hmin, hmax")
    tol = {name: _finite(name, value, "see simulate()") for name, value in
           (("rtol", rtol), ("atol", atol), ("hmin", hmin), ("hmax", hmax), ("h0", h0),
            ("x0", x0), ("v0", v0))}

    if max_steps is None:
        max_steps = 10**6 if (every_step and method == "dopri5") else 10**8
    max_steps = _count("max_steps", max_steps)

    if every_step:
        if n_out is not None:
            raise ValueError("n_out: give either n_out or every_step, not both")
        rows = max_steps
        if method == "rk4" and h > 0.0 and t_end > 0.0:
            rows = min(rows, math.ceil(t_end / h * (1.0 - 1e-12)))
        rows = max(rows, 1) + 1
        if rows > MAX_ROWS:
            raise ValueError(f"max_steps: every_step would allocate {rows} rows (limit {MAX_ROWS}); "
                             "lower max_steps or use n_out")
        t_grid = np.zeros(rows)
    else:
        n_out = _count("n_out", 1001 if n_out is None else n_out, 1, MAX_ROWS)
        t_grid = np.linspace(0.0, t_end, n_out) if n_out > 1 else np.array([t_end])

    cpu0 = time.process_time()
    y, istats, rstats, status = _ext.run_simulation(
        scene_code, law_code, method_code, np.array([p[k] for k in _PARAM_ORDER]),
        tol["x0"], tol["v0"], t_end, h if h is not None else 0.0, tol["rtol"], tol["atol"],
        tol["hmin"], tol["hmax"], tol["h0"], max_steps, int(every_step), int(allow_forced),
        int(stop_on_stiff), t_grid)
    cpu = time.process_time() - cpu0
    status = int(status)
    _check_code(status)

    n = int(istats[7])
    stats: dict[str, Any] = {
        "nfev": int(istats[0]), "nstep": int(istats[1]), "naccept": int(istats[2]),
        "nreject": int(istats[3]), "nforced": int(istats[4]), "nstiff": int(istats[5]),
        "stiff": bool(istats[6]), "status": status, "message": status_message(status),
        "t_reached": float(rstats[0]), "h_last": float(rstats[1]), "cpu_seconds": cpu,
    }
    result = Result(scene=scene, law=law, method=method, t_end=t_end, params=p,
                    t=t_grid[:n].copy(), x=np.array(y[0, :n]), v=np.array(y[1, :n]), stats=stats)
    if status != STATUS_OK:
        raise _ERRORS.get(status, IntegrationError)(status, result)
    return result
