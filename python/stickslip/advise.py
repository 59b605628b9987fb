"""The advisor: which method, step or tolerance reaches a target error at the least cost.

`advise(scene, law, target_error, t_end, ...)` answers for the problem at hand, from pilot runs
of that problem, not from tables measured for the paper's scenes, so it holds for parameters no
study covered. For each candidate method (every entry of METHODS by default, read from the
registry, so a method added there joins without edits here):

1. a ladder of pilot runs, loose to tight: fixed-step methods at h = t_end/N with N doubling,
   adaptive ones at rtol = 1e-3, 1e-4, ... (atol = 1e-3 rtol, no h_max); the adaptive methods
   first, in the order of the cost of their first run (a probe), so that the cheap predictions
   come early and prune the others. The ladder stops when
   its differences show a consistent order (three in a row), when it has passed the target,
   when the differences reach round-off, or when the next run would cost more than another
   method is already predicted to need.
2. error estimates by Richardson's argument: the error of run k is |q_k - q_K| plus the finest
   run's own error, |q_K - q_K-1| rho / (1 - rho) with rho the observed ratio of successive
   differences; then a fit error ~ C s^p (s = h or rtol) over the tightest reliable runs and a
   fit of the cost (evaluations) against s.
3. for explicit fixed-step methods (RK4), the stability bound: the eigenvalues lambda of the
   scene's Jacobian (finite differences of the right-hand side, taken from one tiny RK4 step)
   along a pilot trajectory, and the largest h with |R(h lambda)| <= 1 for the method's
   stability polynomial; steps beyond it are never piloted nor advised. No fixed-step method
   (explicit or implicit) is piloted or advised at a step longer than PERIOD_FRACTION of the
   scene's shortest period of free oscillation (2 pi sqrt(m/k) on the belt), where `simulate`
   warns that it cannot follow the oscillation.
4. the cheapest predicted setting (CPU seconds = evaluations x the method's measured seconds
   per evaluation) that meets target/SAFETY, then one verifying run at that setting, whose
   error is estimated against a tighter run of the same method (a pilot, or one more run);
   if the estimate misses the target the setting is tightened (at most MAX_TIGHTEN times).
5. a cross-check: the advised run must agree with the most accurate run of at least one other
   method (within the target plus that run's error, counting runs whose own estimate is within
   the target), and when it disagrees with all, a third adaptive method run tight decides. This
   catches a bias a method shares with its own tighter runs (implicit Euler's large steps skip
   the start-up transient of a creeping box and agree with each other to 1e-10 m while being
   5e-7 m off).

The error is that of the position x [m] (quantity="x") or the velocity v [m/s] (quantity="v")
at t_end, absolute. Where no method can reach the target (Coulomb's jump under event-free
stepping converges at order 1 with chatter; a target below round-off), the Advice says so
(`feasible` False, `message`) and names what can.
"""
from __future__ import annotations

import functools
import math
import time
import warnings
from dataclasses import dataclass, field
from typing import Any, Sequence

import numpy as np

from .core import (LAWS, METHODS, REGISTRY, SCENES, CONTROLS, IntegrationError, RegularisedLawWarning, _choice,
                   _physical, shortest_period, friction_coefficient, _shown, simulate)

#: Aim at target/SAFETY, so that a prediction off by this factor still meets the target.
SAFETY: float = 2.0
#: Times a verified setting is tightened before the advisor moves to the next method.
MAX_TIGHTEN: int = 3
#: Runs in one ladder at most.
MAX_LADDER: int = 14
#: Steps of a fixed-step method's first pilot: h = t_end/N0.
N0: int = 16
#: First and tightest tolerance of an adaptive method's ladder (the library accepts >= 100 eps).
RTOL0: float = 1e-3
#: Tightest rtol of an adaptive ladder: the advisor's own floor, above the library's
#: stickslip.core.RTOL_MIN (100 eps = 2.2e-14), where round-off still leaves an order to see.
RTOL_MIN: float = 1e-13
#: atol = ATOL_RATIO rtol (as the work-precision study).
ATOL_RATIO: float = 1e-3
#: A pilot never costs more than this many evaluations, and an adaptive pilot never takes more
#: than PILOT_MAX_STEPS steps (Coulomb pins DOPRI5 and RADAU5 at h_min: millions of steps).
PILOT_NFEV_CAP: float = 2e6
PILOT_MAX_STEPS: int = 200_000
#: Fraction of the stability bound a fixed-step explicit pilot or advice may use.
STABILITY_MARGIN: float = 0.8
#: A fixed step is at most this fraction of the scene's shortest period of free oscillation
#: (simulate warns beyond the period and advises a tenth of it).
PERIOD_FRACTION: float = 0.1
#: A difference below ROUNDOFF eps max|q| is round-off.
ROUNDOFF: float = 100.0
#: Steps the library takes by default at most (simulate's max_steps).
MAX_STEPS: float = 1e8
#: A ladder stops before a run predicted to cost more than PRUNE times the cheapest prediction
#: of the methods piloted before it: it cannot win.
PRUNE: float = 3.0
PRUNED = "pruned: another method is predicted cheaper than its next pilot"
#: The probe (first rung) of each adaptive method stops after this many steps: a method that
#: needs more (DOPRI5 on a stiff problem) is priced by its pace and run in full only if the
#: others leave it a chance (PRUNE).
PROBE_MAX_STEPS: int = 2_000
#: Tolerance of the tie-breaking runs of a third method (_tiebreak).
TIEBREAK_RTOL: float = 1e-10
#: Points of a pilot's output grid (the trajectory the Jacobian is sampled on).
N_GRID: int = 33
#: Methods that step through a friction jump with set-valued friction (when registered).
NONSMOOTH_METHODS: tuple[str, ...] = ("moreau", "event_driven")
#: The reference of a model whose every contact takes exact stick (`_exact_reference`).
EXACT_METHOD: str = "event_driven"
QUANTITIES: dict[str, str] = {"x": "position x [m]", "v": "velocity v [m/s]"}


@dataclass
class Run:
    """One run the advice rests on: its role ("pilot"; "survey", a trajectory for the Jacobian
    when only fixed-step methods are candidates; "verify"; "check", a tie-breaker;
    "reference", a model's exact-stick reference), method and
    controls,
    the quantity at t_end (q), the error estimate (None where none could be made), and its cost
    (evaluations, CPU seconds of the integration)."""

    role: str
    method: str
    controls: dict[str, float]
    q: float | None
    error: float | None
    nfev: int
    seconds: float
    status: str = "ok"
    t_reached: float = math.nan

    def setting(self) -> str:
        """The control that sets the accuracy, as text: 'h = 0.01 s' or 'rtol = 1e-06'."""
        if "h" in self.controls:
            return f"h = {self.controls['h']:.4g} s"
        return f"rtol = {self.controls['rtol']:.3g}"


@dataclass
class Candidate:
    """What the pilots say about one method: the exponent p of error ~ C s^p against its setting
    s (the observed order for a fixed step h; for an adaptive method the exponent of rtol, near
    1), the setting predicted for target/SAFETY, its predicted error and cost, and whether it
    can reach the target (with the reason when not)."""

    method: str
    exponent: float | None = None
    controls: dict[str, float] | None = None
    predicted_error: float | None = None
    nfev: float | None = None
    seconds: float | None = None
    feasible: bool = False
    note: str = ""


@dataclass
class Advice:
    """The advisor's answer.

    ``method`` and ``controls`` go straight into
    ``simulate(a.scene, a.law, method=a.method, t_end=a.t_end, x0=a.x0, v0=a.v0,
    **a.controls, **a.params)``, or ``simulate(a.model, method=a.method, t_end=a.t_end,
    **a.controls)`` for a model (``scene`` "model", ``law`` its contacts' laws joined by "+",
    ``body`` the body whose x or v was advised on); they are None and ``{}`` when no method can meet the target
    (``feasible`` is then False and ``message`` names what can).

    Attributes
    ----------
    predicted_error : float or None
        The error estimate of the advised run [m, or m/s for ``quantity="v"``], verified by
        running it.
    predicted_cost : dict
        ``{"nfev": evaluations, "seconds": CPU seconds}`` of the advised run.
    runs : list of Run
        Every run the advisor made (pilots, verification, cross-checks).
    candidates : list of Candidate
        What the pilots say about each method.
    pilot_cost : dict
        The total cost of all runs and its ratio to the advised run's.
    roundoff : float
        The round-off level of the quantity, ROUNDOFF eps max|q| over the runs [m or m/s]; 0
        when q was exactly 0 in every run (a held body). No estimate below it is printed.
    """

    scene: str
    law: str
    t_end: float
    quantity: str
    target_error: float
    params: dict[str, float]
    x0: float
    v0: float
    feasible: bool
    message: str
    method: str | None = None
    controls: dict[str, float] = field(default_factory=dict)
    predicted_error: float | None = None
    predicted_cost: dict[str, float] = field(default_factory=dict)
    runs: list[Run] = field(default_factory=list)
    candidates: list[Candidate] = field(default_factory=list)
    pilot_cost: dict[str, float] = field(default_factory=dict)
    seconds_per_evaluation: dict[str, float] = field(default_factory=dict)
    stability_bound: float | None = None
    roundoff: float = 0.0
    model: Any = None
    body: int = 0

    def table(self) -> str:
        """The candidates and the runs as two text tables."""
        unit = "m" if self.quantity == "x" else "m/s"
        cand = [[c.method, _fmt(c.exponent, ".2f"), _setting(c.controls),
                 error_text(c.predicted_error, self.roundoff),
                 _fmt(c.nfev, ".0f"), _fmt(c.seconds), "yes" if c.feasible else "no", c.note]
                for c in self.candidates]
        runs = [[r.role, r.method, r.setting(), _fmt(r.q, ".12g"), error_text(r.error, self.roundoff),
                 str(r.nfev),
                 _fmt(r.seconds), r.status] for r in self.runs]
        return (format_table(["method", "p", "setting", f"error [{unit}]", "nfev", "CPU [s]",
                             "meets", "note"], cand) + "\n" +
                format_table(["role", "method", "setting", f"{self.quantity}(t_end) [{unit}]",
                             f"error [{unit}]", "nfev", "CPU [s]", "status"], runs))

    def _explicit_fixed_question(self) -> bool:
        """Whether an explicit fixed-step method (RK4) is the question: the advised method, or,
        when none is advised, one the advisor tried (the bound may say why it fails). Elsewhere its stability bound is not printed
        (it can be far below any step the advised method takes: 6e-10 s on a stiff drill string
        that radau5 runs at its own steps)."""
        def explicit_fixed(m: str | None) -> bool:
            return m is not None and _fixed(m) and not REGISTRY["method"][m]["implicit"]
        if self.feasible:
            return explicit_fixed(self.method)
        return any(explicit_fixed(c.method) and not c.note.startswith("refused") for c in self.candidates)

    def __str__(self) -> str:
        unit = "m" if self.quantity == "x" else "m/s"
        head = [f"advise: {self.scene}, {self.law}, t_end = {self.t_end:g} s, target |error of "
                f"{QUANTITIES[self.quantity].split(' [')[0]} at t_end| <= {self.target_error:.3g} {unit}"]
        if self.feasible:
            ctl = ", ".join(f"{k}={v:.10g}" for k, v in self.controls.items())
            est = error_text(self.predicted_error, self.roundoff)
            head.append(f"use method={self.method!r}, {ctl}: estimated error {est}"
                        f"{'' if est == 'exactly 0' else ' ' + unit}, "
                        f"{self.predicted_cost['nfev']:.0f} evaluations, "
                        f"{self.predicted_cost['seconds']:.3g} s CPU")
        head.append(self.message)
        if self.stability_bound is not None and self._explicit_fixed_question():
            head.append(f"explicit fixed-step stability bound along the trajectory: h < "
                        f"{self.stability_bound:.4g} s")
        head.append(f"all {len(self.runs)} runs cost {self.pilot_cost['nfev']:.0f} evaluations, "
                    f"{self.pilot_cost['seconds']:.3g} s CPU"
                    + (f" ({self.pilot_cost['ratio']:.1f} x the advised run)"
                       if self.pilot_cost.get("ratio") is not None else ""))
        return "\n".join(head) + "\n\n" + self.table()


def _fmt(value: float | None, spec: str = ".3g") -> str:
    return "" if value is None else format(value, spec)


def error_text(error: float | None, floor: float) -> str:
    """An error estimate as printed: "exactly 0" when the runs agree exactly with nothing to
    round (q = 0 throughout: a held body), "round-off" when it is at or below the round-off
    level `floor` (ROUNDOFF eps max|q|), else three digits; never a number below the error
    that q's floating-point values can represent."""
    if error is None:
        return ""
    if error == 0.0 and floor == 0.0:
        return "exactly 0"
    if error <= floor:
        return f"round-off (<= {floor:.2g})"
    return format(error, ".3g")


def _setting(controls: dict[str, float] | None) -> str:
    if not controls:
        return ""
    return f"h = {controls['h']:.4g} s" if "h" in controls else f"rtol = {controls['rtol']:.3g}"


def format_table(header: Sequence[str], rows: Sequence[Sequence[str]]) -> str:
    """A plain text table, columns padded to their widest cell."""
    cells = [list(header)] + [list(r) for r in rows]
    width = [max(len(row[i]) for row in cells) for i in range(len(header))]
    lines = ["  ".join(c.ljust(w) for c, w in zip(row, width)).rstrip() for row in cells]
    lines.insert(1, "  ".join("-" * w for w in width))
    return "\n".join(lines) + "\n"


# ---------------------------------------------------------------------------------------------
# Stability of the explicit fixed-step methods
# ---------------------------------------------------------------------------------------------
@functools.lru_cache(maxsize=4096)
def _stability_radius(order: int, phi: float) -> float:
    """Largest r with |R(r e^(i phi))| <= 1 on all of (0, r], R(z) = sum_{k<=order} z^k/k! (the
    stability polynomial of an explicit Runge-Kutta method with as many stages as its order,
    order <= 4). RK4 on the negative real axis: 2.785."""
    coef = np.array([1.0 / math.factorial(k) for k in range(order + 1)])
    direction = complex(math.cos(phi), math.sin(phi))

    def gain(r: Any) -> Any:
        z = np.asarray(r) * direction
        return np.abs(np.polyval(coef[::-1], z))

    grid = np.linspace(1e-3, 6.0, 6000)
    bad = np.flatnonzero(gain(grid) > 1.0 + 1e-12)
    if bad.size == 0:
        return 6.0
    if bad[0] == 0:
        return 0.0
    lo, hi = float(grid[bad[0] - 1]), float(grid[bad[0]])
    for _ in range(50):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if gain(mid) <= 1.0 + 1e-12 else (lo, mid)
    return lo


def _rhs(scene: str, law: str, y: np.ndarray, params: dict[str, float]) -> np.ndarray:
    """The right-hand side f(y) of the scene (autonomous), from one RK4 step of DELTA s: (y(DELTA)
    - y) / DELTA = f + O(DELTA |J| |f|)."""
    delta = 1e-9
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RegularisedLawWarning)   # one step: the law is the question
        r = simulate(scene, law, method="rk4", h=delta, t_end=delta, n_out=1, x0=float(y[0]),
                     v0=float(y[1]), z0=y[2:] if y.size > 2 else None, **params)
    return (r.y[:, -1] - y) / delta


def jacobian_eigenvalues(scene: str, law: str, states: np.ndarray,
                         params: dict[str, float]) -> np.ndarray:
    """Eigenvalues [1/s] of the scene's Jacobian df/dy at each state (columns of `states`,
    shape (n, m)), by central differences of the right-hand side."""
    out = []
    for y in states.T:
        n = y.size
        jac = np.empty((n, n))
        for j in range(n):
            eps = 1e-6 * max(abs(y[j]), 1e-3 if j < 2 else 1e-6)
            e = np.zeros(n)
            e[j] = eps
            jac[:, j] = (_rhs(scene, law, y + e, params) - _rhs(scene, law, y - e, params)) / (2 * eps)
        if np.isfinite(jac).all():
            out.extend(np.linalg.eigvals(jac))
    return np.array(out, dtype=complex)


def stability_bound(order: int, eigenvalues: np.ndarray) -> float | None:
    """Largest h [s] at which an explicit Runge-Kutta method of `order` (<= 4, as many stages
    as its order) is stable for every eigenvalue: min over lambda of r(arg lambda)/|lambda|. An
    eigenvalue with Re >= 0 (an oscillation, or a physical growth) is judged on the imaginary
    axis. None when there is no bound (no eigenvalue, or order > 4)."""
    if order > 4 or eigenvalues.size == 0:
        return None
    bound = math.inf
    for lam in eigenvalues:
        mag = abs(lam)
        if mag < 1e-9:
            continue
        phi = math.atan2(lam.imag, lam.real) if lam.real < 0 else math.copysign(math.pi / 2, lam.imag or 1.0)
        bound = min(bound, _stability_radius(order, max(round(abs(phi), 6), math.pi / 2)) / mag)
    return None if math.isinf(bound) else bound


# ---------------------------------------------------------------------------------------------
# Pilot ladders
# ---------------------------------------------------------------------------------------------
class _Problem:
    """The problem being advised on and the runs made so far."""

    def __init__(self, scene: str, law: str, t_end: float, quantity: str, x0: float, v0: float,
                 params: dict[str, float], model: Any = None, body: int = 0) -> None:
        self.scene, self.law, self.t_end, self.quantity = scene, law, t_end, quantity
        self.x0, self.v0, self.params = x0, v0, params
        self.model, self.body = model, body         # a Model (scene "model") and its body advised on
        self.exact: Run | None = None               # the exact-stick reference run (a model)
        self.runs: list[Run] = []
        self.results: dict[int, Any] = {}          # id(Run) -> Result (for the trajectory)
        self.scale = 0.0                           # max |q| seen [m or m/s]

    def run(self, role: str, method: str, controls: dict[str, float],
            max_steps: int | None = None) -> Run:
        """Run the problem with `method` and `controls` and record it."""
        kw = dict(controls)
        if max_steps is not None:
            kw["max_steps"] = max_steps
        t0 = time.process_time()
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")     # the advisor checks RK4's bound itself
                if self.model is not None:
                    res = simulate(self.model, method=method, t_end=self.t_end, n_out=N_GRID, **kw)
                else:
                    res = simulate(self.scene, self.law, method=method, t_end=self.t_end, n_out=N_GRID,
                                   x0=self.x0, v0=self.v0, **kw, **self.params)
        except IntegrationError as exc:
            s = exc.result.stats
            run = Run(role, method, dict(controls), None, None, int(s["nfev"]), float(s["cpu_seconds"]),
                      status=s["message"], t_reached=float(s["t_reached"]))
        else:
            qs = res.x if self.quantity == "x" else res.v
            if self.model is not None:
                qs = qs[self.body]
            self.scale = max(self.scale, float(np.max(np.abs(qs))))
            run = Run(role, method, dict(controls), float(qs[-1]), None, int(res.stats["nfev"]),
                      float(res.stats["cpu_seconds"]) or (time.process_time() - t0), t_reached=self.t_end)
            self.results[id(run)] = res
        self.runs.append(run)
        return run

    @property
    def floor(self) -> float:
        """Round-off level of q [m or m/s]: 0 when every run so far gives q = 0 exactly (a
        held body), where the runs' differences are exactly 0 too."""
        return ROUNDOFF * float(np.finfo(float).eps) * self.scale


def _fixed(method: str) -> bool:
    return "h" in REGISTRY["method"][method]["controls"]


def takes(method: str, law: str) -> bool:
    """Whether `method` takes `law` (the registry's list of a method's laws; None: every law)."""
    laws = REGISTRY["method"][method].get("laws")
    return laws is None or law in laws


def controls_at(method: str, s: float, atol_ratio: float = 0.0) -> dict[str, float]:
    """The controls of `method` at setting s: h = s [s] for a fixed-step method; rtol = s,
    atol = atol_ratio s (ATOL_RATIO when 0) and no step cap (hmax = 0, where the method reads
    it) for an adaptive one."""
    s = float(s)
    if _fixed(method):
        return {"h": s}
    ctl = {"rtol": s, "atol": (atol_ratio or ATOL_RATIO) * s}
    if "hmax" in REGISTRY["method"][method]["controls"]:
        ctl["hmax"] = 0.0
    return ctl


@dataclass
class _Ladder:
    """One method's pilot runs."""

    method: str
    runs: list[Run] = field(default_factory=list)     # the successful ones, loose to tight
    failed: list[Run] = field(default_factory=list)
    ratio: float = 2.0                                 # setting ratio between rungs
    stopped: str = ""

    def diffs(self) -> list[float]:
        q = [r.q for r in self.runs]
        return [abs(a - b) for a, b in zip(q, q[1:])]


def _orders(d: list[float], ratio: float, floor: float) -> list[float]:
    """Observed orders from successive differences (a factor `ratio` apart in the setting)."""
    return [math.log(a / b) / math.log(ratio) if a > floor and b > floor else math.nan
            for a, b in zip(d, d[1:])]


def _pilot(prob: _Problem, method: str, goal: float, bound: float | None, omega: float,
           budget_seconds: float, prior_sec_per_eval: float, first: Run | None = None) -> _Ladder:
    """Run the pilot ladder of `method` (see the module's docstring) and estimate the error of
    each run. A fixed-step ladder of order p starts where an oscillation of `omega` [rad/s] (the
    fastest on the trajectory) accumulates an error of order one over the run, (omega h)^p omega
    t_end = 1: at larger steps a method can look converged when it has damped the oscillation
    away (implicit Euler settles on the centre of the belt's orbit). An explicit method starts
    within STABILITY_MARGIN `bound`. The ladder stops before a run predicted to cost more than
    `budget_seconds` (a multiple of the cheapest prediction so far; the first run of a fixed-step
    method is priced at `prior_sec_per_eval`, the lowest seconds per evaluation seen). `first`:
    the adaptive ladder's first run, when made already (the probe that orders the ladders)."""
    fixed = _fixed(method)
    lad = _Ladder(method, ratio=2.0 if fixed else 10.0)
    if fixed:
        n = N0
        if omega > 0.0:                 # (omega h)^p omega t_end <= 1: in the asymptotic range
            p = max(REGISTRY["method"][method]["order"], 1)
            n = max(n, math.ceil(prob.t_end * omega * (omega * prob.t_end) ** (1.0 / p)))
        if bound is not None:
            n = max(n, math.ceil(prob.t_end / (STABILITY_MARGIN * bound)))
        period = shortest_period(prob.model if prob.model is not None else prob.scene, **prob.params)
        if period is not None:          # never beyond the scene's own oscillation
            n = max(n, math.ceil(prob.t_end / (PERIOD_FRACTION * period)))
        setting = prob.t_end / n
        first_nfev = n * max(REGISTRY["method"][method]["order"], 1)
        if first_nfev * prior_sec_per_eval > budget_seconds:
            lad.stopped = PRUNED
            return lad
        if first_nfev > PILOT_NFEV_CAP or n > MAX_STEPS:
            lad.stopped = (f"its first pilot (h = {setting:.3g} s, within the stability bound and "
                           f"resolving the oscillation) needs about {first_nfev:.3g} evaluations: "
                           "beyond the pilot budget")
            return lad
    else:
        setting = RTOL0
    sec_per_eval = None
    for rung in range(MAX_LADDER):
        if fixed and prob.t_end / setting > MAX_STEPS:
            lad.stopped = "step count beyond max_steps"
            break
        if not fixed and setting < RTOL_MIN:
            lad.stopped = f"rtol below {RTOL_MIN:g}"
            break
        if rung == 0 and first is not None and first.q is None and first.status.startswith("step budget"):
            # the probe ran out of PROBE_MAX_STEPS: price the whole run by its pace, then rerun
            full = first.seconds * prob.t_end / max(first.t_reached, 1e-300)
            if full > budget_seconds:
                lad.stopped = PRUNED
                break
            first = None
        if rung == 0 and first is not None:
            run = first
        else:
            run = prob.run("pilot", method, controls_at(method, setting),
                           None if fixed else PILOT_MAX_STEPS)
        if run.q is None:
            lad.failed.append(run)
            if lad.runs or len(lad.failed) >= 3 or run.status.startswith("step budget"):
                lad.stopped = f"a pilot failed: {run.status}"
                break
        else:
            lad.runs.append(run)
            if run.nfev > 0 and run.seconds > 0:
                sec_per_eval = run.seconds / run.nfev
        d = lad.diffs()
        if len(d) >= 2:
            if d[-1] <= goal / 4.0 or d[-1] <= prob.floor:
                lad.stopped = "passed the target" if d[-1] > prob.floor else "reached round-off"
                break
            p = _orders(d, lad.ratio, prob.floor)
            if len(p) >= 2 and p[-1] > 0.5 and abs(p[-1] - p[-2]) <= 0.25 * max(p[-1], p[-2]):
                lad.stopped = "consistent order"
                break
        # the next rung's cost: twice (fixed) or as the last two rungs grew (adaptive)
        growth = 2.0
        if not fixed and len(lad.runs) >= 2 and lad.runs[-2].nfev > 0:
            growth = max(1.0, lad.runs[-1].nfev / lad.runs[-2].nfev)
        next_nfev = (lad.runs[-1].nfev if lad.runs else 0) * growth
        if next_nfev > PILOT_NFEV_CAP:
            lad.stopped = "pilot budget"
            break
        if sec_per_eval is not None and next_nfev * sec_per_eval > budget_seconds:
            lad.stopped = PRUNED
            break
        setting /= lad.ratio
    _estimate_errors(lad, prob.floor, float(REGISTRY["method"][method]["order"]) if fixed else 1.0)
    return lad


def _rho(lad: _Ladder, floor: float, exponent: float) -> float:
    """The ratio of successive differences (the error's shrink factor per rung), from the last
    two differences when both are above round-off, else ratio^-exponent (the method's order for
    a fixed step, 1 for a tolerance); at most 0.5."""
    d = lad.diffs()
    if len(d) >= 2 and d[-1] > floor and d[-2] > floor:
        return min(d[-1] / d[-2], 0.5)
    return min(lad.ratio ** -exponent, 0.5)


def _estimate_errors(lad: _Ladder, floor: float, exponent: float) -> None:
    """Set each pilot's error estimate: |q_k - q_K| + e_K, e_K = d rho/(1 - rho), the finest
    run's own (Richardson) error; the finest run of a one-run ladder gets none."""
    if len(lad.runs) < 2:
        return
    d_last = lad.diffs()[-1]
    rho = _rho(lad, floor, exponent)
    e_fine = max(d_last * rho / (1.0 - rho), floor)
    finest = lad.runs[-1]
    finest.error = e_fine
    for r in lad.runs[:-1]:
        r.error = abs(r.q - finest.q) + e_fine


def _fit(x: np.ndarray, y: np.ndarray) -> tuple[float, float]:
    """Least-squares (slope, intercept) of log y against log x."""
    if x.size == 1:
        return math.nan, math.nan
    slope, intercept = np.polyfit(np.log(x), np.log(y), 1)
    return float(slope), float(intercept)


def _candidate(prob: _Problem, lad: _Ladder, goal: float, bound: float | None,
               sec_per_eval: float) -> tuple[Candidate, float | None]:
    """The method's cheapest setting predicted to meet `goal`, and that setting (None: a pilot
    run itself, already verified)."""
    method = lad.method
    fixed = _fixed(method)
    cand = Candidate(method)
    if len(lad.runs) < 2:
        if lad.stopped == PRUNED or not lad.failed:
            cand.note = lad.stopped
        else:
            cand.note = f"too few pilots ({lad.failed[-1].status})"
        return cand, None
    s = np.array([_setting_of(r) for r in lad.runs])
    e = np.array([r.error for r in lad.runs])
    nfev = np.array([max(r.nfev, 1) for r in lad.runs], dtype=float)
    e_fine = e[-1]
    # reliable points: well above the finest run's own error and round-off
    rel = np.flatnonzero((e >= 4.0 * e_fine) & (e > prob.floor))[-3:]
    p, c = _fit(s[rel], e[rel]) if rel.size >= 2 else (math.nan, math.nan)
    if rel.size == 1 or (rel.size >= 2 and not p > 0.2):
        if rel.size >= 1:               # one point: the method's nominal exponent through it
            p = float(REGISTRY["method"][method]["order"]) if fixed else 1.0
            c = math.log(e[rel[-1]]) - p * math.log(s[rel[-1]])
    cand.exponent = p if math.isfinite(p) else None
    # cost model: log nfev against log s over the last three pilots
    q_cost, c_cost = _fit(s[-3:], nfev[-3:])
    if not math.isfinite(q_cost):
        q_cost, c_cost = (-1.0, math.log(nfev[-1] * s[-1])) if fixed else (0.0, math.log(nfev[-1]))

    def cost(setting: float) -> float:
        if fixed:                        # evaluations per step as in the finest pilot
            return nfev[-1] / round(prob.t_end / s[-1]) * math.ceil(prob.t_end / setting * (1 - 1e-12))
        return math.exp(c_cost + q_cost * math.log(setting))

    # a pilot that already meets the goal
    best: tuple[float, float | None, float] | None = None    # (nfev, setting or None, error)
    ok = np.flatnonzero(e <= goal)
    if ok.size:
        i = int(ok[np.argmin(nfev[ok])])
        best = (float(nfev[i]), None, float(e[i]))
        chosen_run = lad.runs[i]
    # an extrapolated setting
    if cand.exponent is not None and cand.exponent > 0.2:
        target_s = math.exp((math.log(goal) - c) / p)
        target_s = min(target_s, s[rel[0]] if rel.size else s[0])      # no looser than the data
        if fixed:
            n = math.ceil(prob.t_end / target_s * (1 - 1e-12))
            target_s = prob.t_end / n
        if bound is not None and fixed and target_s > STABILITY_MARGIN * bound:
            target_s = prob.t_end / math.ceil(prob.t_end / (STABILITY_MARGIN * bound))
        steps = prob.t_end / target_s if fixed else None
        if fixed and steps > MAX_STEPS:
            cand.note = f"needs {steps:.3g} steps (> {MAX_STEPS:.0e}) at order {p:.2f}"
        elif not fixed and target_s < RTOL_MIN:
            cand.note = f"needs rtol = {target_s:.2g} (< {RTOL_MIN:g}) at tolerance order {p:.2f}"
        elif best is None or cost(target_s) < best[0]:
            err = math.exp(c + p * math.log(target_s))
            best = (cost(target_s), target_s, max(err, prob.floor))
    elif best is None:
        cand.note = ("error at round-off in every pilot" if e_fine <= prob.floor else lad.stopped
                     if lad.stopped == PRUNED else f"no convergence seen ({lad.stopped or 'ladder ended'})")
    if best is None:
        if not cand.note:
            cand.note = f"pilots stop at error {e.min():.2g} ({lad.stopped})"
        return cand, None
    cand.feasible = True
    cand.nfev, setting, cand.predicted_error = best
    cand.seconds = cand.nfev * sec_per_eval
    cand.controls = controls_at(method, setting) if setting is not None else dict(chosen_run.controls)
    cand.note = "a pilot run" if setting is None else f"fit over {rel.size} pilots ({lad.stopped})"
    return cand, setting


def _setting_of(run: Run) -> float:
    return run.controls["h"] if "h" in run.controls else run.controls["rtol"]


def _seconds_per_eval(runs: list[Run]) -> float:
    nfev = sum(r.nfev for r in runs)
    secs = sum(r.seconds for r in runs)
    return secs / nfev if nfev > 0 and secs > 0 else 1e-7


def _has_jump(law: str, params: dict[str, float]) -> bool:
    """mu(v) jumps at v = 0 (Coulomb's sign(v))."""
    p = {k: v for k, v in params.items() if k in REGISTRY["law"][law]["params"]}
    lo, hi = friction_coefficient(law, [-1e-12, 1e-12], **p)
    return hi - lo > 1e-3


# ---------------------------------------------------------------------------------------------
# The advisor
# ---------------------------------------------------------------------------------------------
def advise(scene: Any, law: Any = None, target_error: Any = None, t_end: Any = None, *,
           quantity: str = "x", x0: float = 0.0, v0: float = 0.0, methods: Sequence[str] | None = None,
           body: int = 0, **params: float) -> Advice:
    """The cheapest method and controls that reach `target_error` on this problem.

    ``advise(model, target_error, t_end, body=0, ...)`` advises on a `stickslip.Model` (your own
    system): the error is that of body `body`'s x or v at t_end; the candidates are the methods
    that take every contact's law (event_driven and moreau, exact stick, when every contact is
    coulomb or stribeck; they are then the cross-check's reference too); the fixed-step pilots
    stay within a tenth of the shortest period of the model's springs and masses, and RK4's
    stability bound comes from the Jacobian of the bodies' positions and velocities along a
    pilot (the laws' internal states at 0 and the signals at t = 0: an estimate, which the
    verifying run checks).

    Parameters
    ----------
    scene, law : str
        As for `simulate` (SCENES but the chain, LAWS); or a `stickslip.Model` and no law.
    target_error : float
        Largest acceptable absolute error of `quantity` at t_end [m or m/s], > 0.
    t_end : float
        End of the run [s], > 0.
    quantity : {"x", "v"}
        The position x [m] or the velocity v [m/s], at t_end.
    x0, v0 : float
        Initial state [m], [m/s] (internal states of a law start at 0).
    methods : sequence of str, optional
        Candidates (default: every method of METHODS, read from the registry).
    body : int
        On a model: the body (its index, from 0) whose x or v is advised on.
    **params : float
        Physical parameters (DEFAULTS); controls are what the advisor chooses and are refused.

    Returns
    -------
    Advice
        ``method`` and ``controls`` for ``simulate(scene, law, method=a.method, t_end=t_end,
        **a.controls, **params)``, the estimated error and cost, every run made, and, when no
        method reaches the target, ``feasible`` False and a ``message`` naming what can.

    Raises
    ------
    ValueError
        A bad name, number or parameter (the message names it and the accepted range).
    """
    from .model import Model
    model = scene if isinstance(scene, Model) else None
    if model is not None:
        if law is not None and not isinstance(law, str):      # advise(model, target_error, t_end)
            law, target_error, t_end = None, law, target_error
        if law is not None or params or x0 != 0.0 or v0 != 0.0:
            raise ValueError("law, x0, v0, parameters: not for a model (its contacts have their laws and "
                             "parameters, its bodies their x0 and v0)")
        if isinstance(body, bool) or not isinstance(body, (int, np.integer)) or not 0 <= body < model.n_bodies:
            raise ValueError(f"body: must be a body index of the model (0 .. {model.n_bodies - 1}), got {body!r}")
        scene, law = "model", "+".join(dict.fromkeys(c.law for c in model.contacts)) or "none"
    else:
        _choice("scene", scene, SCENES)
    if scene == "chain":
        raise ValueError("scene: advise takes the one-body scenes (slope, belt); on the chain choose the "
                         "method with docs/guide/chain.md and run stickslip.simulate")
    if model is None:
        _choice("law", law, LAWS)
    if quantity not in QUANTITIES:
        raise ValueError(f"quantity: unknown value {quantity!r} (accepted: x for the position [m], "
                         "v for the velocity [m/s], both at t_end)")
    if isinstance(target_error, bool) or not isinstance(target_error, (int, float, np.floating, np.integer)) \
            or not math.isfinite(target_error) or target_error <= 0:
        raise ValueError(f"target_error: must be a finite number > 0 [m or m/s], got {_shown(target_error)}")
    target = float(target_error)
    if isinstance(t_end, bool) or not isinstance(t_end, (int, float, np.floating, np.integer)) \
            or not math.isfinite(t_end) or t_end <= 0:
        raise ValueError(f"t_end: must be a finite number > 0 [s], got {_shown(t_end)}")
    controls = sorted(set(params) & set(CONTROLS))
    if controls:
        raise ValueError(f"{', '.join(controls)}: controls are what advise chooses; pass only physical "
                         "parameters (stickslip.DEFAULTS)")
    given = _physical(params)
    laws = [c.law for c in model.contacts] if model is not None else [law]
    if model is None:
        friction_coefficient(law, 0.0, **{k: v for k, v in given.items() if k in REGISTRY["law"][law]["params"]})
    if methods is None:                   # every method that takes the law(s)
        methods = [m for m in METHODS if all(takes(m, lw) for lw in laws)]
    methods = [m for m in dict.fromkeys(methods)]
    for m in methods:
        _choice("method", m, METHODS)
    if not methods:
        raise ValueError("methods: give at least one (accepted: " + ", ".join(METHODS) + ")")

    prob = _Problem(scene, law, float(t_end), quantity, float(x0), float(v0), given, model, int(body))
    goal = target / SAFETY
    info = REGISTRY["method"]
    explicit_fixed = [m for m in methods if _fixed(m) and not info[m]["implicit"]]
    # The cheap predictions should come first, to prune the others: the adaptive methods first,
    # in the order of the cost of their first rung (made here as a probe), then the fixed-step
    # ones by decreasing order, the explicit last (they need the Jacobian along a trajectory).
    probes: dict[str, Run] = {}
    for m in methods:
        if not _fixed(m):
            try:
                probes[m] = prob.run("pilot", m, controls_at(m, RTOL0), PROBE_MAX_STEPS)
            except ValueError:            # refused again, with its message, by _pilot below
                pass

    def pace(m: str) -> float:           # seconds for the whole run at the probe's pace
        r = probes.get(m)
        return r.seconds * prob.t_end / max(r.t_reached, 1e-300) if r is not None else 0.0

    order = sorted(methods, key=lambda m: (m in explicit_fixed, _fixed(m), pace(m), -info[m]["order"]))
    ladders: dict[str, _Ladder] = {}
    cands: dict[str, tuple[Candidate, float | None]] = {}
    refused: dict[str, str] = {}
    eig: np.ndarray | None = None
    bound: float | None = None
    omega = 0.0
    best_seconds = math.inf
    for m in order:
        if _fixed(m) and eig is None:
            eig = _eigenvalues(prob, ladders, info)
            bounds = [b for b in (stability_bound(info[e]["order"], eig) for e in explicit_fixed)
                      if b is not None]
            bound = min(bounds) if bounds else None
            omega = float(np.max(np.abs(eig.imag))) if eig.size else 0.0
        b = bound if m in explicit_fixed else None
        try:
            lad = _pilot(prob, m, goal, b, omega, PRUNE * best_seconds,
                         min((_seconds_per_eval(x.runs) for x in ladders.values() if x.runs), default=0.0),
                         probes.get(m))
        except ValueError as exc:          # the method cannot take this law or these parameters
            refused[m] = str(exc)
            continue
        ladders[m] = lad
        cand, setting = _candidate(prob, lad, goal, b, _seconds_per_eval(lad.runs))
        cands[m] = (cand, setting)
        if cand.feasible:
            best_seconds = min(best_seconds, cand.seconds)
    if refused and not ladders:
        raise ValueError(next(iter(refused.values())))
    spe = {m: _seconds_per_eval(lad.runs) for m, lad in ladders.items()}
    advice = Advice(scene, law, float(t_end), quantity, target, given, float(x0), float(v0), False, "",
                    seconds_per_evaluation=spe, stability_bound=bound, model=model, body=int(body))
    for m, why in refused.items():
        advice.candidates.append(Candidate(m, note=f"refused: {why}"))
    ranked = sorted((c for c, _ in cands.values() if c.feasible), key=lambda c: c.seconds)
    advice.candidates += sorted((c for c, _ in cands.values()), key=lambda c: (not c.feasible, c.seconds or 0))

    floor = prob.floor
    if target <= floor:
        advice.message = (f"no method can: the target {target:.3g} is below round-off "
                          f"({ROUNDOFF:g} eps max|{quantity}| = {floor:.2g})")
    else:
        for cand in ranked:
            if _verify(prob, advice, cand, cands[cand.method][1], ladders, target):
                break
        if not advice.feasible:
            advice.message = "no method reaches the target: " + (
                _alternatives(law, given, methods) if model is None else _model_alternatives(model, methods))
    advice.runs = prob.runs
    advice.roundoff = prob.floor
    total_nfev = sum(r.nfev for r in prob.runs)
    total_s = sum(r.seconds for r in prob.runs)
    ratio = total_s / advice.predicted_cost["seconds"] if advice.feasible and advice.predicted_cost["seconds"] > 0 else None
    advice.pilot_cost = {"nfev": float(total_nfev), "seconds": total_s, "ratio": ratio}
    return advice


def _eigenvalues(prob: _Problem, ladders: dict[str, _Ladder], info: dict[str, Any]) -> np.ndarray:
    """Eigenvalues [1/s] of the Jacobian along the trajectory of the most accurate pilot so far
    (or of one survey run of the first adaptive method when none has run); empty when no run
    reached t_end."""
    runs = [r for lad in ladders.values() for r in lad.runs if id(r) in prob.results]
    if not runs:                          # only fixed-step candidates: one survey run
        survey = next((m for m in METHODS if info[m]["adaptive"]), None)
        run = prob.run("survey", survey, controls_at(survey, 1e-6), PILOT_MAX_STEPS) if survey else None
        if run is None or run.q is None:
            return np.zeros(0, dtype=complex)
        runs = [run]
    best = min(runs, key=lambda r: r.error if r.error is not None else math.inf)
    if prob.model is not None:
        return model_jacobian_eigenvalues(prob.model, prob.results[id(best)].y)
    return jacobian_eigenvalues(prob.scene, prob.law, prob.results[id(best)].y, prob.params)


def _verify(prob: _Problem, advice: Advice, cand: Candidate, setting: float | None,
            ladders: dict[str, _Ladder], target: float) -> bool:
    """Run the candidate's setting and estimate its error against a tighter run of the same
    method, tightening while the estimate misses; then compare it with the most accurate run of
    another method. On success fill in the advice."""
    method = cand.method
    lad = ladders[method]
    fixed = _fixed(method)
    p = cand.exponent if cand.exponent and cand.exponent > 0.2 else (REGISTRY["method"][method]["order"] if fixed else 1.0)
    if setting is None:                   # a pilot run, its error already estimated
        run = next(r for r in lad.runs if r.controls == cand.controls)
        return _agrees(prob, advice, cand, run, run.error, ladders, target)
    for _ in range(MAX_TIGHTEN):
        run = prob.run("verify", method, controls_at(method, setting))
        if run.q is None:
            cand.note += f"; verifying run failed: {run.status}"
            return False
        tighter = [r for r in lad.runs if _setting_of(r) < setting and r.error is not None]
        if tighter:
            ref = min(tighter, key=lambda r: r.error)
            err = abs(run.q - ref.q) + ref.error
        else:                             # one tighter run: a factor 2 in h, 10 in rtol
            s2 = max(setting / lad.ratio, RTOL_MIN) if not fixed else setting / lad.ratio
            ref = prob.run("verify", method, controls_at(method, s2))
            if ref.q is None:
                cand.note += f"; tighter verifying run failed: {ref.status}"
                return False
            rho = min((setting / s2) ** -p, 0.5)
            d = abs(run.q - ref.q)
            ref.error = max(d * rho / (1.0 - rho), prob.floor)
            err = d + ref.error
        run.error = err
        if err <= target:
            return _agrees(prob, advice, cand, run, err, ladders, target)
        new = setting * (target / SAFETY / err) ** (1.0 / p)
        if fixed:
            new = prob.t_end / math.ceil(prob.t_end / new * (1 - 1e-12))
        if (fixed and prob.t_end / new > MAX_STEPS) or (not fixed and new < RTOL_MIN):
            cand.note += "; verification missed and tightening exceeds the limits"
            return False
        setting = new
    cand.note += f"; verification missed {MAX_TIGHTEN} times"
    _exact_gap(prob, cand, run, target)
    return False


def _exact_gap(prob: _Problem, cand: Candidate, run: Run, target: float) -> None:
    """Where a candidate's own ladder did not verify but the model has an exact-stick reference
    run accurately enough to judge, say how far its last run is from it (a method that converges
    to another motion often fails its own verification on the way)."""
    exact = _exact_reference(prob)
    if exact is None or exact.error is None or exact.error > target or run.q is None:
        return
    gap = abs(run.q - exact.q)
    if gap > target + exact.error:
        cand.note += (f"; its last run differs from the exact-stick reference {exact.method} "
                      f"({exact.setting()}) by {gap:.2g} > target + its error "
                      f"{error_text(exact.error, prob.floor)}")


def _agrees(prob: _Problem, advice: Advice, cand: Candidate, run: Run, err: float,
            ladders: dict[str, _Ladder], target: float) -> bool:
    """Accept `run` if it agrees with the most accurate run of at least one other method within
    target + that run's error (a method can converge to a wrong value: implicit Euler's large
    steps damp an oscillation to its centre, forced steps at h_min bias DOPRI5), and fill in the
    advice; refuse it when it disagrees with every other method, unless a third, adaptive
    method run tight (_tiebreak) sides with it."""
    exact = _exact_reference(prob)
    if exact is not None:                 # a model whose contacts all take exact stick
        refs = [exact] if exact.error is not None and exact.error <= target else []
    else:
        refs = [min((r for r in lad.runs if r.error is not None), key=lambda r: r.error)
                for m, lad in ladders.items() if m != cand.method and any(r.error is not None for r in lad.runs)]
        refs = sorted((r for r in refs if r.error <= target), key=lambda r: r.error)   # able to judge
    agree = [r for r in refs if abs(run.q - r.q) <= target + r.error]
    if refs and not agree and exact is None:   # a third method decides, where one can run tight
        judge = _tiebreak(prob, ladders, {cand.method} | {r.method for r in refs}, target)
        if judge is not None:
            refs.append(judge)
            if abs(run.q - judge.q) <= target + judge.error:
                agree = [judge]
    if refs and not agree:
        ref = refs[0]
        cand.note += (("; differs from the exact-stick reference " if exact is not None else
                       "; differs from every other method, e.g. ") + f"{ref.method} ({ref.setting()}) by "
                      f"{abs(run.q - ref.q):.2g} > target + its error {error_text(ref.error, prob.floor)}: "
                      "refused")
        cand.feasible = False
        return False
    if agree:
        ref = agree[0]
        gap = abs(run.q - ref.q)
        check = (f"; agrees with {ref.method} ({ref.setting()}, error {error_text(ref.error, prob.floor)}) "
                 + ("exactly" if gap == 0.0 else f"within {error_text(gap, prob.floor)}"))
    else:
        check = "; no other method's run was accurate enough to cross-check against"
    advice.feasible = True
    advice.method = cand.method
    advice.controls = dict(run.controls)
    advice.predicted_error = err
    advice.predicted_cost = {"nfev": float(run.nfev), "seconds": run.seconds}
    advice.message = (f"{cand.method} is the cheapest candidate that meets the target (aimed at "
                      f"target/{SAFETY:g}, error estimated against a tighter run of the same method)"
                      + check)
    return True


def _exact_reference(prob: _Problem) -> Run | None:
    """On a model whose every contact takes exact stick (its laws those of EXACT_METHOD): a
    tight run of EXACT_METHOD (rtol = TIEBREAK_RTOL, its error estimated against rtol/10), made
    once, the reference every candidate is checked against. The event-free methods integrate the
    laws' regularised forms (Coulomb's mu_s band of width v_s), another motion, so they cannot
    judge the exact one. None elsewhere, or when EXACT_METHOD cannot run the model."""
    model = prob.model
    if model is None or not model.contacts or EXACT_METHOD not in METHODS \
            or not all(takes(EXACT_METHOD, c.law) for c in model.contacts):
        return None
    if prob.exact is None:
        a = prob.run("reference", EXACT_METHOD, controls_at(EXACT_METHOD, TIEBREAK_RTOL), PILOT_MAX_STEPS)
        b = prob.run("reference", EXACT_METHOD, controls_at(EXACT_METHOD, TIEBREAK_RTOL / 10.0), PILOT_MAX_STEPS)
        if a.q is not None and b.q is not None:
            b.error = max(abs(a.q - b.q) * 0.1 / 0.9, prob.floor)
            a.error = abs(a.q - b.q) + b.error
        prob.exact = b
    return prob.exact if prob.exact.q is not None else None


def _tiebreak(prob: _Problem, ladders: dict[str, _Ladder], exclude: set[str],
              target: float) -> Run | None:
    """A tight run of an adaptive method not in `exclude` (rtol = TIEBREAK_RTOL, its error
    estimated against rtol/10 as in the ladders), added to that method's ladder; None when no
    such method reaches an error within the target."""
    for m, lad in ladders.items():
        if m in exclude or _fixed(m):
            continue
        a = prob.run("check", m, controls_at(m, TIEBREAK_RTOL), PILOT_MAX_STEPS)
        b = prob.run("check", m, controls_at(m, TIEBREAK_RTOL / 10.0), PILOT_MAX_STEPS)
        if a.q is None or b.q is None:
            continue
        d = abs(a.q - b.q)
        b.error = max(d * 0.1 / 0.9, prob.floor)
        a.error = d + b.error
        lad.runs += [a, b]
        lad.runs.sort(key=lambda r: -_setting_of(r))
        if b.error <= target:
            return b
    return None


def _alternatives(law: str, params: dict[str, float], tried: Sequence[str]) -> str:
    """What can reach a target the candidates cannot. For a law whose mu jumps at v = 0: the
    set-valued methods (when registered and not tried) and a smooth or regularised law; else the
    methods left out with `methods=`, or a looser target."""
    if not _has_jump(law, params):
        left = [m for m in METHODS if m not in tried]
        return ("the candidates' notes say why each failed; "
                + (f"the methods left out ({', '.join(left)}) may, " if left else "")
                + "or a looser target")
    parts = [f"{law}'s mu(v) jumps at v = 0, so event-free stepping converges at order 1 at best "
             "and chatters while the body should stick"]
    nonsmooth = [m for m in NONSMOOTH_METHODS if m in METHODS]
    untried = [m for m in nonsmooth if m not in tried]
    if untried:
        parts.append("try " + " or ".join(f"method={m!r}" for m in untried) + " (set-valued friction)")
    elif not nonsmooth:
        parts.append("a method with set-valued friction (an exact stick) would; none is registered")
    smooth = [l for l in ("stribeck", "karnopp", "recurdyn") if l in LAWS and l != law]
    parts.append("or model the friction with a smooth or regularised law (" + ", ".join(smooth) +
                 "): the pilots of such a law converge at the methods' orders")
    return "; ".join(parts)


def _model_alternatives(model: Any, tried: Sequence[str]) -> str:
    """_alternatives for a model: that of its first contact whose law jumps (else its first)."""
    if not model.contacts:
        return "the candidates' notes say why each failed; or a looser target"
    jumps = [c for c in model.contacts if _has_jump(c.law, c.params)]
    c = (jumps or model.contacts)[0]
    return _alternatives(c.law, dict(c.params), tried)


def model_jacobian_eigenvalues(model: Any, states: np.ndarray) -> np.ndarray:
    """Eigenvalues [1/s] of a model's Jacobian in the bodies' positions and velocities at each
    state (columns of `states`: x, v, then internal states, which are ignored), by central
    differences of the right-hand side from one tiny RK4 step at t = 0 with the laws' internal
    states at 0: an estimate for the stability bound (the signals and the internal states are
    those of the start)."""
    from .model import Model
    nb = model.n_bodies
    base = model.to_dict()
    delta = 1e-9

    def rhs(y: np.ndarray) -> np.ndarray:
        for i, row in enumerate(base["body"]):
            row["x0"], row["v0"] = float(y[i]), float(y[nb + i])
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RegularisedLawWarning)   # one step: the law is the question
            r = simulate(Model.from_dict(base), method="rk4", h=delta, t_end=delta, n_out=1)
        return (np.concatenate([r.x[:, -1], r.v[:, -1]]) - y) / delta

    out = []
    for y in states[:2 * nb].T:
        jac = np.empty((2 * nb, 2 * nb))
        for j in range(2 * nb):
            eps = 1e-6 * max(abs(y[j]), 1e-3)
            e = np.zeros(2 * nb)
            e[j] = eps
            jac[:, j] = (rhs(y + e) - rhs(y - e)) / (2 * eps)
        if np.isfinite(jac).all():
            out.extend(np.linalg.eigvals(jac))
    return np.array(out, dtype=complex)
