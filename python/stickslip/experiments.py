"""Experiment workflows of a friction test rig, beside `fit_friction` (docs/guide/identification.md):

- `steady_friction`: the steady friction force of each constant-velocity step of a record (a
  velocity staircase), with its standard error;
- `fit_stribeck_curve`: a law's steady friction against speed (its Stribeck curve,
  `stickslip.friction_coefficient`) fitted to those points, weighted by their errors;
- `fit_two_step`: the static parameters from the steady curve, then the dynamic ones (LuGre's
  sigma0 and sigma1, ...) from presliding or hysteresis records with the static ones held.

Statistics as in `stickslip.identify`: the covariance s^2 (J^T W J)^-1 of the weighted least
squares (W the inverse variances of the points; s^2 their reduced chi-square, as lmfit's
scale_covar), 95 % intervals Student-t on a scale where the parameter's range is the whole line.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Mapping, Sequence

import numpy as np

from .core import LAWS, REGISTRY, _choice, _finite, friction_coefficient
from .identify import (FitResult, _Estimates, _central_jacobian, _check_keys, _coordinates, _in_range, _interval,
                       _model_mesh, _range_of, _record_params, _records, _start, _wald_intervals, fit_friction,
                       parameter_unit)

__all__ = ["SteadyPoints", "SteadyCurve", "TwoStepFit", "steady_friction", "fit_stribeck_curve", "fit_two_step"]


# --------------------------------------------------------------------------------------------
# Steady friction of constant-velocity steps
# --------------------------------------------------------------------------------------------
@dataclass
class SteadyPoints:
    """The steady friction of constant-velocity steps, one entry per step.

    speed [m/s] and force [N] are the means over the kept part of the step (its last
    1 - settle fraction), stderr [N] the standard error of the mean force (inflated by
    sqrt((1 + rho)/(1 - rho)) for the force's lag-1 correlation rho within the window),
    normal_force [N] the mean normal force (1 when it was not given: force levels), n_samples
    the samples averaged, t_start and t_end [s] the window, record the index of its record.
    """

    speed: np.ndarray
    force: np.ndarray
    stderr: np.ndarray
    normal_force: np.ndarray
    n_samples: np.ndarray
    t_start: np.ndarray
    t_end: np.ndarray
    record: np.ndarray
    force_levels: bool = True

    def __len__(self) -> int:
        return int(self.speed.size)

    def table(self) -> str:
        """One line per step: speed, steady force and its standard error, samples, window."""
        rows = [f"{'speed [m/s]':>12} {'force [N]':>12} {'+- s.e. [N]':>11} {'samples':>7}  window [s]"]
        rows += [f"{v:>12.5g} {f:>12.6g} {e:>11.3g} {n:>7d}  {a:.4g} .. {b:.4g}"
                 for v, f, e, n, a, b in zip(self.speed, self.force, self.stderr, self.n_samples,
                                             self.t_start, self.t_end)]
        return "\n".join(rows)


def _steps(v: np.ndarray, rel: float, floor: float) -> list[tuple[int, int]]:
    """Runs [a, b) of samples whose velocity stays within rel |mean| + floor of the run's
    running mean."""
    runs = []
    a, total = 0, float(v[0])
    for i in range(1, v.size):
        mean = total / (i - a)
        if abs(v[i] - mean) > rel * abs(mean) + floor:
            runs.append((a, i))
            a, total = i, 0.0
        total += float(v[i])
    runs.append((a, v.size))
    return runs


def _flat(t: np.ndarray, v: np.ndarray, rel: float) -> bool:
    """Whether a run's velocity is constant: a quadratic least-squares fit over the run varies
    by at most rel |mean| (a run about a sine's velocity peak, or along a ramp, drifts across
    the whole tolerance band; a plateau's fit is flat to its noise)."""
    tau = (t - t.mean()) / (np.ptp(t) or 1.0)
    fit = np.polyval(np.polyfit(tau, v, 2 if v.size > 3 else 0), tau)
    return float(np.ptp(fit)) <= rel * abs(float(np.mean(v)))


def steady_friction(t: Any, x: Any = None, force: Any = None, v: Any = None, *, normal_force: Any = None,
                    v_tol: float = 0.05, v_floor: float | None = None, settle: float = 0.5,
                    min_samples: int = 10, min_fraction: float = 0.5) -> SteadyPoints:
    """The steady friction force of each constant-velocity step of a record.

    A step is a run of samples whose velocity stays within v_tol |u| + v_floor of the run's
    mean velocity u; runs shorter than `min_samples` (the ramps between steps) and runs at
    rest (|u| <= v_floor) are dropped. The first `settle` fraction of each step
    is the transient (the presliding states relaxing to the new speed) and is left out; the
    force is averaged over the rest.

    Parameters
    ----------
    t, x, force, v, normal_force
        One record or several (lists, or `stickslip.Record` objects as t), as in
        `fit_friction`: times [s], displacement [m], measured force [N], velocity [m/s]
        (measured; by default derived from x), normal force [N] (default: not measured, the
        forces are force levels).
    v_tol : float
        Tolerance of a step's velocity, relative to the step's speed, in (0, 1).
    v_floor : float, optional
        Absolute part of the tolerance [m/s], >= 0: above the velocity's noise (default: 1e-3
        times each record's largest |v|).
    settle : float
        Fraction of each step left out as its transient, in [0, 1).
    min_samples : int
        Fewest samples of a step (>= 4); at least 2 are averaged.
    min_fraction : float
        Least fraction of each record's moving time (|v| > v_floor) that its steps must cover,
        in (0, 1] (default 0.5). A step must also hold a constant velocity: a quadratic fit of
        its velocity varies by at most v_tol/2 of its speed. A velocity staircase is such
        steps joined by short ramps (the synthetic one of the guide: 98 % of the moving time);
        a record of continuously varying velocity (a sine) is cut into runs within v_tol of
        their mean too, but their velocity drifts across the band: such a record is refused,
        the message naming the runs found, their durations and how many were constant.

    Returns
    -------
    SteadyPoints
        One entry per step, in the order of the records and of time.

    Raises
    ------
    ValueError
        Bad data (as `fit_friction`), a v_tol, settle, min_samples or min_fraction out of
        range, no step found, or a record whose steps cover less than min_fraction of its
        moving time (not a velocity staircase).
    """
    v_tol = _finite("v_tol", v_tol, "in (0, 1)")
    if not 0.0 < v_tol < 1.0:
        raise ValueError(f"v_tol: must be in (0, 1) (relative to the top speed) [-], got {v_tol!r}")
    settle = _finite("settle", settle, "in [0, 1)")
    if not 0.0 <= settle < 1.0:
        raise ValueError(f"settle: must be in [0, 1) (fraction of a step) [-], got {settle!r}")
    if not (isinstance(min_samples, (int, np.integer)) and min_samples >= 4):
        raise ValueError(f"min_samples: must be an integer >= 4, got {min_samples!r}")
    min_fraction = _finite("min_fraction", min_fraction, "in (0, 1]")
    if not 0.0 < min_fraction <= 1.0:
        raise ValueError(f"min_fraction: must be in (0, 1] (fraction of the moving time) [-], got {min_fraction!r}")
    if v_floor is not None:
        v_floor = _finite("v_floor", v_floor, ">= 0 [m/s]")
        if v_floor < 0.0:
            raise ValueError(f"v_floor: must be >= 0 [m/s], got {v_floor!r}")
    data = _records(t, x, force, v, normal_force)
    out: dict[str, list[float]] = {k: [] for k in ("speed", "force", "stderr", "normal_force", "n",
                                                   "t0", "t1", "record")}
    for j, d in enumerate(data):
        vel = d.v if d.v is not None else np.gradient(d.x, d.t)
        floor = 1e-3 * float(np.max(np.abs(vel))) if v_floor is None else v_floor
        nf = np.broadcast_to(np.asarray(d.normal_force, dtype=float), d.t.shape)
        runs = [(a, b) for a, b in _steps(vel, v_tol, floor)
                if b - a >= min_samples and abs(float(np.mean(vel[a:b]))) > floor]
        plateaus = [(a, b) for a, b in runs if _flat(d.t[a:b], vel[a:b], 0.5 * v_tol)]
        dt = np.gradient(d.t)
        moving = float(dt[np.abs(vel) > floor].sum())
        covered = sum(float(dt[a:b].sum()) for a, b in plateaus)
        if runs and covered < min_fraction * moving:
            span = np.array([d.t[b - 1] - d.t[a] for a, b in runs])
            tag = f"[{j}]" if len(data) > 1 else ""
            raise ValueError(
                f"t{tag}: not a velocity staircase: {len(runs)} run(s) within v_tol {v_tol:g} of their mean "
                f"velocity ({1e3 * span.min():.3g}-{1e3 * span.max():.3g} ms), {len(plateaus)} of them at a "
                f"constant velocity (a quadratic fit varying by less than v_tol/2), covering "
                f"{100 * covered / moving:.3g} % of the record's moving time ({moving:.4g} s), below "
                f"min_fraction {100 * min_fraction:g} %; steady friction needs constant-velocity plateaus "
                "(fit a law to this record with fit_friction instead)")
        for a, b in plateaus:
            a = a + int(math.ceil(settle * (b - a)))
            if b - a < 2 or abs(float(np.mean(vel[a:b]))) <= floor:
                continue
            f = d.force[a:b]
            dev = f - f.mean()
            ss = float(dev @ dev)
            rho = float(dev[:-1] @ dev[1:]) / ss if ss > 0.0 and f.size > 2 else 0.0
            rho = min(max(rho, 0.0), 0.99)
            se = math.sqrt(ss / (f.size - 1) / f.size * (1.0 + rho) / (1.0 - rho))
            for key, value in (("speed", np.mean(vel[a:b])), ("force", f.mean()), ("stderr", se),
                               ("normal_force", np.mean(nf[a:b])), ("n", b - a), ("t0", d.t[a]),
                               ("t1", d.t[b - 1]), ("record", j)):
                out[key].append(float(value))
    if not out["speed"]:
        raise ValueError(f"t: no constant-velocity step of at least {min_samples} samples found "
                         f"(v_tol {v_tol:g}); is the record a velocity staircase?")
    arr = {k: np.array(val) for k, val in out.items()}
    return SteadyPoints(speed=arr["speed"], force=arr["force"], stderr=arr["stderr"],
                        normal_force=arr["normal_force"], n_samples=arr["n"].astype(int),
                        t_start=arr["t0"], t_end=arr["t1"], record=arr["record"].astype(int),
                        force_levels=normal_force is None)


# --------------------------------------------------------------------------------------------
# A law's steady curve fitted to the steady points
# --------------------------------------------------------------------------------------------
@dataclass
class SteadyCurve(_Estimates):
    """A law's steady friction against speed, fitted to steady points (`fit_stribeck_curve`).

    `params` holds the parameters that shape the law's steady curve, fitted or fixed (the
    law's other parameters do not change it); `free` the fitted ones, in the order of
    `covariance` and `correlation`; `stderr` and `ci95` (Student t with `dof` degrees of
    freedom, on a scale where the range is the whole line) cover them. `reduced_chi2` is the
    weighted sum of squares over dof (about 1 when the points' errors are right; the
    covariance is scaled by it), `rmse` [N] the unweighted error. Units: force levels (N,
    N s/m) when the normal force was not given (`force_levels`).
    """

    points: SteadyPoints
    rmse: float
    reduced_chi2: float
    dof: int
    force_levels: bool
    success: bool = True
    message: str = ""
    undetermined: tuple[str, ...] = field(default_factory=tuple)

    def mu(self, v: Any) -> np.ndarray:
        """The fitted steady curve at velocities v [m/s]: the friction coefficient [-] (a force
        level [N] when the normal force was not given)."""
        return _steady_mu(self.law, np.asarray(v, dtype=float), self.params)

    def summary(self) -> str:
        """The parameters with their intervals, and the scores."""
        what = "force levels (normal force not given: N = 1 N)" if self.force_levels else "coefficients"
        lines = [f"{self.law} steady curve: {len(self.points)} steps, {what}",
                 f"  rmse {self.rmse:.4g} N, reduced chi-square {self.reduced_chi2:.3g} ({self.dof} dof)"]
        for name, value in self.params.items():
            if name in self.ci95:
                lo, hi = self.ci95[name]
                flag = " (not determined)" if name in self.undetermined else ""
                lines.append(f"  {name:>8} = {value:.6g} {self.units[name]}  +- {self.stderr[name]:.3g}  "
                             f"95% CI [{lo:.6g}, {hi:.6g}]{flag}")
            else:
                lines.append(f"  {name:>8} = {value:.6g} {self.units[name]}  (fixed)")
        return "\n".join(lines)


def _steady_mu(law: str, v: np.ndarray, params: Mapping[str, float]) -> np.ndarray:
    """The law's steady curve mu(v), its other parameters at values that let it evaluate."""
    full = _steady_completion(law, params)
    return friction_coefficient(law, v, **full)


def _steady_completion(law: str, params: Mapping[str, float]) -> dict[str, float]:
    """params with the law's other parameters filled by valid values (they do not change the
    steady curve; a stiffness is given the sliding level per metre)."""
    level = params.get("mu_k", 1.0) or 1.0
    s = {"level_pos": level, "level_neg": level, "v_max": 1.0, "amplitude": 1.0}
    full = {}
    for name in REGISTRY["law"][law]["params"]:
        if name in params:
            full[name] = params[name]
        elif name == "n_elements":
            full[name] = float(REGISTRY["param"][name]["default"])
        else:
            full[name] = _start(name, s, False)
    if "mu_s" in full and full["mu_s"] < full.get("mu_k", 0.0):
        full["mu_s"] = full["mu_k"]
    if "v_d" in full and full["v_d"] <= full["v_s"]:
        full["v_d"] = 2.0 * full["v_s"]
    return full


def steady_curve_params(law: str, speeds: Any = None) -> tuple[str, ...]:
    """The parameters of `law` that change its steady friction curve (at `speeds` [m/s], by
    default a spread from 1e-4 to 1 m/s): each is changed by 30 % from a valid point and kept if
    the curve moves. LuGre: mu_s, mu_k, v_s, sigma2; Dahl: mu_k; Stribeck: all but v_eps's
    effect at rest."""
    _choice("law", law, LAWS)
    v = np.asarray(speeds, dtype=float) if speeds is not None else np.geomspace(1e-4, 1.0, 13)
    v = np.concatenate([v, -v])
    base = _steady_completion(law, {"mu_k": 1.0, "mu_s": 1.5, "v_s": float(np.median(np.abs(v)))})
    if "v_d" in base:
        base["v_d"] = 2.0 * base["v_s"]
    for name in ("c_v", "sigma2", "sigma1"):
        if name in base:
            base[name] = 0.1 / float(np.max(np.abs(v)))
    mu0 = friction_coefficient(law, v, **base)
    names = []
    for name in REGISTRY["law"][law]["params"]:
        if name == "n_elements":
            continue
        trial = dict(base, **{name: base[name] * 1.3 if name != "mu_k" else base[name] / 1.3})
        try:
            mu1 = friction_coefficient(law, v, **trial)
        except ValueError:
            continue
        if np.max(np.abs(mu1 - mu0)) > 1e-9 * np.max(np.abs(mu0)):
            names.append(name)
    return tuple(names)


def _curve_starts(law: str, names: Sequence[str], speed: np.ndarray, level: np.ndarray) -> dict[str, float]:
    """Starting values of the steady-curve parameters from the points (|v|, |F| sign-folded):
    mu_k the lowest level, mu_s the level at the lowest speed, v_s where the level is halfway
    between them, the viscous slope from the fastest half of the points."""
    s = np.abs(speed)
    order = np.argsort(s)
    s, f = s[order], np.abs(level[order])
    mu_k = max(float(f.min()), 1e-12)
    mu_s = max(float(np.median(f[: max(1, s.size // 5)])), mu_k * (1.0 + 1e-3))
    half = np.flatnonzero(f <= 0.5 * (mu_s + mu_k))
    v_s = float(s[half[0]]) if half.size else float(np.sqrt(s[0] * s[-1]))
    fast = s >= np.median(s)
    slope = float(np.polyfit(s[fast], f[fast], 1)[0]) if np.ptp(s[fast]) > 0.0 else 0.0
    viscous = max(slope, 0.01 * mu_k / float(s[-1]))
    scales = {"level_pos": mu_k, "level_neg": mu_k, "v_max": float(s[-1]), "amplitude": 1.0}
    starts = {"mu_k": mu_k, "mu_s": mu_s, "v_s": max(v_s, 1e-12), "v_d": 2.0 * max(v_s, 1e-12),
              "c_v": viscous, "sigma2": viscous}
    return {n: starts[n] if n in starts else _start(n, scales, False) for n in names}


def fit_stribeck_curve(points: SteadyPoints | tuple, law: str = "lugre", *,
                       fixed: Mapping[str, float] | None = None,
                       params0: Mapping[str, float] | None = None) -> SteadyCurve:
    """Fit the steady friction curve of `law` (its Stribeck curve: `friction_coefficient` at
    constant speed) to steady points, by weighted least squares.

    Parameters
    ----------
    points : SteadyPoints or (speed, force) or (speed, force, stderr)
        Steady points (`steady_friction`), or arrays of speeds [m/s] and steady forces [N]
        (force levels; unweighted without stderr [N]). Both directions may be given: the curve
        is odd in v.
    law : str
        A law of `stickslip.LAWS` (default "lugre"). Only the parameters that change its
        steady curve are fitted (`steady_curve_params`: LuGre's mu_s, mu_k, v_s, sigma2).
    fixed : dict, optional
        Steady-curve parameters held at given values (e.g. {"delta": 2.0} for "stribeck").
    params0 : dict, optional
        Starting values (default: from the points).

    Returns
    -------
    SteadyCurve

    Raises
    ------
    ValueError
        An unknown law or parameter, a value out of range, fewer points than fitted
        parameters + 1, non-finite points.
    """
    from scipy import stats
    from scipy.optimize import least_squares

    _choice("law", law, LAWS)
    if isinstance(points, SteadyPoints):
        pts = points
    else:
        if not isinstance(points, (tuple, list)) or len(points) not in (2, 3):
            raise ValueError("points: give SteadyPoints, (speed, force) or (speed, force, stderr)")
        sp = np.asarray(points[0], dtype=float)
        fo = np.asarray(points[1], dtype=float)
        se = np.asarray(points[2], dtype=float) if len(points) == 3 else np.ones_like(fo)
        if sp.ndim != 1 or fo.shape != sp.shape or se.shape != sp.shape:
            raise ValueError(f"points: speed, force (and stderr) must be 1-d of one length, got shapes "
                             f"{sp.shape}, {fo.shape}, {se.shape}")
        if not (np.isfinite(sp).all() and np.isfinite(fo).all() and np.isfinite(se).all()) or (se <= 0.0).any():
            raise ValueError("points: speed [m/s] and force [N] must be finite, stderr finite and > 0 [N]")
        n = sp.size
        pts = SteadyPoints(speed=sp, force=fo, stderr=se, normal_force=np.ones(n), n_samples=np.ones(n, int),
                           t_start=np.zeros(n), t_end=np.zeros(n), record=np.zeros(n, int))
    force_levels = pts.force_levels
    names = steady_curve_params(law, pts.speed[pts.speed != 0.0] if (pts.speed != 0.0).any() else None)
    fixed = dict(fixed or {})
    params0 = dict(params0 or {})
    _check_keys("fixed", fixed, names, law)
    _check_keys("params0", params0, names, law)
    fixed_all = {k: _in_range(f"fixed[{k!r}]", k, val, force_levels) for k, val in fixed.items()}
    free = tuple(n for n in names if n not in fixed_all)
    if not free:
        raise ValueError("fixed: every parameter of the steady curve is fixed; nothing to fit")
    if len(pts) < len(free) + 1:
        raise ValueError(f"points: {len(pts)} steps cannot determine {len(free)} parameters "
                         f"({', '.join(free)}) and the scatter; give at least {len(free) + 1}")
    mu = pts.force / pts.normal_force
    w = pts.normal_force / pts.stderr              # 1 / standard error of mu
    starts = _curve_starts(law, names, pts.speed, mu)
    p0 = np.array([_in_range(f"params0[{n!r}]", n, params0[n], force_levels) if n in params0
                   else starts[n] for n in free])
    space, q_lo, q_hi, u0 = _coordinates(free, p0, {}, fixed_all, {})

    def params_of(u: np.ndarray) -> dict[str, float]:
        p = dict(fixed_all)
        p.update(zip(free, space.to_params(u).tolist()))
        return {n: p[n] for n in names}

    def residuals(u: np.ndarray) -> np.ndarray:
        return (_steady_mu(law, pts.speed, params_of(u)) - mu) * w

    penalty = np.full(mu.size, 1e3 * float(np.max(np.abs(mu * w))) + 1.0)

    def trial(u: np.ndarray) -> np.ndarray:
        try:
            return residuals(u)
        except ValueError:
            return penalty

    u_start = np.minimum(np.maximum(u0, np.nextafter(q_lo, np.inf)), np.nextafter(q_hi, -np.inf))
    sol = least_squares(trial, u_start, bounds=(q_lo, q_hi), method="trf", max_nfev=200 * len(free))
    r = residuals(sol.x)
    k = len(free)
    dof = mu.size - k
    chi2 = float(r @ r) / dof if dof > 0 else math.inf
    jac = _central_jacobian(residuals, sol.x, q_lo, q_hi, 1e-6) @ np.linalg.inv(space.matrix())
    _, sv, vt = np.linalg.svd(jac, full_matrices=False)
    keep = sv > sv[0] * 1e-10 if sv.size and sv[0] > 0.0 else np.zeros(k, bool)
    cov = chi2 * (vt[keep].T / sv[keep] ** 2) @ vt[keep]
    null = vt[~keep]
    blind = (np.abs(null) > 1e-6).any(axis=0) if null.size else np.zeros(k, bool)
    sd = np.sqrt(np.maximum(np.diag(cov), 0.0))
    sd[blind] = np.inf
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov / np.outer(np.sqrt(np.diag(cov)), np.sqrt(np.diag(cov)))
    tq = float(stats.t.ppf(0.975, max(dof, 1)))
    pv = space.to_params(sol.x)
    params = params_of(sol.x)
    units = {n: parameter_unit(n, force_levels) for n in names}
    resid_force = (_steady_mu(law, pts.speed, params) - mu) * pts.normal_force
    return SteadyCurve(
        law=law, params=params, units=units, free=free,
        stderr={n: float(sd[i]) for i, n in enumerate(free)},
        ci95=_wald_intervals(space, pv, sd, tq),
        covariance=cov, correlation=corr, points=pts, rmse=float(np.sqrt(np.mean(resid_force ** 2))),
        reduced_chi2=chi2, dof=dof, force_levels=force_levels, success=bool(sol.success),
        message=str(sol.message),
        undetermined=tuple(n for i, n in enumerate(free) if not math.isfinite(sd[i]) or sd[i] > abs(pv[i])))


# --------------------------------------------------------------------------------------------
# Two steps: the steady curve, then the dynamic parameters with the static ones held
# --------------------------------------------------------------------------------------------
@dataclass
class TwoStepFit:
    """The outcome of `fit_two_step`: `steady` (the SteadyCurve of step 1) and `dynamic` (the
    FitResult of step 2, the steady-curve parameters held at step 1's values). `params` holds
    every parameter of the model; `stderr` and `ci95` each fitted parameter's: step 1's from
    step 1, step 2's with step 1's uncertainty carried into them (the delta method:
    `covariance` = step 2's own covariance + S C1 S^T, C1 step 1's covariance and S =
    `sensitivity`, the change of step 2's estimates per unit change of step 1's values).
    `dynamic.stderr` keeps step 2's conditional errors (step 1's values taken as exact)."""

    steady: SteadyCurve
    dynamic: FitResult
    params: dict[str, float]
    stderr: dict[str, float]
    ci95: dict[str, tuple[float, float]]
    #: step 2's fitted parameters (dynamic.free) and their covariance with step 1's carried in
    covariance: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    #: d(step 2's estimates)/d(step 1's values): rows dynamic.free, columns steady.free
    sensitivity: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))

    def predict(self, *args: Any, **kwargs: Any) -> Any:
        """The model's force along a motion: `FitResult.predict` of the dynamic step."""
        return self.dynamic.predict(*args, **kwargs)

    def summary(self) -> str:
        """Both steps' summaries."""
        return "step 1, " + self.steady.summary() + "\nstep 2, " + self.dynamic.summary()


def fit_two_step(steady: SteadyCurve, t: Any, x: Any = None, force: Any = None, v: Any = None,
                 **fit_kwargs: Any) -> TwoStepFit:
    """Identify a law with internal states in two steps: its steady-curve parameters from
    constant-velocity steps (`steady`, a `fit_stribeck_curve` result: LuGre's mu_s, mu_k, v_s,
    sigma2), then the rest (LuGre's sigma0 and sigma1) from records of presliding or hysteresis
    (small back-and-forth motions, where the states matter), with the first held fixed.

    Parameters
    ----------
    steady : SteadyCurve
        Step 1, fitted for the same law.
    t, x, force, v
        The records of step 2, as in `fit_friction`.
    **fit_kwargs
        Passed to `fit_friction` (normal_force, fixed, params0, backlash, offset, ...). A
        parameter of the steady curve may not be given in `fixed` (it is step 1's).

    Returns
    -------
    TwoStepFit

    Raises
    ------
    ValueError
        A steady curve fitted with the normal force and records without it (or the reverse),
        a steady-curve parameter in `fixed`, or bad data (as `fit_friction`).
    """
    if not isinstance(steady, SteadyCurve):
        raise ValueError(f"steady: must be a SteadyCurve (fit_stribeck_curve), got {type(steady).__name__}")
    if steady.force_levels != (fit_kwargs.get("normal_force") is None):
        raise ValueError("normal_force: step 1 was fitted " + ("without" if steady.force_levels else "with")
                         + " the normal force; give step 2 " + ("none" if steady.force_levels else "the normal force")
                         + " too (force levels and coefficients cannot be mixed)")
    fixed = dict(fit_kwargs.pop("fixed", None) or {})
    clash = [k for k in fixed if k in steady.params]
    if clash:
        raise ValueError(f"fixed: {', '.join(map(repr, clash))} come(s) from the steady curve (step 1); "
                         "fix it there")
    fixed.update(steady.params)
    dynamic = fit_friction(steady.law, t, x, force, v, fixed=fixed, **fit_kwargs)
    data = _records(t, x, force, v, fit_kwargs.get("normal_force"))
    sens, cov = _carry_step_one(steady, dynamic, data)
    from scipy import stats
    tq = float(stats.t.ppf(0.975, max(dynamic.n_samples - len(dynamic.free), 1)))
    sd = np.sqrt(np.maximum(np.diag(cov), 0.0))
    stderr = dict(steady.stderr)
    ci95 = dict(steady.ci95)
    for i, name in enumerate(dynamic.free):
        own = dynamic.stderr[name]
        stderr[name] = float(sd[i]) if math.isfinite(own) else own
        ci95[name] = _interval(name, dynamic.params[name], stderr[name], tq)
    return TwoStepFit(steady=steady, dynamic=dynamic, params=dict(dynamic.params), stderr=stderr, ci95=ci95,
                      covariance=cov, sensitivity=sens)


def _carry_step_one(steady: SteadyCurve, dynamic: FitResult, data: list) -> tuple[np.ndarray, np.ndarray]:
    """Step 2's covariance with step 1's uncertainty carried in, and its sensitivity to step
    1's values. At step 2's least-squares optimum J2^T r = 0 for every step 1 value a, so to
    first order d(estimates)/da = -(J2^T J2)^+ J2^T Ja (J2, Ja the Jacobians of step 2's
    residuals in its fitted parameters and in step 1's; central differences on the substeps
    of the integration at the optimum, frozen, so that they measure the model), and the
    estimates' covariance gains S C1 S^T."""
    free2, free1 = dynamic.free, steady.free
    cov2 = np.where(np.isfinite(dynamic.covariance), dynamic.covariance, 0.0)
    if not free1:
        return np.zeros((len(free2), 0)), cov2
    p = dict(dynamic.params)
    meshes = [_model_mesh(dynamic.law, d, _record_params(p, i), dynamic.rtol)[1] for i, d in enumerate(data)]

    def column(name: str) -> np.ndarray:
        low, high = _range_of(name)[:2]
        h = 1e-4 * max(abs(p[name]), 1e-12)
        up, down = dict(p), dict(p)
        up[name] = min(p[name] + h, high)
        down[name] = max(p[name] - h, low)
        f_up, f_down = (np.concatenate([_model_mesh(dynamic.law, d, _record_params(q, i), dynamic.rtol, m)[0]
                                        for i, (d, m) in enumerate(zip(data, meshes))]) for q in (up, down))
        return (f_up - f_down) / (up[name] - down[name])

    j2 = np.column_stack([column(n) for n in free2])
    j1 = np.column_stack([column(n) for n in free1])
    sens = -np.linalg.lstsq(j2, j1, rcond=None)[0]
    c1 = np.where(np.isfinite(steady.covariance), steady.covariance, 0.0)
    return sens, cov2 + sens @ c1 @ sens.T
