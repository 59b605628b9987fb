"""Identify a friction law from measurements: fit its parameters to measured forces along
measured motions (`fit_friction`), with standard errors, 95 % confidence intervals and
information criteria to compare laws.

The model of a record is `stickslip.prescribed_motion`: the law's force along the measured
displacement x(t) (velocity v(t) measured or derived from x), its internal states starting at 0
in every record, with the two options of the prescribed-motion model that a real device may
need: a backlash (a play of total width b [m] after each reversal) and an asymmetry (the ratio
of the negative-direction sliding level to the positive one); and two terms of the measurement
beside the law: a force-sensor offset [N] added to the force, and a linear drift [1/s] of the
friction level over each record (the law's force times 1 + drift (t - t_mid), t_mid the
record's middle time, so the law's parameters are the record's mean level). All four are fixed
(at 0, 1, 0, 0) unless given as "fit".

Experiment workflows beside the fit of a record: `steady_friction` (the steady force of each
constant-velocity step of a record), `fit_stribeck_curve` (a law's steady friction against
speed fitted to those points) and `fit_two_step` (static parameters from the steady curve, then
the dynamic ones from presliding records with the static ones held).

Statistics. The fit minimises the sum of squared force residuals over all samples of all
records (scipy.optimize.least_squares, trust-region reflective, with bounds). With Gaussian
noise of constant variance and independent samples, the covariance of the parameters is
s^2 (J^T J)^-1 (J the Jacobian of the residuals at the optimum, s^2 = SSR / (n - k)), the
intervals are estimate +- t(0.975, n - k) stderr, and AIC and BIC are those of the Gaussian
likelihood with the noise variance counted as a parameter. Measured noise is rarely
independent from sample to sample (the damper's is not): the covariance is multiplied by
(1 + rho)/(1 - rho), rho the residuals' lag-1 correlation within the records (the variance
inflation of an AR(1) noise), and the intervals are taken on a scale where the parameter's
accepted range is the whole line (log above a lower bound, logit between two), so they stay
in it, or (`interval="profile"`, the default for laws without states) by profile likelihood:
where the sum of squares with the other parameters refitted exceeds its minimum by
t^2 s^2 times the inflation; a parameter near a bound is always profiled (its interval
one-sided there). The error on held-out records is the honest measure of a law:
`select_friction_law` chooses by it (cross-validation over records or groups of records), BIC
is information only, and the held-out residuals calibrate the prediction intervals. Every fit
ends with a cheap probe for a lower point about its end, and restarts from one it (or a profile)
finds; a fit that still has one reports success=False.

The normal force. A force measured without its normal force cannot separate the friction
coefficient from N. `normal_force=None` (the default) sets N = 1 N: the "coefficients" and the
parameters proportional to them (mu_s, mu_k, sigma0, sigma1, sigma2, c_v, gms_c) are then force
levels in newtons (N/m, N s/m, N/s), which `FitResult.units` says and `FitResult.force_levels` flags.
"""
from __future__ import annotations

import contextlib
import math
import re
import warnings
from dataclasses import dataclass, field
from typing import Any, Mapping, Sequence

import numpy as np

from .core import DEFAULTS, LAWS, REGISTRY, _choice, _finite
from .core import _shown as _plain
from .data import Record, decimate
from .prescribed import _samples

#: Parameters of the prescribed-motion model that are not the law's: unit, accepted range.
EXTRA_PARAMS: dict[str, tuple[str, str]] = {
    "backlash": ("m", ">= 0"),
    "asymmetry": ("-", "> 0"),
    "offset": ("N", "any real number"),
    "drift": ("1/s", "any real number"),
}
#: Their values when not given: no play, symmetric, no sensor offset, no drift.
EXTRA_DEFAULTS: dict[str, float] = {"backlash": 0.0, "asymmetry": 1.0, "offset": 0.0, "drift": 0.0}
#: Those that may be fitted one value per record ("per_record"): fitted as `name[i]` for record
#: i, and not carried over to a record the fit has not seen (which gets the default).
PER_RECORD: tuple[str, ...] = ("asymmetry", "offset", "drift")


def _base(name: str) -> str:
    """The parameter's name without a record index: "offset[2]" -> "offset"."""
    return name.split("[", 1)[0]
#: Pairs (lower, upper) of parameters the library requires ordered (mu_k <= mu_s, v_s < v_d):
#: when both are fitted, the upper one is fitted as its excess over the lower (>= 0).
ORDERED_PAIRS: tuple[tuple[str, str], ...] = (("mu_k", "mu_s"), ("v_s", "v_d"))
#: Units of the parameters proportional to the friction coefficient (the force is N mu, so a
#: fit at N = 1 N reads them as force levels): unit as a coefficient -> unit as a force level.
#: (GMS's gms_c [1/s] is a rate of mu per second.)
_FORCE_UNITS: dict[str, str] = {"-": "N", "1/m": "N/m", "s/m": "N s/m", "1/s": "N/s"}
#: Dimensionless parameters that are not proportional to mu (shape exponents, ratios).
_SHAPE_PARAMS: frozenset[str] = frozenset({"beta", "a", "delta", "z_ba_ratio", "dahl_alpha", "gms_shape",
                                           "n_elements"})
#: Integer parameters: not fitted (least squares needs a continuum), held at the value given in
#: `fixed` or at their default.
DISCRETE_PARAMS: frozenset[str] = frozenset({"n_elements"})
#: A fit that lowers the sum of squares of the force (the error of predicting zero) by less
#: than this fraction is no better than zero.
ZERO_GAIN: float = 0.01


def _force_scaled(name: str) -> bool:
    """Whether parameter `name` of a law scales with the friction coefficient."""
    name = _base(name)
    if name in EXTRA_PARAMS or name in _SHAPE_PARAMS:
        return False
    return REGISTRY["param"][name]["unit"] in _FORCE_UNITS


def parameter_unit(name: str, force_levels: bool) -> str:
    """The unit of parameter `name` in a fit: as a coefficient, or as a force level when the
    normal force was not given (force_levels)."""
    name = _base(name)
    if name in EXTRA_PARAMS:
        return EXTRA_PARAMS[name][0]
    unit = REGISTRY["param"][name]["unit"]
    return _FORCE_UNITS[unit] if force_levels and _force_scaled(name) else unit


def _range_of(name: str) -> tuple[float, float, bool, bool]:
    """(low, high, low_open, high_open) that the library accepts for a parameter, read from the
    registry's rule ("must be finite and > 0", "in (0, 1)", ...); an order constraint with another
    parameter (mu_k <= mu_s, v_d > v_s) is handled by ORDERED_PAIRS."""
    name = _base(name)
    rule = EXTRA_PARAMS[name][1] if name in EXTRA_PARAMS else REGISTRY["param"][name]["rule"]
    m = re.search(r"in ([(\[])\s*(-?[0-9.eE+]+),\s*(-?[0-9.eE+]+)\s*([)\]])", rule)
    if m:
        return float(m[2]), float(m[3]), m[1] == "(", m[4] == ")"
    m = re.search(r"(>=|>)\s*(-?[0-9.eE+]+)", rule)
    if m:
        return float(m[2]), math.inf, m[1] == ">", True
    return -math.inf, math.inf, True, True


# --------------------------------------------------------------------------------------------
# Input
# --------------------------------------------------------------------------------------------
@dataclass
class _Data:
    """One record as the fit uses it."""

    t: np.ndarray
    x: np.ndarray
    v: np.ndarray | None
    force: np.ndarray | None
    normal_force: float | np.ndarray


def _one_record(tag: str, t: Any, x: Any, force: Any, v: Any, normal_force: Any,
                min_samples: int = 2) -> _Data:
    """Validate one record; `tag` ("" or "[i]") names it in messages."""
    tt = _samples(f"t{tag}", t, None, "s")
    if tt.size < min_samples:
        raise ValueError(f"t{tag}: must hold at least {min_samples} samples [s], got {tt.size}")
    step = np.diff(tt)
    if not (step > 0.0).all():
        i = int(np.flatnonzero(~(step > 0.0))[0])
        raise ValueError(f"t{tag}: must be strictly increasing [s], got t[{i}] = {_plain(tt[i])} and "
                         f"t[{i + 1}] = {_plain(tt[i + 1])}")
    n = tt.size
    xx = _samples(f"x{tag}", x, n, "m")
    ff = None if force is None else _samples(f"force{tag}", force, n, "N")
    vv = None if v is None else _samples(f"v{tag}", v, n, "m/s")
    if normal_force is None:
        nf: float | np.ndarray = 1.0
    elif np.ndim(normal_force) == 0:
        nf = _finite(f"normal_force{tag}", normal_force, "> 0, a scalar or one value per sample [N]")
        if nf <= 0.0:
            raise ValueError(f"normal_force{tag}: must be > 0 [N], got {nf!r}")
    else:
        nf = _samples(f"normal_force{tag}", normal_force, n, "N")
        if (nf <= 0.0).any():
            raise ValueError(f"normal_force{tag}: must be > 0 [N], got {_plain(nf[nf <= 0.0][0])}")
    return _Data(tt, xx, vv, ff, nf)


def _is_list(value: Any) -> bool:
    """Several records: a list or tuple of arrays (not a flat list of numbers)."""
    return isinstance(value, (list, tuple)) and len(value) > 0 and np.ndim(value[0]) == 1


def _records(t: Any, x: Any, force: Any, v: Any, normal_force: Any, *, need_force: bool = True) -> list[_Data]:
    """One record or several (lists of arrays, or Record objects) as a list of _Data."""
    if isinstance(t, Record) or (isinstance(t, (list, tuple)) and t and all(isinstance(r, Record) for r in t)):
        recs = [t] if isinstance(t, Record) else list(t)
        if x is not None or force is not None or v is not None:
            raise ValueError("x, force, v: give either Record objects (as t) or the arrays t, x, force, v, not both")
        t, x, force, v = ([r.t for r in recs], [r.x for r in recs], [r.force for r in recs],
                          [r.v for r in recs])
        if all(a is None for a in v):
            v = None
    if need_force and force is None:
        raise ValueError("force: the measured force [N] is required")
    if not _is_list(t):
        out = [_one_record("", t, x, force, v, normal_force)]
    else:
        out = _record_list(t, x, force, v, normal_force)
    if need_force:
        for i, d in enumerate(out):
            if not np.ptp(d.x) > 0.0:
                tag = f"[{i}]" if len(out) > 1 else ""
                raise ValueError(f"x{tag}: every sample is {_plain(d.x[0])} m (no motion); a record without "
                                 "motion cannot identify friction (give the displacement of a moving contact)")
    return out


def _record_list(t: Any, x: Any, force: Any, v: Any, normal_force: Any) -> list[_Data]:
    """Several records given as lists of arrays (see _records)."""
    m = len(t)
    for name, value in (("x", x), ("force", force), ("v", v), ("normal_force", normal_force)):
        if value is None or (name == "normal_force" and np.ndim(value) == 0):
            continue
        if not isinstance(value, (list, tuple)) or len(value) != m:
            raise ValueError(f"{name}: t is a list of {m} records, so {name} must be a list of {m} too")
    pick = lambda value, i: value[i] if isinstance(value, (list, tuple)) else value  # noqa: E731
    return [_one_record(f"[{i}]", t[i], pick(x, i), pick(force, i), pick(v, i), pick(normal_force, i))
            for i in range(m)]


# --------------------------------------------------------------------------------------------
# Parameters: names, starts, bounds, the scaled coordinates of the optimiser
# --------------------------------------------------------------------------------------------
def law_fit_params(law: str) -> tuple[str, ...]:
    """The parameters a fit of `law` can adjust: the law's (registry order), then backlash,
    asymmetry, offset and drift."""
    return REGISTRY["law"][law]["params"] + tuple(EXTRA_PARAMS)


def _data_scales(data: list[_Data]) -> dict[str, float]:
    """Scales read from the records: sliding levels in each direction (the median of mu N over
    the samples moving faster than a quarter of the top speed), top speed, amplitude."""
    v = np.concatenate([d.v if d.v is not None else np.gradient(d.x, d.t) for d in data])
    x = np.concatenate([d.x - np.median(d.x) for d in data])
    mu = np.concatenate([d.force / d.normal_force for d in data])
    v_max = float(np.max(np.abs(v))) or 1.0
    pos, neg = mu[v > 0.25 * v_max], mu[v < -0.25 * v_max]
    level_pos = float(np.median(pos)) if pos.size else float(np.max(np.abs(mu)))
    level_neg = float(-np.median(neg)) if neg.size else level_pos
    level_pos = level_pos if level_pos > 0.0 else float(np.max(np.abs(mu))) or 1.0
    level_neg = level_neg if level_neg > 0.0 else level_pos
    amp = 0.5 * float(np.ptp(x)) or 1.0
    return {"level_pos": level_pos, "level_neg": level_neg, "v_max": v_max, "amplitude": amp}


def _start(name: str, s: dict[str, float], asym_free: bool) -> float:
    """A starting value of parameter `name` from the data's scales (see _data_scales)."""
    level = s["level_pos"] if asym_free else 0.5 * (s["level_pos"] + s["level_neg"])
    presliding = 0.05 * s["amplitude"]          # travel over which the force turns round [m]
    starts = {
        "mu_k": level, "mu_s": 1.2 * level, "v_s": 0.1 * s["v_max"], "v_d": 0.15 * s["v_max"],
        "dv": 0.01 * s["v_max"], "v_eps": 0.01 * s["v_max"],
        "sigma0": level / presliding, "sigma1": 0.01 * level / s["v_max"],
        "sigma2": 0.05 * level / s["v_max"], "c_v": 0.05 * level / s["v_max"],
        "backlash": 0.02 * s["amplitude"], "asymmetry": s["level_neg"] / s["level_pos"],
        "offset": 0.0, "drift": 0.0,
    }
    if name in starts:
        return starts[name]
    default = DEFAULTS.get(name)
    if default is None or default == 0.0:
        raise ValueError(f"params0: no starting value of {name!r} can be derived from the data; "
                         "give one in params0")
    return float(default) * (level if _force_scaled(name) else 1.0)


@dataclass
class _Space:
    """The optimiser's coordinates u of the free parameters: u_i = q_i / scale_i, with q_i the
    parameter itself or, for the upper member of an ordered pair whose lower member is free
    too, its excess over the lower one. p = P u + p_fixed (P linear)."""

    free: tuple[str, ...]
    scale: np.ndarray
    lower_of: dict[int, int]          # index of an upper member -> index of its lower member

    def to_params(self, u: np.ndarray) -> np.ndarray:
        q = u * self.scale
        p = q.copy()
        for hi, lo in self.lower_of.items():
            p[hi] = q[hi] + q[lo]
        return p

    def from_params(self, p: np.ndarray) -> np.ndarray:
        q = np.array(p, dtype=float)
        for hi, lo in self.lower_of.items():
            q[hi] = p[hi] - p[lo]
        return q / self.scale

    def matrix(self) -> np.ndarray:
        """dp/du (constant)."""
        m = np.diag(self.scale)
        for hi, lo in self.lower_of.items():
            m[hi, lo] = self.scale[lo]
        return m


#: The largest z_ba_ratio a fit tries unless `bounds` says otherwise (see `_coordinates`).
Z_BA_RATIO_MAX: float = 0.999


def _coordinates(free: tuple[str, ...], p0: np.ndarray, bounds: Mapping[str, Any], fixed_all: Mapping[str, float],
                 typical: Mapping[str, float]) -> tuple[_Space, np.ndarray, np.ndarray, np.ndarray]:
    """The optimiser's coordinates of the free parameters (see _Space): the space, the bounds
    q_lo, q_hi in it (the library's ranges, narrowed by `bounds`, a hair inside an open end,
    a stiffness at most 1000 times its start, the ordered pairs) and the start u0. `p0` is
    the start in the parameters (the upper member of a fitted ordered pair may be raised
    above its lower one); `typical` sizes a parameter that starts at 0."""
    k = len(free)
    lo = np.empty(k)
    hi = np.empty(k)
    for i, n in enumerate(free):
        low, high, low_open, high_open = _range_of(n)
        if n == "mu_k":
            low_open = True     # the laws with states divide by the sliding level: keep it > 0
        if n in bounds:
            try:
                b_lo, b_hi = (float(b) for b in bounds[n])
            except (TypeError, ValueError):
                raise ValueError(f"bounds[{n!r}]: must be a pair (low, high), got {bounds[n]!r}") from None
            if not (b_lo < b_hi) or math.isnan(b_lo) or math.isnan(b_hi):
                raise ValueError(f"bounds[{n!r}]: must have low < high, got {bounds[n]!r}")
            low_open, high_open = low_open and b_lo <= low, high_open and b_hi >= high
            low, high = max(low, b_lo), min(high, b_hi)
        if n not in bounds and REGISTRY["param"].get(n, {}).get("unit") == "1/m":
            # a stiffness: at most 1000 times its start (a presliding travel of 5e-5 times the
            # amplitude); beyond that the states are too stiff to integrate cheaply, and a static
            # law describes the data as well
            high = min(high, 1e3 * p0[i])
        if n == "z_ba_ratio" and n not in bounds and high > Z_BA_RATIO_MAX:
            # the elasto-plastic transition narrows as z_ba_ratio nears 1, and its substeps
            # multiply (one damper record at v_s 0.033 m/s: 0.12 s at 0.999, 0.75 s at
            # 0.9999, over 15 s at 0.999999)
            high, high_open = Z_BA_RATIO_MAX, False
        # an open end of the library's range: stay a relative hair inside it
        margin = 1e-9 * max(abs(p0[i]), 1e-300)
        lo[i] = low + margin if low_open and math.isfinite(low) else low
        hi[i] = high - margin if high_open and math.isfinite(high) else high
    lower_of: dict[int, int] = {}
    for a, b in ORDERED_PAIRS:
        if a in free and b in free:
            ia, ib = free.index(a), free.index(b)
            if b in bounds:
                raise ValueError(f"bounds: {b!r} cannot be bounded while {a!r} is fitted too "
                                 f"({b} is fitted as {b} - {a} >= 0); fix {a} or drop the bounds")
            lower_of[ib] = ia
            strict = REGISTRY["param"][b]["rule"].split(a)[0].rstrip().endswith(">")
            lo[ib], hi[ib] = (1e-9 * abs(p0[ib]) if strict else 0.0), math.inf
            p0[ib] = max(p0[ib], p0[ia] * (1.0 + 1e-3))
        elif a in fixed_all and b in free:
            lo[free.index(b)] = max(lo[free.index(b)], fixed_all[a])
        elif b in fixed_all and a in free:
            hi[free.index(a)] = min(hi[free.index(a)], fixed_all[b])
    scale = np.array([abs(p0[i]) if p0[i] != 0.0 else typical.get(_base(n), 1.0) for i, n in enumerate(free)])
    for hi_i, lo_i in lower_of.items():     # the excess is scaled like the parameter itself
        scale[hi_i] = max(abs(p0[hi_i]), scale[lo_i])
    space = _Space(free, scale, lower_of)
    q_lo, q_hi = lo / scale, hi / scale
    u0 = np.clip(space.from_params(p0), q_lo, q_hi)
    bad = [free[i] for i in range(k) if not (q_lo[i] <= u0[i] <= q_hi[i]) or q_lo[i] >= q_hi[i]]
    if bad:
        raise ValueError(f"bounds: empty range for {', '.join(bad)}")
    return space, q_lo, q_hi, u0


def _check_keys(what: str, given: Mapping[str, Any], allowed: Sequence[str], law: str) -> None:
    unknown = [k for k in given if k not in allowed]
    if unknown:
        raise ValueError(f"{what}: unknown parameter(s) {', '.join(map(repr, unknown))} of law {law!r} "
                         f"(accepted: {', '.join(allowed)})")


def _extra_option(name: str, value: Any) -> float | str | None:
    """backlash, asymmetry, offset, drift: a fixed value (range-checked), None for "fit", or
    "per_record" (asymmetry, offset, drift)."""
    if isinstance(value, str):
        accepted = ("fit", "per_record") if name in PER_RECORD else ("fit",)
        if value not in accepted:
            raise ValueError(f"{name}: must be a number or {' or '.join(map(repr, accepted))}, got {value!r}")
        return None if value == "fit" else value
    x = _finite(name, value, EXTRA_PARAMS[name][1])
    lo, _, lo_open, _ = _range_of(name)
    if x < lo or (lo_open and x == lo):
        raise ValueError(f"{name}: must be {EXTRA_PARAMS[name][1]} [{EXTRA_PARAMS[name][0]}], got {x!r}")
    return x


def _in_range(label: str, name: str, value: Any, force_levels: bool) -> float:
    """A given value of parameter `name` (fixed or a start), finite and in the range the
    library accepts, or a ValueError naming `label`, the range and the unit."""
    unit = parameter_unit(name, force_levels)
    x = _finite(label, value, "a real number")
    low, high, low_open, high_open = _range_of(name)
    if x < low or x > high or (low_open and x == low) or (high_open and x == high):
        lo_s = ("(" if low_open else "[") + f"{low:g}"
        hi_s = f"{high:g}" + (")" if high_open else "]")
        rng = f"> {low:g}" if math.isinf(high) and low_open else (f">= {low:g}" if math.isinf(high) else f"in {lo_s}, {hi_s}")
        raise ValueError(f"{label}: must be {rng} [{unit}], got {x!r}")
    if name in DISCRETE_PARAMS and x != int(x):
        raise ValueError(f"{label}: must be an integer [{unit}], got {x!r}")
    return x


# --------------------------------------------------------------------------------------------
# Result
# --------------------------------------------------------------------------------------------
@dataclass
class _Estimates:
    """What every fit of parameters holds: the law, every parameter (fitted or fixed) with its
    unit, the fitted ones (`free`, the order of the covariance's rows), their standard errors
    and 95 % intervals, covariance and correlation."""

    law: str
    params: dict[str, float]
    units: dict[str, str]
    free: tuple[str, ...]
    stderr: dict[str, float]
    ci95: dict[str, tuple[float, float]]
    covariance: np.ndarray
    correlation: np.ndarray


@dataclass
class FitResult(_Estimates):
    """A fitted friction law.

    `params` holds every parameter of the model (the law's, backlash, asymmetry, offset and
    drift), fitted or fixed; `units` their units (force levels in N, N/m, N s/m when `force_levels`); `free` the
    fitted ones, in the order of the rows and columns of `covariance` and `correlation`.
    `stderr` and `ci95` (95 % interval, Student t with n - k degrees of freedom) cover the
    fitted parameters; a parameter the data does not determine (a zero direction of the
    Jacobian) has stderr inf. `at_bound` names fitted parameters that ended on a bound of
    their range or nearer to it than t(0.975) stderr (the data cannot tell them from the
    bound), whose intervals mean little.

    Scores over the fitted samples: `chisqr` (sum of squared residuals) [N^2], `redchi`
    (chisqr / (n - k)) [N^2], `rmse` [N], `nrmse` (rmse over the range of the measured force)
    [-], `aic`, `bic` (the full Gaussian likelihood; k = len(free) + 1, the noise variance
    included), `aic_lmfit`, `bic_lmfit` (lmfit's: n ln(chisqr / n) + 2 k and + k ln n, k =
    len(free); they differ from `aic`, `bic` by n (1 + ln 2 pi) + 2 and + ln n), `n_samples`,
    `n_records`; `cv_nrmse` (mean, standard error) when `select_friction_law` made the fit,
    and `heldout_residuals` [N] (the residuals of fits without each record on it, which
    calibrate `predict`'s intervals) when it or `fit_friction(..., calibrate=True)` did. `optimizer` names the
    optimiser, `bounds` the range each free parameter was fitted in, `nfev` counts the
    optimiser's model evaluations (not its Jacobians'), `n_evaluations` every model evaluation
    of the fit (Jacobians, restarts, standard errors, profiles and probes included).

    `profiled` names the parameters whose `ci95` is a profile-likelihood interval (the others'
    are Wald intervals, see `fit_friction`'s `interval`) and `profile_evals` counts the model
    evaluations the profiles took.

    The residuals: `residual_sd` [N], `noise_correlation` (lag-1, within records) and the
    `variance_inflation` (1 + rho)/(1 - rho) applied to the covariance. `undetermined` names
    fitted parameters whose standard error exceeds them (or is inf). `start` holds the start
    of the best local fit.

    The outcome: `success` is False (with `message` saying why, and a RuntimeWarning at the
    fit) when the optimiser used its budget, stopped short of a minimum (after `restarts`
    further local searches from the lower points found, each while the last lowered the cost
    by more than the gain asked below, MAX_RESTARTS at most, a cheap probe about its end, a
    Gauss-Newton step or two standard errors along a parameter, still lowers the sum of squares
    by more than PROBE_GAIN reduced chi-squares, `probe_gain` [N^2] the best decrease; or a
    profile of the intervals found such a point, the model itself evaluated there and not only
    on the optimum's frozen substeps), or the fit is no better than predicting zero.
    `optimality` is the largest cosine between the residual and a free parameter's Jacobian
    column (0 at a minimum). `report()` prints all of it.
    """

    rmse: float
    nrmse: float
    aic: float
    bic: float
    n_samples: int
    n_records: int
    force_levels: bool
    normal_force: Any
    at_bound: tuple[str, ...] = ()
    cost: float = 0.0
    nfev: int = 0
    n_starts: int = 1
    success: bool = True
    message: str = ""
    start_costs: tuple[float, ...] = field(default_factory=tuple)
    rtol: float = 1e-6
    optimality: float = 0.0
    noise_correlation: float = 0.0
    variance_inflation: float = 1.0
    residual_sd: float = 0.0
    undetermined: tuple[str, ...] = ()
    start: dict[str, float] = field(default_factory=dict)
    cv_nrmse: tuple[float, float] | None = None
    profiled: tuple[str, ...] = ()
    profile_evals: int = 0
    optimizer: str = "scipy.optimize.least_squares (trf, bounded)"
    chisqr: float = 0.0
    redchi: float = 0.0
    aic_lmfit: float = 0.0
    bic_lmfit: float = 0.0
    n_evaluations: int = 0
    bounds: dict[str, tuple[float, float]] = field(default_factory=dict)
    heldout_residuals: np.ndarray | None = None
    probe_gain: float = 0.0
    restarts: int = 0
    _lower_point: np.ndarray | None = field(default=None, repr=False, compare=False)

    @property
    def law_params(self) -> dict[str, float]:
        """The law's parameters (without backlash, asymmetry, offset and drift)."""
        return {k: v for k, v in self.params.items() if _base(k) not in EXTRA_PARAMS}

    def predict(self, t: Any, x: Any = None, v: Any = None, normal_force: Any = None,
                interval: float | None = None) -> Any:
        """The fitted model's force [N] along a motion x(t) [m] (v [m/s] measured, or derived
        from x), internal states from 0; `t` may be a Record (its x and v are used). Several
        records (lists) give a list of forces.
        normal_force [N]: required when the fit was of coefficients with a per-sample normal
        force; by default the fit's own (1 N, i.e. force levels, when it was not given).

        interval : float in (0, 1), optional
            Also return a prediction interval of that probability for a measured force at each
            sample: (force, lower, upper). Calibrated, when the fit holds held-out residuals
            (`heldout_residuals`: `select_friction_law`'s folds, or `fit_friction(...,
            calibrate=True)` on several records): the half-width is that
            quantile of their magnitudes, the same at every sample (the scatter of new records
            about a model fitted without them, parameter error included). Otherwise from the
            fit alone: z sqrt(s^2 + d^T R d), z the normal quantile, s the residual standard
            deviation of the fit (the scatter of a measurement about the model), R the
            parameters' correlation and d_i the force's change over one standard error of
            parameter i (finite differences, one model evaluation per parameter, stepped to
            the side the parameter's range and the ordered pairs mu_k <= mu_s, v_s < v_d
            allow). For a parameter at a bound (`at_bound`), whose Jacobian there says little,
            d_i is the force's change between the estimate and the far end of its 95 %
            interval, over t(0.975): a secant over the range the data allow, not a tangent.
            Gaussian scatter is assumed; a parameter the data do not determine makes the
            interval infinite where the force depends on it.
        """
        if normal_force is None:
            if np.ndim(self.normal_force) != 0:
                raise ValueError("normal_force: the fit had a normal force per sample; give the one of "
                                 "this motion [N]")
            normal_force = None if self.force_levels else self.normal_force
        if interval is not None:
            q = _finite("interval", interval, "in (0, 1)")
            if not 0.0 < q < 1.0:
                raise ValueError(f"interval: must be in (0, 1), got {_plain(interval)}")
        data = _records(t, x, None, v, normal_force, need_force=False)
        out = [_model(self.law, d, _new_record_params(self.params), self.rtol) for d in data]
        if interval is None:
            return out if isinstance(t, (list, tuple)) else out[0]
        from scipy import stats
        bands = []
        if self.heldout_residuals is not None and self.heldout_residuals.size:
            half_c = float(np.quantile(np.abs(self.heldout_residuals), q))
            bands = [(f, f - half_c, f + half_c) for f in out]
        else:
            z = float(stats.norm.ppf(0.5 + 0.5 * q))
            tq = float(stats.t.ppf(0.975, max(self.n_samples - len(self.free), 1)))
            sd = np.array([self.stderr[name] for name in self.free])
            blind = [i for i in range(len(self.free)) if not math.isfinite(sd[i])]
            corr = np.where(np.isfinite(self.correlation), self.correlation, 0.0)
            for d, f in zip(data, out):
                if blind:
                    bands.append((f, f - math.inf, f + math.inf))
                    continue
                change = np.column_stack([self._change(d, f, name, float(sd[i]), tq)
                                          for i, name in enumerate(self.free)]) if self.free else np.zeros((f.size, 0))
                var = self.residual_sd ** 2 + np.einsum("ij,jk,ik->i", change, corr, change)
                half = z * np.sqrt(var)
                bands.append((f, f - half, f + half))
        if isinstance(t, (list, tuple)):
            return [b[0] for b in bands], [b[1] for b in bands], [b[2] for b in bands]
        return bands[0]

    def _change(self, d: _Data, f: np.ndarray, name: str, sd: float, tq: float) -> np.ndarray:
        """The force's change on record `d` (force `f` at the estimate) over one standard error
        of parameter `name` (see `predict`): a tangent by a small step to the side the range
        and the ordered pairs allow, or at a bound the secant to the far end of the 95 %
        interval over tq."""
        value = self.params[name]
        if name in self.at_bound and name in self.ci95:
            lo, hi = self.ci95[name]
            end = hi if abs(hi - value) >= abs(value - lo) else lo
            if math.isfinite(end) and end != value:
                return (self._model_with(d, name, end) - f) / tq
        h = 1e-3 * max(abs(value), sd, 1e-12)
        for step in (h, -h, 0.5 * h, -0.5 * h):
            try:
                return (self._model_with(d, name, value + step) - f) / step * sd
            except ValueError:
                continue
        return np.zeros_like(f)

    def _model_with(self, d: _Data, name: str, value: float) -> np.ndarray:
        """The model's force on `d` with parameter `name` at `value`, or ValueError when that
        leaves its range or breaks an ordered pair (mu_k <= mu_s, v_s < v_d)."""
        low, high, low_open, high_open = _range_of(name)
        if value < low or value > high or (low_open and value == low) or (high_open and value == high):
            raise ValueError(f"{name}: {value!r} out of range")
        p = dict(self.params)
        p[name] = value
        for a, b in ORDERED_PAIRS:
            if a in p and b in p and not p[a] <= p[b]:
                raise ValueError(f"{a} > {b}")
        return _model(self.law, d, _new_record_params(p), self.rtol)

    def score(self, t: Any, x: Any = None, force: Any = None, v: Any = None,
              normal_force: Any = None) -> dict[str, float]:
        """The error of the fitted model on other records (held out): rmse [N] and nrmse (over
        the range of their measured force) [-], pooled over every sample given. Per-record
        terms (offset, drift, asymmetry "per_record") are not carried over, as in `predict`."""
        data = _records(t, x, force, v, normal_force if normal_force is not None else
                        (None if self.force_levels else self.normal_force))
        r = np.concatenate([_model(self.law, d, _new_record_params(self.params), self.rtol) - d.force for d in data])
        f = np.concatenate([d.force for d in data])
        rmse = float(np.sqrt(np.mean(r**2)))
        return {"rmse": rmse, "nrmse": rmse / float(np.ptp(f)), "n_samples": int(r.size)}

    def report(self, min_correl: float = 0.1) -> str:
        """A full report of the fit (at least lmfit's fit_report): the fit's outcome (optimiser,
        success, termination message, model evaluations: the optimiser's and every one the fit
        made, Jacobians, intervals and probes included; starts, restarts), the scores
        (chi-square, reduced chi-square, rmse, nrmse, AIC and BIC in lmfit's definitions and in
        the full Gaussian likelihood's, and the cross-validated NRMSE when `select_friction_law`
        made this fit), the residuals' correlation in time and the variance inflation it
        brings, then each parameter with its start, estimate, standard error (and relative %),
        95 % interval, bounds and flags (fixed, at a bound, not determined), and the
        correlations above `min_correl` in magnitude (lmfit's default 0.1)."""
        q = _finite("min_correl", min_correl, "in [0, 1)")
        if not 0.0 <= q < 1.0:
            raise ValueError(f"min_correl: must be in [0, 1), got {_plain(min_correl)}")
        what = "force levels (normal force not given: N = 1 N)" if self.force_levels else "coefficients"
        lines = ["[[Fit]]",
                 f"    law                = {self.law}",
                 f"    optimiser          = {self.optimizer}",
                 f"    data               = {self.n_records} record(s), {self.n_samples} samples, {what}",
                 f"    success            = {self.success}",
                 f"    message            = {self.message}",
                 f"    model evaluations  = {self.nfev} by the optimiser (Jacobians not counted); "
                 f"{self.n_evaluations} in all (Jacobians, intervals and probes included)",
                 f"    starts             = {self.n_starts}, restarts from a lower point = {self.restarts}",
                 f"    fitted parameters  = {len(self.free)}",
                 f"    95% intervals      = {self._interval_kinds()}",
                 "[[Scores]]",
                 f"    chi-square         = {self.chisqr:.6g} N^2 (sum of squared residuals)",
                 f"    reduced chi-square = {self.redchi:.6g} N^2 (over n - k = {self.n_samples - len(self.free)})",
                 f"    rmse               = {self.rmse:.6g} N",
                 f"    nrmse              = {self.nrmse:.6g} (rmse / range of the measured force)",
                 f"    AIC (lmfit)        = {self.aic_lmfit:.6g} (n ln(chi-square / n) + 2 k)",
                 f"    BIC (lmfit)        = {self.bic_lmfit:.6g} (n ln(chi-square / n) + k ln n)",
                 f"    AIC                = {self.aic:.6g} (full Gaussian -2 ln L + 2 (k + 1), the noise "
                 "variance counted: `aic`)",
                 f"    BIC                = {self.bic:.6g} (-2 ln L + (k + 1) ln n: `bic`)"]
        if self.cv_nrmse is not None:
            lines.append(f"    cross-validated    = {self.cv_nrmse[0]:.6g} +- {self.cv_nrmse[1]:.2g} (held-out NRMSE, "
                         "mean +- standard error over folds)")
        lines += ["[[Residuals]]",
                  f"    standard deviation = {self.residual_sd:.6g} N",
                  f"    lag-1 correlation  = {self.noise_correlation:.4f} (variance inflation of the "
                  f"parameters {self.variance_inflation:.3g})",
                  "[[Parameters]]"]
        for name, value in self._shown():
            unit = self.units[name]
            if name not in self.free:
                lines.append(f"    {name + ':':<12} {value:<14.7g} (fixed) [{unit}]")
                continue
            sd = self.stderr[name]
            rel = f"({100 * sd / abs(value):.2f}%)" if value != 0 and math.isfinite(sd) else ""
            lo, hi = self.ci95[name]
            flags = [f for f, on in (("at a bound", name in self.at_bound),
                                     ("not determined by the data", name in self.undetermined)) if on]
            start = self.start.get(name, float("nan"))
            b_lo, b_hi = self.bounds.get(name, (-math.inf, math.inf))
            lines.append(f"    {name + ':':<12} {value:<14.7g} +/- {sd:<11.4g} {rel:<10} (start {start:.5g}) "
                         f"[{unit}]  95% [{lo:.6g}, {hi:.6g}]  bounds [{b_lo:.6g}, {b_hi:.6g}]"
                         + (f"  {'; '.join(flags)}" if flags else ""))
        pairs = []
        for i, a in enumerate(self.free):
            for j in range(i + 1, len(self.free)):
                c = self.correlation[i, j]
                if math.isfinite(c) and abs(c) > q:
                    pairs.append((abs(c), c, a, self.free[j]))
        lines.append(f"[[Correlations]] (|c| > {q:g})")
        lines += [f"    C({a}, {b}) = {c:+.4f}" for _, c, a, b in sorted(pairs, reverse=True)] or ["    none"]
        return "\n".join(lines)

    def _interval_kinds(self) -> str:
        """How the 95 % intervals were made, for the report."""
        if not self.profiled:
            return "Wald, on the range's scale"
        others = "; Wald (on the range's scale) for the others" if len(self.profiled) < len(self.free) else ""
        return f"profile likelihood for {', '.join(self.profiled)} ({self.profile_evals} model evaluations){others}"

    def _shown(self) -> list[tuple[str, float]]:
        """The parameters a report lists: all but an offset or drift held at 0 (not used)."""
        return [(name, value) for name, value in self.params.items()
                if name in self.free or name not in ("offset", "drift") or value != EXTRA_DEFAULTS[name]]

    def summary(self) -> str:
        """A plain-text table of the parameters with their intervals, and the scores."""
        what = "force levels (normal force not given: N = 1 N)" if self.force_levels else "coefficients"
        lines = [f"{self.law}: {self.n_records} record(s), {self.n_samples} samples, {what}",
                 f"  rmse {self.rmse:.4g} N, nrmse {self.nrmse:.4g}, AIC {self.aic:.6g}, BIC {self.bic:.6g}"]
        for name, value in self._shown():
            unit = self.units[name]
            if name in self.ci95:
                lo, hi = self.ci95[name]
                flag = " (at a bound)" if name in self.at_bound else ""
                lines.append(f"  {name:>10} = {value:.6g} {unit}  95% CI [{lo:.6g}, {hi:.6g}]{flag}")
            else:
                lines.append(f"  {name:>10} = {value:.6g} {unit}  (fixed)")
        return "\n".join(lines)


def _motion(d: _Data) -> tuple[np.ndarray, np.ndarray]:
    """The velocity and the normal force of a record as arrays for the library, derived once
    (the velocity as `prescribed_motion` derives it when none is given)."""
    cached = d.__dict__.get("_motion")
    if cached is None:
        n = d.t.size
        v = d.v if d.v is not None else (np.gradient(d.x, d.t, edge_order=2 if n > 2 else 1) if n > 1
                                         else np.zeros(1))
        nf = np.ascontiguousarray(np.atleast_1d(np.asarray(d.normal_force, dtype=np.float64)))
        cached = d.__dict__["_motion"] = (np.ascontiguousarray(v), nf)
    return cached


def _model_mesh(law: str, d: _Data, params: Mapping[str, float], rtol: float = 1e-8,
                substeps: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The model's force [N] on one record (see `_model`) and the substeps per monotone piece
    of each sample interval that its state integration used; `substeps` given: on that frozen
    mesh, a smooth function of the parameters (the finite-difference Jacobian's model)."""
    from .prescribed import _force_on
    law_p = {k: v for k, v in params.items() if _base(k) not in EXTRA_PARAMS}
    v, nf = _motion(d)
    backlash = _finite("backlash", params["backlash"], ">= 0 [m]")
    asymmetry = _finite("asymmetry", params["asymmetry"], "> 0 [-]")
    if backlash < 0.0:
        raise ValueError(f"backlash: must be >= 0 [m], got {backlash!r}")
    if asymmetry <= 0.0:
        raise ValueError(f"asymmetry: must be > 0 (negative-direction level / positive one) [-], got {asymmetry!r}")
    force, used = _force_on(law, law_p, d.t, d.x, v, nf, backlash, asymmetry, rtol, substeps)
    drift, offset = params.get("drift", 0.0), params.get("offset", 0.0)
    if drift != 0.0:
        force = force * (1.0 + drift * (d.t - 0.5 * (d.t[0] + d.t[-1])))
    return (force + offset if offset != 0.0 else force), used


def _model(law: str, d: _Data, params: Mapping[str, float], rtol: float = 1e-8) -> np.ndarray:
    """The model's force [N] on one record: stickslip.prescribed_motion with the states at 0,
    times 1 + drift (t - t_mid), plus the offset."""
    return _model_mesh(law, d, params, rtol)[0]


# --------------------------------------------------------------------------------------------
# The fit
# --------------------------------------------------------------------------------------------
def _one_blas_thread() -> contextlib.AbstractContextManager:
    """A context in which BLAS and LAPACK run on one thread, when threadpoolctl is installed
    (else no change). A fit's linear algebra (the optimiser's SVD of a samples x parameters
    Jacobian, a few per iteration) is too small to gain from threads, and between two such calls
    the model's evaluations leave the idle BLAS threads spinning: on the damper's ten records an
    elasto-plastic fit spent about a quarter more CPU time with two threads, for the same wall
    time (the identification guide)."""
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:
        return contextlib.nullcontext()
    return threadpool_limits(limits=1, user_api="blas")


def fit_friction(law: str, t: Any, x: Any = None, force: Any = None, v: Any = None, *,
                 normal_force: Any = None, fixed: Mapping[str, float] | None = None,
                 params0: Mapping[str, float] | None = None,
                 bounds: Mapping[str, tuple[float, float]] | None = None,
                 backlash: float | str = 0.0, asymmetry: float | str = 1.0,
                 offset: float | str = 0.0, drift: float | str = 0.0, n_starts: int = 1, seed: int = 0, max_nfev: int | None = None,
                 rtol: float = 1e-6, diff_step: float = 1e-4, interval: str = "auto",
                 calibrate: bool = False) -> FitResult:
    """Fit the parameters of friction `law` to measured forces along measured motions.

    Parameters
    ----------
    law : str
        A law of `stickslip.LAWS`.
    t, x, force : array_like or list of array_like
        Sample times [s] (strictly increasing), displacement [m] and measured force [N] of one
        record, or lists of them for several records fitted jointly (the internal states start
        at 0 in each). `t` may instead be a `stickslip.Record` or a list of them (x, force and v
        then come from the records and must not be given).
    v : array_like or list, optional
        Measured velocity [m/s]; by default derived from x (`prescribed_motion`).
    normal_force : float, array_like or list, optional
        Normal force N [N], > 0 (scalar, per sample, or per record). None (the default): not
        measured; N = 1 N and the fitted "coefficients" (mu_s, mu_k, sigma0, ...) are force levels
        in N (N/m, N s/m): mu and N cannot be told apart. `FitResult.force_levels` says which.
    fixed : dict, optional
        Law parameters held at the given values (not fitted). An integer parameter (GMS's
        n_elements) is never fitted: it stays at its default unless given here.
    params0 : dict, optional
        Starting values of fitted parameters (default: derived from the data).
    bounds : dict, optional
        name -> (low, high) for fitted parameters (default: the range the library accepts, and
        for a stiffness [1/m] at most 1000 times its start, and the elasto-plastic z_ba_ratio at most
        Z_BA_RATIO_MAX, 0.999: its transition narrows towards 1 and its integration costs in
        proportion).
        Not for mu_s (or v_d) while mu_k (v_s) is fitted too: the upper member of an ordered pair
        is then fitted as its excess over the lower one.
    backlash : float or "fit"
        Total width of the play after each reversal [m] (default 0): a value fixes it, "fit"
        fits it.
    asymmetry : float, "fit" or "per_record"
        Negative-direction sliding level over the positive one [-] (default 1).
    offset : float, "fit" or "per_record"
        A constant added to the measured force, such as a load cell's zero offset [N]
        (default 0). "fit": one value for all records.
    drift : float, "fit" or "per_record"
        Relative rate of change of the friction level over each record [1/s] (default 0): the
        law's force is multiplied by 1 + drift (t - t_mid), t_mid the record's middle time (the
        level of a contact that heats or wears during a record). "fit": one value for all
        records.

        "per_record" (asymmetry, offset, drift): one value per record, fitted as `name[i]`
        for record i (`FitResult.params`, `free`), the common entry held at its default. These
        are nuisance terms of each record's measurement: `predict` and `score` on another
        record do not carry them over (that record gets the default: symmetric, no offset, no
        drift), nor do the held-out folds of `select_friction_law` and `calibrate`.
    n_starts : int
        Starts of the local optimiser: the data-derived start, then starts drawn log-uniformly
        within a factor of 10 of it (seeded by `seed`); the best fit is kept. Default 1: give
        more where the cost may have several minima (a law with internal states is not convex
        in its stiffness). Each start costs a fit, and a draw far from the data's start can
        cost many (a stiff bristle).
    seed : int
        Seed of the extra starts.
    rtol : float
        Relative tolerance of the state integration (`prescribed_motion`'s rtol), default 1e-6.
    diff_step : float
        Relative step of the finite-difference Jacobian (default 1e-4): well above rtol, whose
        integration error would otherwise swamp the differences.
    max_nfev : int, optional
        Largest number of model evaluations per start, Jacobian evaluations not counted
        (default 30 per fitted parameter).
    interval : {"auto", "wald", "profile"}
        How the 95 % intervals `ci95` are made. "wald": estimate +- t(0.975, n - k) stderr on a
        scale where the parameter's range is the whole line (log above a lower bound, logit
        between two; for mu_s fitted with mu_k, and v_d with v_s, the log of its excess over
        the other), so they stay in it. "profile": profile likelihood: each end is the value
        at which the sum of squares, the other parameters refitted, exceeds its minimum by
        t(0.975, n - k)^2 s^2 (times the variance inflation); the interval follows the cost's
        own shape (asymmetric where it is), stops at a bound of the range when the cost stays
        below the threshold up to it (the parameter is then in `at_bound`) and is infinite on
        a side with no bound and no end within 50 Wald half-widths (the parameter is then in
        `undetermined`). The refits are chord Gauss-Newton steps with the optimum's Jacobian on
        its frozen substeps (about 25 model evaluations a parameter: 1.1-1.6 times the cost of
        a static law's fit on short synthetic records, 2-3 times on the damper's records, twice
        that of LuGre's). "auto" (default): for the laws without internal states, profiles of
        the parameters in turn while the profiles' evaluations stay below the fit's own (so at
        most about twice the cost), Wald intervals for the rest and for the laws with states.
        `FitResult.profiled` names the profiled parameters. On synthetic records both kinds
        give the same coverage (see the identification guide). A parameter near a bound (within
        a Wald half-width) is profiled whatever the method: its interval is one-sided there.
    calibrate : bool
        With several records: also refit leaving one record out at a time (Wald intervals,
        the same options) and keep the residuals of each refit on its held-out record
        (`FitResult.heldout_residuals`), which then set the width of `predict`'s intervals.
        Costs one fit per record.

    Returns
    -------
    FitResult

    Raises
    ------
    ValueError
        Bad input, naming it: an unknown law or parameter, NaN or infinite samples, records of
        mismatched lengths, t not strictly increasing, a value out of its range, fewer samples
        than fitted parameters + 2.

    Examples
    --------
    >>> import numpy as np, stickslip
    >>> t = np.linspace(0.0, 4.0, 801)
    >>> x = 0.01 * np.sin(np.pi * t)
    >>> f = stickslip.prescribed_motion("lugre", t, x, mu_s=1200.0, mu_k=1000.0, v_s=0.005,
    ...                                 sigma0=2e6, sigma1=0.0, sigma2=500.0).force
    >>> fit = stickslip.fit_friction("lugre", t, x, f, fixed={"sigma1": 0.0})
    >>> round(fit.params["mu_k"])
    1000
    """
    from scipy.optimize import least_squares

    _choice("law", law, LAWS)
    data = _records(t, x, force, v, normal_force)
    force_levels = normal_force is None
    names = law_fit_params(law)
    law_names = REGISTRY["law"][law]["params"]
    fixed = dict(fixed or {})
    params0 = dict(params0 or {})
    bounds = dict(bounds or {})
    for key in fixed:
        if key in EXTRA_PARAMS:
            raise ValueError(f"fixed: give {key} as its own argument ({key}=value), not in fixed")
    extras = {name: _extra_option(name, value) for name, value in
              (("backlash", backlash), ("asymmetry", asymmetry), ("offset", offset), ("drift", drift))}
    per_record = [name for name, value in extras.items() if value == "per_record"]
    names += tuple(f"{name}[{i}]" for name in per_record for i in range(len(data)))
    _check_keys("fixed", fixed, law_names, law)
    _check_keys("params0", params0, names, law)
    _check_keys("bounds", bounds, names, law)
    fixed_all = {k: _in_range(f"fixed[{k!r}]", k, v, force_levels) for k, v in fixed.items()}
    for a, b in ORDERED_PAIRS:
        if a in fixed_all and b in fixed_all and not fixed_all[a] <= fixed_all[b]:
            raise ValueError(f"fixed: {a} = {fixed_all[a]!r} must be <= {b} = {fixed_all[b]!r}")
    for k in DISCRETE_PARAMS.intersection(law_names) - fixed.keys():
        fixed_all[k] = float(REGISTRY["param"][k]["default"])
    fixed_all.update({k: (EXTRA_DEFAULTS[k] if v == "per_record" else v) for k, v in extras.items() if v is not None})
    free = tuple(n for n in names if n not in fixed_all)
    for what, given in (("params0", params0), ("bounds", bounds)):
        clash = [k for k in given if k in fixed_all]
        if clash:
            raise ValueError(f"{what}: {', '.join(map(repr, clash))} is fixed, so it has no {what}")
    if not free:
        raise ValueError("fixed: every parameter is fixed; nothing to fit")
    if not (isinstance(n_starts, (int, np.integer)) and n_starts >= 1):
        raise ValueError(f"n_starts: must be an integer >= 1, got {n_starts!r}")
    if calibrate and len(data) < 2:
        raise ValueError(f"calibrate: needs several records to hold one out, got {len(data)}")
    if not (isinstance(interval, str) and interval in INTERVAL_METHODS):
        raise ValueError(f"interval: must be one of {', '.join(INTERVAL_METHODS)}, got {interval!r}")
    method = interval if interval != "auto" else ("profile" if REGISTRY["law"][law]["n_states"] == 0 else "wald")
    diff_step = _finite("diff_step", diff_step, "in (0, 0.1]")
    if not 0.0 < diff_step <= 0.1:
        raise ValueError(f"diff_step: must be in (0, 0.1], got {diff_step!r}")
    n_total = sum(d.t.size for d in data)
    k = len(free)
    all_forces = np.concatenate([d.force for d in data])
    if not np.ptp(all_forces) > 0.0:
        raise ValueError(f"force: every sample is {float(all_forces[0])!r} N; a constant force cannot identify a "
                         "friction law (record one along a motion that reverses)")
    if n_total < k + 2:
        raise ValueError(f"t: {n_total} samples cannot determine {k} parameters and the noise "
                         f"(at least {k + 2} needed)")

    # starts, bounds and the scaled coordinates
    scales = _data_scales(data)
    asym_free = "asymmetry" in free or "asymmetry" in per_record
    p0 = np.array([_in_range(f"params0[{n!r}]", n, params0[n], force_levels) if n in params0
                   else _start(_base(n), scales, asym_free) for n in free])
    # a parameter starting at 0 gets the size of what it can do: an offset a hundredth of the
    # force's range, a drift that moves the level by 1 % over the longest record
    typical = {"offset": 0.01 * float(np.ptp(all_forces)),
               "drift": 0.01 / max(float(d.t[-1] - d.t[0]) for d in data)}
    space, q_lo, q_hi, u0 = _coordinates(free, p0, bounds, fixed_all, typical)

    fixed_params = dict(fixed_all)
    forces = np.concatenate([d.force for d in data])

    def params_of(u: np.ndarray) -> dict[str, float]:
        p = dict(fixed_params)
        p.update(zip(free, space.to_params(u).tolist()))
        return {name: p[name] for name in names}

    # the last evaluation: its point, residuals and substeps (the mesh the Jacobian freezes);
    # the point of the last Jacobian the same (the optimiser's end, usually)
    last: dict[str, Any] = {}
    at_jacobian: dict[str, Any] = {}

    n_evals = [0]          # model evaluations (all of them: the budget of interval="auto")

    def residuals(u: np.ndarray, meshes: list[np.ndarray] | None = None) -> np.ndarray:
        n_evals[0] += 1
        p = params_of(u)
        parts = [_model_mesh(law, d, _record_params(p, i), rtol, None if meshes is None else meshes[i])
                 for i, d in enumerate(data)]
        r = np.concatenate([f for f, _ in parts]) - forces
        if meshes is None:
            last.update(u=u.copy(), r=r, meshes=[m for _, m in parts])
        return r

    def mesh_at(u: np.ndarray) -> tuple[np.ndarray, list[np.ndarray]]:
        """Residuals at u and the substeps of its state integration."""
        for known in (last, at_jacobian):
            if "u" in known and np.array_equal(known["u"], u):
                return known["r"], known["meshes"]
        residuals(u)
        return last["r"], last["meshes"]

    def jacobian(u: np.ndarray) -> np.ndarray:
        """Forward differences (scipy's 2-point scheme and step: diff_step |u|, sqrt(eps) max(1,
        |u|) at u = 0, backward where the bound is crossed) of the model on the substeps of the integration at u, frozen:
        a smooth function of the parameters, whose differences measure the model and not the
        step-doubling choices; each column costs one sweep, no doubling test."""
        r0, meshes = mesh_at(u)
        at_jacobian.update(u=u.copy(), r=r0, meshes=meshes)
        jac = np.empty((r0.size, u.size))
        for i in range(u.size):
            sign = 1.0 if u[i] >= 0.0 else -1.0
            h = diff_step * sign * abs(u[i])
            if (u[i] + h) - u[i] == 0.0:
                h = math.sqrt(np.finfo(float).eps) * sign * max(1.0, abs(u[i]))
            if u[i] + h > q_hi[i] or u[i] + h < q_lo[i]:
                h = -h
            w = u.copy()
            w[i] = u[i] + h
            h = w[i] - u[i]
            try:
                jac[:, i] = (residuals(w, meshes) - r0) / h
            except (RuntimeError, ValueError):
                jac[:, i] = 0.0
        return jac

    # A trial point the model rejects (the state integration fails, e.g. an implicit law's
    # Newton iteration far from the data, or a law's own limit beyond the registry's range,
    # such as LuGre's mu_k > 0) counts as a very bad fit: the trust region shrinks away from it.
    penalty = np.full(forces.size, 100.0 * float(np.ptp(forces)) + 1.0)

    def trial_residuals(u: np.ndarray) -> np.ndarray:
        if "u" in last and np.array_equal(last["u"], u):      # the start, checked below
            return last["r"].copy()
        try:
            return residuals(u)
        except (RuntimeError, ValueError):
            return penalty

    try:
        residuals(u0)
    except (RuntimeError, ValueError) as exc:
        raise ValueError(f"params0: the model of {law!r} fails at the start "
                         f"{dict(zip(free, space.to_params(u0).tolist()))} ({exc}); give other starting values") from None

    # starts: the data's, then log-uniform draws within x/10 .. x10 of it, inside the bounds
    rng = np.random.default_rng(seed)
    starts = [u0]
    lo_inside = q_lo.copy()
    finite = np.isfinite(q_lo)
    lo_inside[finite] += 1e-12 * np.abs(q_lo[finite])
    for _ in range(int(n_starts) - 1):
        factor = np.exp(rng.uniform(-math.log(10.0), math.log(10.0), k))
        starts.append(np.clip(u0 * factor, lo_inside, q_hi))
    if "backlash" in free and "backlash" not in params0 and REGISTRY["law"][law]["n_states"] == 0:
        starts += _backlash_starts(trial_residuals, u0, free.index("backlash"), space.scale,
                                   scales["amplitude"], q_lo, q_hi)
    max_nfev = max_nfev or 30 * k
    best = None
    costs = []
    nfev = 0
    best_start = u0

    def local(u_start: np.ndarray, hold: bool = False) -> Any:
        """A local search from u_start (moved strictly inside the bounds, trf's requirement).
        `hold`: the coordinates of u_start on a bound stay there (a search on that face of the
        box)."""
        held = ((u_start <= q_lo) | (u_start >= q_hi)) if hold else np.zeros(k, bool)
        moved = ~held
        lo, hi = q_lo[moved], q_hi[moved]
        inner = np.minimum(np.maximum(u_start[moved], np.nextafter(lo, np.inf)), np.nextafter(hi, -np.inf))
        if not held.any():
            return least_squares(trial_residuals, inner, jac=jacobian, bounds=(lo, hi), method="trf",
                                 x_scale=1.0, max_nfev=max_nfev)

        def whole(w: np.ndarray) -> np.ndarray:
            u = u_start.copy()
            u[moved] = w
            return u
        sol = least_squares(lambda w: trial_residuals(whole(w)), inner, jac=lambda w: jacobian(whole(w))[:, moved],
                            bounds=(lo, hi), method="trf", x_scale=1.0, max_nfev=max_nfev)
        jac = np.zeros((sol.fun.size, k))       # the held coordinates' columns unknown: 0
        jac[:, moved] = sol.jac
        sol.x, sol.jac = whole(sol.x), jac
        return sol

    def restart(u_start: np.ndarray, cost: float, gain: float) -> Any:
        """A local search from a point lower than the best end (of cost `cost`) by more than
        `gain` [N^2]; where it ends higher than that and the point has coordinates on a bound,
        the search on that face of the box (the cost may jump just inside a bound: a LuGre
        backlash of exactly 0 against 1e-12 m, 136 reduced chi-squares apart on the damper's
        records, so the search moved inside starts far above the point)."""
        nonlocal nfev
        sol = local(u_start)
        nfev += int(sol.nfev)
        if 2.0 * (cost - sol.cost) <= gain and ((u_start <= q_lo) | (u_start >= q_hi)).any():
            face = local(u_start, hold=True)
            nfev += int(face.nfev)
            sol = face if face.cost < sol.cost else sol
        return sol

    with _one_blas_thread():
        for u_start in starts:
            sol = local(u_start)
            nfev += int(sol.nfev)
            costs.append(float(sol.cost))
            if best is None or sol.cost < best.cost:
                best, best_start = sol, u_start
        assert best is not None
        # a cheap probe about the end; a lower point found starts a second local search
        # (a decrease below the state integration's own error, (rtol x force range)^2 a sample,
        # is no lower point); the profiles of the intervals may find one too: a search from it.
        # Each search starts at a point lower than the best end by more than `needed` (on the
        # face of the box its coordinates on a bound are on, where the search moved inside ends
        # higher: `restart`): the restarts go on while they lower the cost by that much,
        # MAX_RESTARTS at most
        restarts = 0
        floor = n_total * (rtol * float(np.ptp(all_forces))) ** 2
        progress = True
        while True:
            r_end = residuals(best.x)
            s2_end = float(r_end @ r_end) / max(n_total - k, 1)
            probe = _probe(residuals, best.x, r_end, best.jac, q_lo, q_hi, s2_end, free)
            needed = max(PROBE_GAIN * s2_end, floor)
            if probe[0] > needed and restarts < MAX_RESTARTS and progress:
                restarts += 1
                sol = restart(probe[1], best.cost, needed)
                progress = 2.0 * (best.cost - sol.cost) > needed
                if sol.cost < best.cost:
                    best = sol
                continue
            meshes = mesh_at(best.x)[1]
            # (the warnings of an end that a restart then leaves are not the fit's: only the
            # last end's are raised, below)
            with warnings.catch_warnings(record=True) as said:
                warnings.simplefilter("always")
                result = _statistics(law, best, space, params_of, residuals, forces, data, q_lo, q_hi,
                                     force_levels, normal_force, nfev, tuple(costs), diff_step, rtol,
                                     frozen=lambda w, m=meshes: residuals(w, m), interval=method,
                                     profile_budget=n_evals[0] if interval == "auto" else None,
                                     probe=(probe[0], probe[2], restarts, needed))
            if result._lower_point is None or restarts >= MAX_RESTARTS or not progress:
                break
            restarts += 1
            sol = restart(result._lower_point, best.cost, needed)
            progress = 2.0 * (best.cost - sol.cost) > needed
            if sol.cost < best.cost:
                best = sol
    for w in said:
        warnings.warn(w.message, w.category, stacklevel=2)
    result.restarts, result.probe_gain = restarts, probe[0]
    result.rtol = rtol
    result.start = dict(zip(free, space.to_params(best_start).tolist()))
    result.n_evaluations = n_evals[0]
    result.bounds = _physical_bounds(space, q_lo, q_hi, result.params)
    if calibrate:
        def fold(members: list[_Data]) -> FitResult:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                return fit_friction(
                    law, [m.t for m in members], [m.x for m in members], [m.force for m in members],
                    v=None if any(m.v is None for m in members) else [m.v for m in members],
                    normal_force=None if force_levels else [m.normal_force for m in members],
                    fixed=fixed, params0=params0, bounds=bounds, backlash=backlash, asymmetry=asymmetry,
                    offset=offset, drift=drift, n_starts=n_starts, seed=seed, max_nfev=max_nfev, rtol=rtol,
                    diff_step=diff_step, interval="wald")
        result.heldout_residuals = _cross_validate(law, data, None, fold)[1]
    return result


#: Backlash widths, as fractions of the records' amplitude, at which the cost of a static law
#: is evaluated (the other parameters at their start) to pick extra starts.
BACKLASH_GRID: tuple[float, ...] = (0.0, 0.003, 0.01, 0.03, 0.1, 0.2, 0.3, 0.45)
#: Extra starts taken from that scan (the lowest costs).
BACKLASH_STARTS: int = 2


def _backlash_starts(cost_of: Any, u0: np.ndarray, i: int, scale: np.ndarray, amplitude: float,
                     q_lo: np.ndarray, q_hi: np.ndarray) -> list[np.ndarray]:
    """Extra starts of a static law's fit with the backlash fitted: its sum of squares is a
    staircase in the backlash (a sample enters or leaves the play), on which a local search
    started at one width stays near it. The cost at each width of BACKLASH_GRID (the other
    parameters at the start `u0`) is evaluated; the BACKLASH_STARTS lowest give starts."""
    tried = []
    for frac in BACKLASH_GRID:
        u = u0.copy()
        u[i] = min(max(frac * amplitude / scale[i], q_lo[i]), q_hi[i])
        if abs(u[i] - u0[i]) <= 1e-12 * max(abs(u0[i]), 1.0):
            continue
        r = cost_of(u)
        tried.append((float(r @ r), u))
    tried.sort(key=lambda c: c[0])
    return [u for _, u in tried[:BACKLASH_STARTS]]


#: A point found by `_probe` whose sum of squares is lower than the end's by more than this
#: many reduced chi-squares (s^2) is "a lower point nearby": the fit restarts from it.
PROBE_GAIN: float = 1.0
#: Most local searches restarted from a lower point found by the probe or a profile (the
#: restarts stop sooner when one does not lower the cost by more than PROBE_GAIN s^2). On the
#: damper's ten 36 lb records Drake continuous took 7 (3 stopped it 12.9 s^2 short along v_s).
MAX_RESTARTS: int = 8


def _probe(residuals: Any, u: np.ndarray, r: np.ndarray, jac: np.ndarray, q_lo: np.ndarray,
           q_hi: np.ndarray, s2: float, free: Sequence[str]) -> tuple[float, np.ndarray, str]:
    """A cheap search for a lower point near the end u of a local search (residuals r,
    Jacobian jac in the optimiser's coordinates, s2 the reduced chi-square): a Gauss-Newton
    step (whole, 0.3, 0.1; shortened so that no coordinate moves by more than half of it) and
    a step of two standard errors (s2 (J^T J)^+, at most half the coordinate) up and down each
    coordinate, within the bounds; 3 + 2k model evaluations. At a
    least-squares minimum none lowers the sum of squares (the coordinate steps raise it by
    about 4 s^2 or more). Returns the largest decrease [N^2], its point and what found it."""
    ssr = float(r @ r)
    tries = []
    jac = np.asarray(jac, dtype=float)
    if jac.shape == (r.size, u.size) and np.isfinite(jac).all():
        # every step at most half a coordinate (or 0.5 where it is below 1), so that the probe
        # stays near the end: along a flat valley the whole Gauss-Newton step can reach a bound
        # far away (a stiffness 1000 times its start), where the states may be slow to integrate
        reach = 0.5 * np.maximum(np.abs(u), 1.0)
        step = np.linalg.lstsq(jac, -r, rcond=None)[0]
        step *= min(1.0, float(np.min(reach / np.maximum(np.abs(step), 1e-300))))
        tries += [(u + lam * step, "a Gauss-Newton step") for lam in (1.0, 0.3, 0.1)]
        sd = np.sqrt(np.maximum(s2 * np.diag(np.linalg.pinv(jac.T @ jac)), 0.0))
        sd = np.minimum(sd, reach)
        for i in range(u.size):
            for sgn in (1.0, -1.0):
                w = u.copy()
                w[i] += sgn * 2.0 * sd[i]
                tries.append((w, f"a step of two standard errors along {free[i]}"))
    gain, best, how = 0.0, u, ""
    for w, what in tries:
        w = np.clip(w, q_lo, q_hi)
        if np.array_equal(w, u):
            continue
        try:
            rw = residuals(w)
        except (RuntimeError, ValueError):
            continue
        if ssr - float(rw @ rw) > gain:
            gain, best, how = ssr - float(rw @ rw), w, what
    return gain, best, how


def _physical_bounds(space: _Space, q_lo: np.ndarray, q_hi: np.ndarray,
                     params: Mapping[str, float]) -> dict[str, tuple[float, float]]:
    """The bounds of the free parameters as the fit applied them, in their own units (the
    upper member of a fitted ordered pair: from the lower member's estimate up)."""
    out = {}
    for i, name in enumerate(space.free):
        lo, hi = float(q_lo[i] * space.scale[i]), float(q_hi[i] * space.scale[i])
        if i in space.lower_of:
            base = params[space.free[space.lower_of[i]]]
            lo, hi = base + lo, base + hi
        out[name] = (lo, hi)
    return out


def _interval(name: str, value: float, sd: float, tq: float,
              limits: tuple[float, float] | None = None) -> tuple[float, float]:
    """The interval value +- tq sd, taken on a scale on which the parameter's accepted range
    is the whole line, so that it stays inside it: log(p - low) for a range bounded below,
    the logit of (p - low)/(high - low) for one bounded on both sides, p itself otherwise
    (the delta method: the same width to first order where sd is small). A value nearer a
    bound than tq sd gets the plain interval cut at the bound. `limits` (low, high): the range
    instead of the library's for `name` (the upper member of an ordered pair: above the
    lower one)."""
    if limits is not None:
        low, high = limits
    elif _base(name) in EXTRA_PARAMS or _base(name) in REGISTRY["param"]:
        low, high = _range_of(name)[:2]
    else:
        low, high = -math.inf, math.inf
    if not math.isfinite(sd):
        return (low, high)
    # nearer a bound than the plain half-width: the plain interval, cut at the bound (a log or
    # logit scale would stretch the far end without limit)
    if value - low < tq * sd or high - value < tq * sd:
        return (max(low, value - tq * sd), min(high, value + tq * sd))
    if math.isfinite(low) and math.isfinite(high) and low < value < high:
        w = high - low
        y = (value - low) / w
        h = tq * sd / (w * y * (1.0 - y))
        lg = math.log(y / (1.0 - y))
        return (low + w / (1.0 + math.exp(-(lg - h))), low + w / (1.0 + math.exp(-(lg + h))))
    if math.isfinite(low) and value > low:
        h = tq * sd / (value - low)
        return (low + (value - low) * math.exp(-min(h, 700.0)), low + (value - low) * math.exp(min(h, 700.0)))
    return (value - tq * sd, value + tq * sd)


def _wald_intervals(space: _Space, pv: np.ndarray, sd: np.ndarray, tq: float) -> dict[str, tuple[float, float]]:
    """The Wald intervals (`_interval`) of the free parameters `pv` with standard errors `sd`.
    The upper member of an ordered pair whose lower member is fitted too (mu_s over mu_k, v_d
    over v_s) ranges over (lower, inf): its interval is taken on the log of its excess over the
    lower member's estimate. (Its standard error grows with that excess: LuGre's mu_s over 1000
    synthetic draws with a backlash, 10 N of noise, missed low in 75 draws, all with estimates
    below the truth and small standard errors, on the log of mu_s itself; 48 on the excess's.)"""
    ci = {}
    for i, name in enumerate(space.free):
        base = float(pv[space.lower_of[i]]) if i in space.lower_of else None
        if base is None:
            ci[name] = _interval(name, float(pv[i]), float(sd[i]), tq)
            continue
        lo, hi = _interval(name, float(pv[i]) - base, float(sd[i]), tq, limits=(0.0, math.inf))
        ci[name] = (base + lo, base + hi)
    return ci


#: The ways `fit_friction` makes the parameters' 95 % intervals (see its `interval`).
INTERVAL_METHODS: tuple[str, ...] = ("auto", "wald", "profile")
#: Tolerance of a profile-likelihood interval's end: the profile statistic there within this
#: fraction of its target t(0.975, n - k).
PROFILE_TOL: float = 0.03
#: Farthest a profile search goes from the estimate, in Wald half-widths (t stderr), before it
#: counts the side as not determined by the data.
PROFILE_REACH: float = 50.0
#: Largest number of points a profile's search of one end evaluates.
PROFILE_ITERATIONS: int = 10
#: Largest number of chord Gauss-Newton steps of the refit at one point of a profile.
PROFILE_STEPS: int = 5


def _profile_intervals(residuals: Any, r_hat: np.ndarray, jac_p: np.ndarray, space: _Space,
                       q_lo: np.ndarray, q_hi: np.ndarray, p_hat: np.ndarray, sd: np.ndarray, tq: float,
                       var_unit: float, budget: int | None = None, only: set[int] | None = None
                       ) -> tuple[dict[int, tuple[float, float]], set[int], set[int], int, tuple]:
    """Profile-likelihood 95 % intervals of the free parameters.

    For parameter i held at c, the others are refitted (chord Gauss-Newton: the Jacobian
    `jac_p` [d r / d p] of the optimum held, at most PROFILE_STEPS steps, each one model
    evaluation, within the bounds); the profile statistic is tau(c) = sqrt((S(c) - S_min) /
    var_unit), var_unit = s^2 times the variance inflation, and each end of the interval is the
    c where tau = tq (secant search from the Wald end p_i +- tq sd). The refit's S is an upper
    bound of the true profile's (the chord steps may stop short), so an interval is at most
    as wide as the exact profile one. `residuals` takes the optimiser's coordinates u.

    Returns the intervals (index -> (lower, upper)), the indices whose interval reached a
    bound of the range (the data cannot tell the parameter from it), those whose interval is
    unbounded on a side with no bound (not determined by the data), and the number of model
    evaluations used, and the lowest sum of squares a refit reached with the parameter it held,
    its value and the parameters there (below the optimum's: the fit stopped short of a
    minimum). A parameter whose sd is not finite is left out, and so are the parameters after
    the evaluations exceed `budget` (given) and those not in `only` (given)."""
    k = p_hat.size
    ssr0 = float(r_hat @ r_hat)
    with np.errstate(invalid="ignore"):
        lim_lo = space.to_params(np.where(np.isfinite(q_lo), q_lo, -np.inf))
        lim_hi = space.to_params(np.where(np.isfinite(q_hi), q_hi, np.inf))
    evals = 0
    lowest: tuple[float, str, float, np.ndarray | None] = (ssr0, "", math.nan, None)

    def place(p: np.ndarray, i: int) -> np.ndarray | None:
        """Coordinates u of p with p_i kept, the others moved into the bounds; None when p_i
        cannot be kept (beyond what the bounds of an ordered pair allow)."""
        u = np.clip(space.from_params(p), q_lo, q_hi)
        if i in space.lower_of:      # p_i = excess + lower: move the lower member to keep p_i
            lo_i = space.lower_of[i]
            u[lo_i] = np.clip((p[i] - space.scale[i] * u[i]) / space.scale[lo_i], q_lo[lo_i], q_hi[lo_i])
            u[i] = np.clip((p[i] - space.scale[lo_i] * u[lo_i]) / space.scale[i], q_lo[i], q_hi[i])
        q = space.to_params(u)
        return u if abs(q[i] - p[i]) <= 1e-9 * max(abs(p[i]), 1e-300) else None

    def refit(i: int, c: float, p_start: np.ndarray) -> tuple[float, np.ndarray] | None:
        nonlocal evals, lowest
        others = np.array([j for j in range(k) if j != i], dtype=int)
        pinv = np.linalg.pinv(jac_p[:, others], rcond=1e-10) if others.size else np.zeros((0, r_hat.size))
        p = p_start.copy()
        p[i] = c
        u = place(p, i)
        if u is None:
            return None
        p = space.to_params(u)
        try:
            r = residuals(u)
        except (RuntimeError, ValueError):
            return None
        evals += 1
        ssr = float(r @ r)
        for _ in range(PROFILE_STEPS):
            if not others.size:
                break
            d = -(pinv @ r)
            accepted = False
            for lam in (1.0, 0.5, 0.25):
                trial = p.copy()
                trial[others] += lam * d
                w = place(trial, i)
                if w is None:
                    continue
                try:
                    rw = residuals(w)
                except (RuntimeError, ValueError):
                    continue
                evals += 1
                sw = float(rw @ rw)
                if sw < ssr:
                    gain = ssr - sw
                    p, r, ssr, accepted = space.to_params(w), rw, sw, True
                    break
            if not accepted or gain < 0.01 * var_unit:
                break
        if ssr < lowest[0]:
            lowest = (ssr, space.free[i], c, p.copy())
        return ssr, p

    def side(i: int, sgn: float) -> tuple[float, str]:
        """The end of the interval of parameter i on side sgn, and 'ok', 'bound' (the range's
        bound reached below the target) or 'open' (no bound and no end within reach).
        Outward steps (secant, at most fourfold) until tau exceeds the target, then regula
        falsi within the bracket (inner point below the target, outer above); not converged,
        the outer end (the wider interval)."""
        lim = lim_hi[i] if sgn > 0 else lim_lo[i]
        reach = PROFILE_REACH * tq * sd[i]
        inner, tau_in, p_start = p_hat[i], 0.0, p_hat
        outer, tau_out = None, math.inf
        c = p_hat[i] + sgn * tq * sd[i]
        lim_tried = False
        for _ in range(PROFILE_ITERATIONS):
            at_lim = (c >= lim) if sgn > 0 else (c <= lim)
            if at_lim:
                c = lim
                lim_tried = True
            out = refit(i, c, p_start) if math.isfinite(c) else None
            if out is None:         # the model fails there: nearer
                c = 0.5 * (c + inner) if math.isfinite(c) else inner + sgn * 4.0 * abs(inner - p_hat[i])
                continue
            ssr, p_found = out
            tau = math.sqrt(max(ssr - ssr0, 0.0) / var_unit)
            if abs(tau - tq) <= PROFILE_TOL * tq:
                return c, "ok"
            if tau < tq:
                if at_lim:
                    return lim, "bound"
                inner, tau_in, p_start = c, tau, p_found
            else:
                outer, tau_out = c, tau
            if outer is not None:       # bracketed: regula falsi, kept off the bracket's ends
                w = outer - inner
                c = inner + w * min(max((tq - tau_in) / (tau_out - tau_in), 0.1), 0.9)
                continue
            dist = abs(c - p_hat[i])
            grow = 4.0 if tau <= 0.0 else min(max(tq / tau, 1.25), 4.0)
            c = p_hat[i] + sgn * grow * dist
            if abs(c - p_hat[i]) > reach and not lim_tried:
                # beyond reach: the range's bound, if any, decides (below the target there: the
                # data cannot tell the parameter from it; above: the end lies between)
                if math.isfinite(lim):
                    c = lim
                    continue
                return sgn * math.inf, "open"
        if outer is not None:
            return outer, "ok"
        return (lim, "bound") if lim_tried else (sgn * math.inf if not math.isfinite(lim) else lim,
                                                  "open" if not math.isfinite(lim) else "bound")

    out: dict[int, tuple[float, float]] = {}
    bound: set[int] = set()
    open_: set[int] = set()
    for i in range(k):
        if not (math.isfinite(sd[i]) and sd[i] > 0.0) or (only is not None and i not in only):
            continue
        if budget is not None and evals >= budget:
            break
        lo, how_lo = side(i, -1.0)
        hi, how_hi = side(i, 1.0)
        out[i] = (float(lo), float(hi))
        if "bound" in (how_lo, how_hi):
            bound.add(i)
        if "open" in (how_lo, how_hi):
            open_.add(i)
    return out, bound, open_, evals, lowest


def _central_jacobian(residuals: Any, u: np.ndarray, q_lo: np.ndarray, q_hi: np.ndarray,
                      step: float, floor: float = 0.0, reference: np.ndarray | None = None) -> np.ndarray:
    """d residuals / d u by central differences (one-sided at a bound), step `step` |u| (at
    least step 1e-3). The step grows tenfold, up to 0.1 max(|u|, 1), while the change of the
    residuals is below `floor` (the integration's own error) or the derivative still differs
    by more than 10 % from the one at the tenfold step: the difference must measure the model,
    not the integrator's step-doubling decisions (a parameter near 0, such as a backlash, got
    a near-infinite derivative from them, and a near-zero standard error).

    `reference`: the optimiser's last Jacobian at u (forward differences of the same
    residuals). A column then starts at the first step of the same tenfold ladder whose
    change the reference predicts to reach the floor, skipping the steps the search would
    reject for a change below it (four evaluations a column instead of six to eight, the same
    step kept)."""
    def column(i: int, h: float) -> tuple[np.ndarray, float]:
        up, down = u.copy(), u.copy()
        up[i] = min(u[i] + h, q_hi[i])
        down[i] = max(u[i] - h, q_lo[i])
        diff = residuals(up) - residuals(down)
        return diff / (up[i] - down[i]), float(np.abs(diff).max())

    jac = np.empty((reference.shape[0] if reference is not None else residuals(u).size, u.size))
    for i in range(u.size):
        h = step * max(abs(u[i]), 1e-3)
        cap = 0.1 * max(abs(u[i]), 1.0)
        if reference is not None and floor > 0.0:
            # start at the first step of the tenfold ladder whose change the reference
            # predicts (2 h max|J_i|) to reach the floor: the steps below it would be rejected
            slope = float(np.abs(reference[:, i]).max())
            if slope > 0.0:
                decades = max(math.ceil(math.log10(floor / (2.0 * h * slope))), 0)
                while decades > 0 and h * 10.0 ** decades >= cap:
                    decades -= 1
                h *= 10.0 ** decades
        d, change = column(i, h)
        if 0.0 < change < floor:
            # the change grows in proportion to the step: skip the tenfold steps whose change
            # would still be below the floor (they would be rejected; two evaluations each)
            jump = 10.0 ** max(math.ceil(math.log10(floor / change)) - 1, 0)
            if jump > 1.0 and h * jump < cap:
                h *= jump
                d, change = column(i, h)
        while h < cap:
            d10, change10 = column(i, min(10.0 * h, cap))
            if change >= floor and np.linalg.norm(d - d10) <= 0.1 * np.linalg.norm(d10):
                break
            h, d, change = min(10.0 * h, cap), d10, change10
        jac[:, i] = d
    return jac


def _statistics(law: str, sol: Any, space: _Space, params_of: Any, residuals: Any, forces: np.ndarray,
                data: list[_Data], q_lo: np.ndarray, q_hi: np.ndarray, force_levels: bool,
                normal_force: Any, nfev: int, costs: tuple[float, ...], step: float,
                rtol: float = 1e-6, frozen: Any = None, interval: str = "wald",
                profile_budget: int | None = None,
                probe: tuple[float, str, int, float] = (0.0, "", 0, 0.0)) -> FitResult:
    """Covariance, intervals and scores at the optimum (see the module notes). `frozen`: the
    residuals on the substeps of the integration at the optimum (for the Jacobian and the
    profiles; default `residuals`). `interval`: "wald" (on the transformed scale, `_interval`)
    or "profile" (`_profile_intervals`, within `profile_budget` model evaluations if given)."""
    from scipy import stats

    u = sol.x
    free = space.free
    k = len(free)
    r = (frozen or residuals)(u)      # the frozen mesh at u reproduces the adaptive model there
    n = r.size
    ssr = float(r @ r)
    dof = n - k
    s2 = ssr / dof
    reference = getattr(sol, "jac", None)
    reference = reference if isinstance(reference, np.ndarray) and reference.shape == (n, k) else None
    jac_u = _central_jacobian(frozen or residuals, u, q_lo, q_hi, 0.1 * step,
                              floor=100.0 * rtol * float(np.ptp(forces)), reference=reference)
    # in the physical parameters: J_p = J_u (dp/du)^-1, cov_p = s2 (J_p^T J_p)^+
    jac_p = jac_u @ np.linalg.inv(space.matrix())
    col = np.linalg.norm(jac_p, axis=0)
    col[col == 0.0] = 1.0
    jn = jac_p / col
    _, sv, vt = np.linalg.svd(jn, full_matrices=False)
    keep = sv > sv[0] * 1e-10 if sv.size and sv[0] > 0.0 else np.zeros(k, bool)
    cov_n = (vt[keep].T / sv[keep] ** 2) @ vt[keep]
    # residuals correlated in time (lag-1 correlation rho within each record) carry less
    # information than as many independent ones: the covariance of an AR(1) mean is larger by
    # (1 + rho)/(1 - rho), applied here to every parameter (rho < 0 is not credited)
    ends = np.cumsum([d.t.size for d in data])
    same = np.ones(n - 1, bool)
    same[ends[:-1] - 1] = False
    rho = float((r[:-1] * r[1:])[same].sum() / ssr) if ssr > 0.0 and n > 2 else 0.0
    rho_c = min(max(rho, 0.0), 0.99)
    inflation = (1.0 + rho_c) / (1.0 - rho_c)
    cov = inflation * s2 * cov_n / np.outer(col, col)
    var = np.diag(cov).copy()
    # a direction the data does not see: the parameters in it have no finite error
    null = vt[~keep]
    undetermined = (np.abs(null) > 1e-6).any(axis=0) if null.size else np.zeros(k, bool)
    var[undetermined] = np.inf
    sd = np.sqrt(np.maximum(var, 0.0))
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov / np.outer(np.sqrt(np.diag(cov)), np.sqrt(np.diag(cov)))
    corr[undetermined, :] = np.nan
    corr[:, undetermined] = np.nan
    tq = float(stats.t.ppf(0.975, dof))
    p = params_of(u)
    pv = space.to_params(u)
    ci = _wald_intervals(space, pv, sd, tq)
    prof_bound: set[int] = set()
    prof_open: set[int] = set()
    profile_evals = 0
    profiled: tuple[str, ...] = ()
    lowest: tuple = (ssr, "", math.nan, None)
    if interval == "profile" and ssr > 0.0:
        prof, prof_bound, prof_open, profile_evals, lowest = _profile_intervals(
            frozen or residuals, r, jac_p, space, q_lo, q_hi, pv, sd, tq, inflation * s2, profile_budget)
        ci.update({free[i]: ends for i, ends in prof.items()})
        profiled = tuple(free[i] for i in sorted(prof))
    tol = 1e-6
    # on a bound, or nearer to it than the half-width of a plain interval (the bound is then
    # inside estimate +- t sd: the data cannot tell the estimate from the bound)
    scale = space.scale

    def near_bound(i: int) -> bool:
        return bool((math.isfinite(q_lo[i]) and (u[i] - q_lo[i] <= tol * max(1.0, abs(q_lo[i]))
                                                 or (u[i] - q_lo[i]) * scale[i] <= tq * sd[i]))
                    or (math.isfinite(q_hi[i]) and (q_hi[i] - u[i] <= tol * max(1.0, abs(q_hi[i]))
                                                    or (q_hi[i] - u[i]) * scale[i] <= tq * sd[i])))

    # A parameter near a bound has a Wald interval that means little there (the cost is not
    # quadratic up to the bound: a backlash at 0 has a near-zero slope and a standard error
    # as large as the amplitude): its interval is its profile, one-sided at the bound.
    near = {i for i in range(k) if near_bound(i) and math.isfinite(sd[i]) and free[i] not in profiled}
    if near and ssr > 0.0:
        prof, bound_b, open_b, evals_b, lowest_b = _profile_intervals(
            frozen or residuals, r, jac_p, space, q_lo, q_hi, pv, sd, tq, inflation * s2, only=near)
        ci.update({free[i]: ends for i, ends in prof.items()})
        prof_bound |= bound_b
        prof_open |= open_b
        profile_evals += evals_b
        lowest = min(lowest, lowest_b, key=lambda low: low[0])
        profiled = tuple(name for i, name in enumerate(free) if name in profiled or i in prof)
    at_bound = tuple(name for i, name in enumerate(free) if near_bound(i) or i in prof_bound)
    if undetermined.any():
        warnings.warn(f"fit of {law!r}: the data do not determine {', '.join(np.array(free)[undetermined])} "
                      "(stderr inf); fix them or use records that excite them", stacklevel=3)
    # Is this a minimum? The cosine between the residual and each free parameter's column of
    # the Jacobian (not at a bound) is 0 at a least-squares minimum: a large one means the
    # optimiser stopped on a tolerance (or its evaluation budget) on a slope.
    rn = math.sqrt(ssr)
    jn_cols = np.linalg.norm(jac_u, axis=0)
    inside = np.array([name not in at_bound for name in free])
    with np.errstate(invalid="ignore", divide="ignore"):
        cosines = np.abs(jac_u.T @ r) / (jn_cols * rn)
    cosines = np.where(inside & (jn_cols > 0.0) & np.isfinite(cosines), cosines, 0.0)
    optimality = float(cosines.max()) if cosines.size and rn > 0.0 else 0.0
    problems = []
    if sol.status == 0:
        problems.append(f"the optimiser used its evaluation budget (max_nfev) and stopped")
    gain, how, restarts, needed = probe
    lower_point = None
    if gain > needed:
        problems.append(f"the optimiser stopped far from a minimum: {how} from its end lowers the sum of "
                        f"squares by {gain:.4g} N^2 ({gain / s2:.3g} reduced chi-squares) after {restarts} "
                        "restart(s) from such points")
    elif ssr - lowest[0] > max(needed, PROBE_GAIN * s2):
        # the profiles evaluate the model on the optimum's frozen substeps, which may miss the
        # model's own value far from it (GMS's gms_shape at 400 times its estimate on the
        # damper's records: 3.8 s^2 lower there, at least 9 s^2 higher with its own substeps):
        # the point is lower only if the model itself (as the optimiser evaluates it) is
        point = np.clip(space.from_params(lowest[3]), q_lo, q_hi)
        try:
            r_low = residuals(point)
            ssr_low = float(r_low @ r_low)
        except (RuntimeError, ValueError):
            ssr_low = math.inf
        if ssr - ssr_low > max(needed, PROBE_GAIN * s2):
            lower_point = point
            problems.append(f"the optimiser stopped short of a minimum: the profile of {lowest[1]} found a sum of "
                            f"squares lower by {ssr - ssr_low:.4g} N^2 ({(ssr - ssr_low) / s2:.3g} reduced "
                            f"chi-squares) at {lowest[1]} = {lowest[2]:.6g} (its intervals are not valid)")
    zero_ssr = float(forces @ forces)
    if ssr >= (1.0 - ZERO_GAIN) * zero_ssr:
        problems.append(f"the fit is no better than predicting zero force (rmse {math.sqrt(ssr / n):.4g} N, "
                        f"rms force {math.sqrt(zero_ssr / n):.4g} N)")
    success = bool(sol.success) and not problems
    message = str(sol.message) if not problems else "; ".join(problems) + f" (optimiser: {sol.message})"
    if problems:
        warnings.warn(f"fit of {law!r} failed: {message}; try other params0, more n_starts or max_nfev",
                      RuntimeWarning, stacklevel=3)
    # -2 ln L at the ML variance; a fit with no residual at all (noise-free data the model
    # reproduces) has an unbounded likelihood: AIC and BIC are -inf
    loglik_term = n * math.log(2.0 * math.pi * ssr / n) + n if ssr > 0.0 else -math.inf
    n_par = k + 1
    # lmfit's definitions (its fit_report's "Akaike info crit" and "Bayesian info crit"): the
    # same likelihood without its constant n (1 + ln 2 pi), and k without the noise variance
    neg2_lmfit = n * math.log(ssr / n) if ssr > 0.0 else -math.inf
    rmse = math.sqrt(ssr / n)
    units = {name: parameter_unit(name, force_levels) for name in p}
    return FitResult(
        law=law, params=p, units=units, free=free,
        stderr={name: float(sd[i]) for i, name in enumerate(free)}, ci95=ci,
        covariance=cov, correlation=corr, rmse=rmse, nrmse=rmse / float(np.ptp(forces)),
        aic=loglik_term + 2.0 * n_par, bic=loglik_term + n_par * math.log(n), n_samples=n,
        n_records=len(data), force_levels=force_levels, normal_force=1.0 if force_levels else normal_force,
        at_bound=at_bound, cost=float(sol.cost), nfev=nfev, n_starts=len(costs), success=success,
        message=message, start_costs=costs, optimality=optimality, noise_correlation=rho,
        variance_inflation=inflation, residual_sd=math.sqrt(s2),
        undetermined=tuple(name for i, name in enumerate(free)
                           if not math.isfinite(sd[i]) or sd[i] > abs(pv[i]) or i in prof_open),
        profiled=profiled, profile_evals=profile_evals, chisqr=ssr, redchi=s2,
        aic_lmfit=neg2_lmfit + 2.0 * k, bic_lmfit=neg2_lmfit + k * math.log(n), _lower_point=lower_point)


# --------------------------------------------------------------------------------------------
# Choosing a law: cross-validation over records
# --------------------------------------------------------------------------------------------
def _decimated(d: _Data, per_cycle: int) -> _Data:
    """Record `d` decimated (`stickslip.data.decimate`) to about `per_cycle` samples per cycle
    of its fundamental (the largest peak of the spectrum of x, the mean removed)."""
    dt = float(np.median(np.diff(d.t)))
    spectrum = np.abs(np.fft.rfft(d.x - d.x.mean()))
    spectrum[0] = 0.0
    f0 = int(np.argmax(spectrum)) / (d.t.size * dt)
    step = max(1, int(1.0 / (f0 * dt * per_cycle))) if f0 > 0.0 else 1
    if step == 1:
        return d
    nf = d.normal_force
    t, (x, force, v, nf_d) = decimate(d.t, [d.x, d.force, d.v, None if np.ndim(nf) == 0 else nf], step)
    return _Data(t, x, v, force, nf if nf_d is None else nf_d)


def _record_params(params: Mapping[str, float], i: int) -> dict[str, float]:
    """The parameters of the model of record i of a fit: its own per-record terms (`name[i]`)
    in place of the common entries."""
    out = {k: v for k, v in params.items() if "[" not in k}
    out.update({_base(k): v for k, v in params.items() if k.endswith(f"[{i}]")})
    return out


def _new_record_params(params: Mapping[str, float]) -> dict[str, float]:
    """The parameters of the model of a record the fit has not seen: the per-record terms
    (`name[i]`, see `fit_friction`'s offset, drift, asymmetry "per_record") are not carried
    over; their common entry (at its default) stands."""
    return {k: v for k, v in params.items() if "[" not in k}


def _cross_validate(law: str, parts: list[_Data], labels: Sequence[Any] | None,
                    fit_fold: Any, scored: list[_Data] | None = None) -> tuple[list[float], np.ndarray, int]:
    """Fold by fold, `fit_fold(members)` on all parts but those held out (one part at a time,
    or all parts of one label at a time when `labels` are given) and the model's residuals on
    the held-out parts (their versions in `scored`, when given: the records at full rate of
    decimated parts): each fold's NRMSE (pooled rmse over the range of its held-out force),
    every held-out residual [N], and how many fold fits reported success=False."""
    groups = list(range(len(parts))) if labels is None else list(labels)
    scored = parts if scored is None else scored
    per_fold, residuals, failed = [], [], 0
    for g in dict.fromkeys(groups):
        held = [p for p, lab in zip(scored, groups) if lab == g]
        fit = fit_fold([p for p, lab in zip(parts, groups) if lab != g])
        failed += not fit.success
        r = np.concatenate([_model(law, h, _new_record_params(fit.params), fit.rtol) - h.force for h in held])
        f = np.concatenate([h.force for h in held])
        per_fold.append(float(np.sqrt(np.mean(r ** 2)) / np.ptp(f)))
        residuals.append(r)
    return per_fold, np.concatenate(residuals), failed


@dataclass
class Selection:
    """The outcome of `select_friction_law`.

    `best` is the chosen law; `fits` maps every candidate to its FitResult on all the data;
    `scores` maps it to (mean, standard error) of its cross-validated NRMSE [-] (each fold's
    held-out rmse over the range of that fold's measured force); `fold_scores` holds every
    fold's NRMSE; `folds` says how the data were split ("records": one record held out at a
    time; "groups": the records of one label; "blocks": one contiguous block of the single record); `n_free` the number of fitted
    parameters of each law. `fold_failures` counts the folds whose fit reported
    success=False. BIC is in each fit (`fits[law].bic`) as information; it does not choose.
    `screen`: the samples per cycle of the screening pass, when there was one (the scores are
    on the held-out records at full rate); `screen_fits` then holds every law's fit to the
    decimated records (the table's fit NRMSE and dBIC), and `fits` the same but for the chosen
    law, refitted at full rate.
    """

    best: str
    fits: dict[str, FitResult]
    scores: dict[str, tuple[float, float]]
    fold_scores: dict[str, tuple[float, ...]]
    folds: str
    n_free: dict[str, int]
    fold_failures: dict[str, int]
    screen: int | None = None
    screen_fits: dict[str, FitResult] | None = None

    def table(self) -> str:
        """A plain-text table: one row per law, best cross-validated score first."""
        fits = self.screen_fits or self.fits
        bic0 = min(f.bic for f in fits.values())
        rows = [f"{'law':<14} {'k':>2} {'CV NRMSE':>9} {'+- s.e.':>8} {'fit NRMSE':>9} {'dBIC':>9}  note",
                "-" * 64]
        for law in sorted(self.scores, key=lambda name: self.scores[name][0]):
            fit = fits[law]
            mean, se = self.scores[law]
            note = ["chosen" if law == self.best else ""]
            if not fit.success:
                note.append("fit failed")
            if self.fold_failures[law]:
                note.append(f"{self.fold_failures[law]} fold fit(s) failed")
            rows.append(f"{law:<14} {self.n_free[law]:>2} {mean:>9.4f} {se:>8.4f} {fit.nrmse:>9.4f} "
                        f"{fit.bic - bic0:>9.1f}  {', '.join(n for n in note if n)}")
        rows.append(f"(cross-validation over {self.folds}; the simplest law within one standard error of "
                    "the best is chosen)")
        if self.screen:
            rows.append(f"(screening: fits to the records decimated to {self.screen} samples per cycle, scored on "
                        "the held-out records at full rate; the chosen law refitted at full rate)")
        return "\n".join(rows)


def _law_kwargs(law: str, laws: Sequence[str], fit_kwargs: Mapping[str, Any]) -> dict[str, Any]:
    """fit_kwargs for one law: a value that is a dict keyed by candidate laws is per law."""
    out = {}
    for key, value in fit_kwargs.items():
        if isinstance(value, Mapping) and value and all(k in laws for k in value):
            if law in value:
                out[key] = value[law]
        else:
            out[key] = value
    return out


def select_friction_law(laws: Sequence[str], t: Any, x: Any = None, force: Any = None, v: Any = None,
                        normal_force: Any = None, cv: str = "records", n_blocks: int = 5,
                        groups: Sequence[Any] | None = None, screen: int | None = None,
                        **fit_kwargs: Any) -> Selection:
    """Choose a friction law by how well it predicts data it was not fitted to.

    Every candidate is fitted (`fit_friction`) to all the data and, fold by fold, to all but
    one part of it, and scored on the part left out: leave one record out when there are
    several records (cv="records"), leave one group of records out (cv="groups": all the
    records of one label of `groups`, such as one excitation type, at a time: a law must then
    predict a kind of motion it was not fitted to), or, with one record (or cv="blocks"),
    n_blocks contiguous blocks of the record (each block then a record of its own, its states
    starting at 0). A law's score is the mean over folds of the held-out NRMSE (rmse over the
    range of the held-out force), with its standard error (standard deviation over folds /
    sqrt(folds)). The held-out residuals calibrate each fit's prediction intervals
    (`FitResult.heldout_residuals`, see `FitResult.predict`).
    The chosen law is the one with the fewest fitted parameters among those whose mean is
    within one standard error of the best mean (the one-standard-error rule): a simpler law
    is preferred when the scores cannot tell them apart. BIC, which on correlated measurement
    noise favours the most flexible law, is reported but does not choose.

    Parameters
    ----------
    laws : sequence of str
        Candidate laws (at least 2, each in `stickslip.LAWS`).
    t, x, force, v, normal_force
        As in `fit_friction` (several records as lists, or Record objects as t).
    cv : "records", "groups" or "blocks"
        How the folds are made (above). "records" with a single record falls back to blocks.
        Default "groups" when `groups` is given, else "records".
    n_blocks : int
        Number of blocks of a single record (>= 2; default 5).
    groups : sequence, optional
        One label per record (at least 2 distinct labels), for cv="groups".
    screen : int, optional
        Samples per cycle of a screening pass (>= 8; the damper study's 48): every law is
        fitted, fold by fold and on all the data, to the records decimated to about that many
        samples per cycle of their fundamental (`stickslip.data.decimate`: an anti-aliasing
        order-8 Butterworth low-pass filter at 0.8 times the new Nyquist frequency, run forward
        and backward, then every q-th sample); the folds' fits are scored on the held-out
        records at their full rate, and the chosen law is refitted at the full rate (its
        `fits` entry; the other laws' entries are their screening fits). With several records
        only.
    **fit_kwargs
        Passed to `fit_friction` for every law (fixed, backlash, asymmetry, rtol, ...); a value
        that is a dict keyed by candidate laws applies per law, e.g.
        ``fixed={"gms": {"gms_c": 1e6}}``. `interval` applies to the fits on all the data; the
        folds' fits, whose intervals are not used, take Wald intervals.

    Returns
    -------
    Selection
        .best, .fits, .scores, .table().

    Raises
    ------
    ValueError
        Fewer than 2 laws, an unknown law, a bad cv or n_blocks, or bad data (as `fit_friction`).
    """
    if isinstance(laws, str) or len(laws) < 2:
        raise ValueError(f"laws: give at least 2 candidate laws, got {laws!r}")
    for law in laws:
        if not isinstance(law, str) or law not in LAWS:
            raise ValueError(f"laws: unknown value {law!r} (accepted: {', '.join(LAWS)})")
    if len(set(laws)) != len(laws):
        raise ValueError(f"laws: each law once, got {list(laws)!r}")
    if groups is not None and cv == "records":
        cv = "groups"
    if cv not in ("records", "groups", "blocks"):
        raise ValueError(f"cv: unknown value {cv!r} (accepted: records, groups, blocks)")
    if not (isinstance(n_blocks, (int, np.integer)) and n_blocks >= 2):
        raise ValueError(f"n_blocks: must be an integer >= 2, got {n_blocks!r}")
    data = _records(t, x, force, v, normal_force)
    labels = None
    if cv == "groups":
        if groups is None or isinstance(groups, str) or len(groups) != len(data):
            raise ValueError(f"groups: cv='groups' needs one label per record ({len(data)}), got {groups!r}")
        labels = list(groups)
        if len(set(labels)) < 2:
            raise ValueError(f"groups: at least 2 distinct labels needed to hold one out, got {labels!r}")
    elif groups is not None:
        raise ValueError(f"groups: only with cv='groups', got cv={cv!r}")
    use_blocks = cv == "blocks" or len(data) == 1
    if use_blocks:
        if len(data) != 1:
            raise ValueError(f"cv: 'blocks' splits one record; got {len(data)} records (use cv='records')")
        d = data[0]
        edges = np.linspace(0, d.t.size, int(n_blocks) + 1).astype(int)
        if np.diff(edges).min() < 4:
            raise ValueError(f"n_blocks: {n_blocks} blocks of a {d.t.size}-sample record are too short")
        nf = d.normal_force
        parts = [_Data(d.t[a:b], d.x[a:b], None if d.v is None else d.v[a:b], d.force[a:b],
                       nf if np.ndim(nf) == 0 else nf[a:b]) for a, b in zip(edges[:-1], edges[1:])]
    else:
        parts = data
    folds = "blocks" if use_blocks else cv
    scored = parts
    if screen is not None:
        if not (isinstance(screen, (int, np.integer)) and screen >= 8):
            raise ValueError(f"screen: must be an integer >= 8 (samples per cycle), got {screen!r}")
        if use_blocks:
            raise ValueError("screen: screening decimates whole records; it needs several records (cv='records' "
                             "or 'groups'), got one")
        parts = [_decimated(d, screen) for d in data]

    def fit_on(law: str, members: list[_Data], quiet: bool) -> FitResult:
        kw = _law_kwargs(law, laws, fit_kwargs)
        if quiet:       # a fold's fit is scored, its intervals unused: the cheap kind
            kw["interval"] = "wald"
        ts, xs, fs = [m.t for m in members], [m.x for m in members], [m.force for m in members]
        vs = None if any(m.v is None for m in members) else [m.v for m in members]
        nfs = None if normal_force is None else [m.normal_force for m in members]
        with warnings.catch_warnings():
            if quiet:
                warnings.simplefilter("ignore")
            return fit_friction(law, ts, xs, fs, v=vs, normal_force=nfs, **kw)

    fits: dict[str, FitResult] = {}
    scores: dict[str, tuple[float, float]] = {}
    fold_scores: dict[str, tuple[float, ...]] = {}
    failures: dict[str, int] = {}
    for law in laws:
        fits[law] = fit_on(law, parts, quiet=False)
        per_fold, residuals, failed = _cross_validate(law, parts, labels, lambda m: fit_on(law, m, quiet=True),
                                                      scored)
        arr = np.array(per_fold)
        scores[law] = (float(arr.mean()), float(arr.std(ddof=1) / math.sqrt(arr.size)))
        fits[law].cv_nrmse = scores[law]
        fits[law].heldout_residuals = residuals
        fold_scores[law] = tuple(per_fold)
        failures[law] = failed
    n_free = {law: len(fits[law].free) for law in laws}
    best_mean, best_se = min(scores.values(), key=lambda s: s[0])
    within = [law for law in laws if scores[law][0] <= best_mean + best_se]
    best = min(within, key=lambda law: (n_free[law], scores[law][0]))
    screen_fits = dict(fits) if screen is not None else None
    if screen is not None:         # the chosen law refitted on the records at their full rate
        screened = fits[best]
        fits[best] = fit_on(best, scored, quiet=False)
        fits[best].cv_nrmse, fits[best].heldout_residuals = screened.cv_nrmse, screened.heldout_residuals
    return Selection(best=best, fits=fits, scores=scores, fold_scores=fold_scores, folds=folds,
                     n_free=n_free, fold_failures=failures, screen=screen, screen_fits=screen_fits)
