"""Bifurcations found by `stickslip.continuation` against independent computations, the
numbers docs/guide/steady-states.md quotes::

    python -m benchmarks.steady_bifurcations                              # print them
    python -m benchmarks.steady_bifurcations --outdir benchmarks/results  # the guide's numbers

* Period doubling and folds of periodic orbits: a unit mass on a unit spring on a belt at
  0.1 m/s with a falling Stribeck law (regularised by its tanh ramp, so the flow is smooth),
  forced by F cos(W t) (`forced_belt`). Continued in W at F = 0.3 its period-1 orbit
  period-doubles twice (a bubble); continued down in F at W = 1 it turns at two saddle-node
  folds. Each located value is compared with a computation by scipy written here: shooting on
  solve_ivp (DOP853, rtol 1e-12) with the variational equations of the law written out, and a
  bracketing root (brentq) of mu_min + 1 over W for the period doubling, and of dF/dx(0) along
  the branch (Newton on (v(0), F) at fixed x(0), the implicit function theorem) for the fold.
* Folds at the edge of frequency locking: the forced belt weakly self-excited (growth rate eps:
  a viscous term c_v cancels all but -2 eps of the law's falling slope, `locking_belt`) and
  forced at W = 1 + eps / 4, continued down in F: its two folds against those of the
  first-order averaged equations (`averaged_locking`) as eps halves (the gap should halve),
  the first also against scipy's, and the averaged lower fold against Adler's locking edge
  F = 2 a0 |W - 1| (Proc. IRE 34, 1946) as (W - 1) / eps shrinks.
  `python -m benchmarks.steady_bifurcations --only locking` prints this entry alone.
* Neimark-Sacker: a unit mass and spring on a belt at 0.1 m/s, a falling stribeck law with a
  viscous term (self-excited sliding that saturates before a stick), forced by F cos(1.3 t)
  (`sliding_belt`); continued down in F, a complex pair leaves the unit circle. Against the
  root of |mu| - 1 of scipy's multipliers (variational equations, brentq).
* A pitchfork and a period doubling of Den Hartog's oscillator with static friction above the
  kinetic one (`stop_oscillator`; Shaw, J. Sound Vib. 108, 1986): the symmetric motion with two
  stops per period, continued in the frequency ratio, has a multiplier through +1 where pairs
  of asymmetric motions are born; the motion with one stop and one reversal then period-doubles.
  Both against the maps of the stop position in closed form (`stop_motion`).
* The Hopf point of steady sliding on the damped belt (m = 10 kg, k = 300 N/m, v_b = 1.5 m/s,
  the `proposed` law, a damper c), continued as equilibria in c: against c + N mu'(v_b) = 0.
* Bilinear hysteresis (Caughey, J. Appl. Mech. 27, 1960): a mass on a spring and a Jenkins
  element (the elastoplastic law in its Jenkins limit, `jenkins_oscillator`), forced; its
  response curve by shooting against Caughey's one-harmonic closed form (`caughey_amplitudes`),
  which has one amplitude at every frequency (no fold, no jump: the jumps of Iwan's 1965 double
  bilinear model do not occur with one Jenkins element).
* A LuGre stick-slip cycle (the belt at v_b = 0.1 m/s, radau5): its bristle state among the
  shooting unknowns; its period against a 60 s transient's.

No assertion here (the tests in tests/test_steady.py assert); CPU times are of this machine.
"""
from __future__ import annotations

import argparse
import math
import time
from typing import Any, Callable, Sequence

import numpy as np

#: the forced belt's law (stribeck) and belt speed [m/s]
MU_S, MU_K, V_S, DELTA, V_EPS, V_B = 0.4, 0.3, 0.1, 2.0, 0.01, 0.1


def forced_belt(w: float = 1.0, amp: float | None = 0.3, c_v: float = 0.0, v_b: float = V_B) -> Any:
    """Unit mass and spring on a belt at v_b, stribeck friction (N = 1, viscous term c_v),
    forced by amp cos(w t) (unforced, an autonomous model, for amp None)."""
    import stickslip as ss
    model = ss.Model()
    b = model.add_body(1.0)
    model.add_spring(b, None, k=1.0)
    if amp is not None:
        model.add_force(b, ss.signal.sine(amp, w / (2 * math.pi), math.pi / 2))
    model.add_contact(b, None, "stribeck", normal_force=1.0, surface_velocity=v_b, mu_s=MU_S, mu_k=MU_K,
                      v_s=V_S, delta=DELTA, c_v=c_v, v_eps=V_EPS)
    return model


def _mu_and_slope(s: Any, c_v: float = 0.0) -> tuple[Any, Any]:
    """The stribeck law mu(s) = g(|s|) tanh(s / v_eps) + c_v s, g = mu_k + (mu_s - mu_k)
    exp(-(|s|/v_s)^delta), and its derivative, written out (s a float or an array)."""
    a = np.abs(s)
    e = np.exp(-(a / V_S) ** DELTA)
    g = MU_K + (MU_S - MU_K) * e
    dg = -(MU_S - MU_K) * e * DELTA * (a / V_S) ** (DELTA - 1) / V_S
    th = np.tanh(s / V_EPS)
    return g * th + c_v * s, dg * np.abs(th) + g / (V_EPS * np.cosh(s / V_EPS) ** 2) + c_v


def scipy_period(y0: np.ndarray, w: float, amp: float, c_v: float = 0.0, v_b: float = V_B
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The forced belt's state after one forcing period from y0 at t = 0, its derivative in y0
    (2 x 2) and in amp, by scipy's DOP853 on the equations and their variations (the law's
    viscous term c_v and the belt speed v_b as given: `forced_belt`'s by default)."""
    from scipy.integrate import solve_ivp

    def rhs(t: float, z: np.ndarray) -> np.ndarray:
        mu, dmu = _mu_and_slope(z[1] - v_b, c_v)
        jac = np.array([[0.0, 1.0], [-1.0, -dmu]])
        return np.concatenate([[z[1], amp * math.cos(w * t) - z[0] - mu], (jac @ z[2:6].reshape(2, 2)).ravel(),
                               jac @ z[6:] + [0.0, math.cos(w * t)]])
    z = solve_ivp(rhs, (0.0, 2 * math.pi / w), np.concatenate([y0, np.eye(2).ravel(), [0.0, 0.0]]),
                  method="DOP853", rtol=1e-12, atol=1e-13).y[:, -1]
    return z[:2], z[2:6].reshape(2, 2), z[6:]


def scipy_period_doubling(w_lo: float, w_hi: float, y0: np.ndarray, amp: float = 0.3) -> float:
    """The forcing frequency in [w_lo, w_hi] where the period-1 orbit's smallest multiplier is
    -1: brentq (to 1e-12) on mu_min + 1, each orbit by Newton on the scipy flow from the last."""
    from scipy.optimize import brentq
    y = np.array(y0, dtype=float)

    def test_function(w: float) -> float:
        nonlocal y
        for _ in range(30):
            y1, m, _ = scipy_period(y, w, amp)
            dy = np.linalg.solve(m - np.eye(2), y - y1)
            y = y + dy
            if np.max(np.abs(dy)) < 1e-12:
                break
        return float(np.min(np.linalg.eigvals(scipy_period(y, w, amp)[1]).real)) + 1.0
    return float(brentq(test_function, w_lo, w_hi, xtol=1e-12))


def scipy_fold(x_lo: float, x_hi: float, v0: float, amp: float, w: float = 1.0, c_v: float = 0.0,
               v_b: float = V_B) -> float:
    """The forcing amplitude at the fold of the period-1 orbits at forcing frequency w, the
    branch parametrised by x(0) in [x_lo, x_hi]: each point by Newton on (v(0), F), dF/dx(0) by
    the implicit function theorem, its root by brentq (to 1e-12); (v0, amp) a start on it; c_v
    and v_b as for `scipy_period`."""
    from scipy.optimize import brentq
    state = {"v0": v0, "amp": amp}

    def slope(x0: float) -> float:
        v, a = state["v0"], state["amp"]
        for _ in range(40):
            y1, m, da = scipy_period(np.array([x0, v]), w, a, c_v, v_b)
            d = np.linalg.solve(np.column_stack([m[:, 1] - [0.0, 1.0], da]), [x0, v] - y1)
            v, a = v + d[0], a + d[1]
            if np.max(np.abs(d)) < 1e-13:
                break
        _, m, da = scipy_period(np.array([x0, v]), w, a, c_v, v_b)
        state.update(v0=v, amp=a)
        return float(np.linalg.solve(np.column_stack([m[:, 1] - [0.0, 1.0], da]), -(m[:, 0] - [1.0, 0.0]))[1])
    slope(brentq(slope, x_lo, x_hi, xtol=1e-12))
    return float(state["amp"])


# ------------------------------------------------------------------------------------------
# Neimark-Sacker: a forced self-excited sliding belt
# ------------------------------------------------------------------------------------------
#: the sliding belt's law (stribeck, N = 1), belt speed [m/s] and forcing frequency [rad/s]
NS_LAW = {"mu_s": 0.4, "mu_k": 0.3, "v_s": 0.1, "delta": 2.0, "c_v": 0.5, "v_eps": 0.01}
NS_VB, NS_W = 0.1, 1.3


def sliding_belt(amp: float) -> Any:
    """A unit mass on a unit spring on a belt at NS_VB with the stribeck law NS_LAW, forced by
    amp cos(NS_W t). At the belt speed the law falls (N mu' = -0.236 N s/m, a negative damper),
    so steady sliding is self-excited, and the viscous c_v stops the growth before the mass
    sticks; forced away from the natural frequency (1 rad/s) the period-1 response is locked at
    larger amp and, as amp falls, a complex pair of multipliers leaves the unit circle (a
    Neimark-Sacker point, as at the edge of a forced van der Pol oscillator's locking region)."""
    import stickslip as ss
    model = ss.Model()
    b = model.add_body(1.0)
    model.add_spring(b, None, k=1.0)
    model.add_force(b, ss.signal.sine(amp, NS_W / (2 * math.pi), math.pi / 2))
    model.add_contact(b, None, "stribeck", normal_force=1.0, surface_velocity=NS_VB, **NS_LAW)
    return model


def scipy_sliding_belt_multipliers(amp: float, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The period-1 orbit of `sliding_belt(amp)` (Newton from y) and its multipliers, by scipy's
    DOP853 (rtol 1e-12) on the equations and their variations, the law and its slope written
    out here: mu(s) = g(|s|) tanh(s/v_eps) + c_v s, g = mu_k + (mu_s - mu_k) exp(-(|s|/v_s)^2)."""
    from scipy.integrate import solve_ivp
    p = NS_LAW

    def law(s: float) -> tuple[float, float]:
        a = abs(s)
        e = math.exp(-(a / p["v_s"]) ** 2)
        g = p["mu_k"] + (p["mu_s"] - p["mu_k"]) * e
        dg = -(p["mu_s"] - p["mu_k"]) * e * 2.0 * a / p["v_s"] ** 2
        th = math.tanh(s / p["v_eps"])
        return g * th + p["c_v"] * s, dg * abs(th) + g / (p["v_eps"] * math.cosh(s / p["v_eps"]) ** 2) + p["c_v"]

    def period(y0: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        def rhs(t: float, z: np.ndarray) -> np.ndarray:
            mu, dmu = law(z[1] - NS_VB)
            jac = np.array([[0.0, 1.0], [-1.0, -dmu]])
            return np.concatenate([[z[1], amp * math.cos(NS_W * t) - z[0] - mu], (jac @ z[2:].reshape(2, 2)).ravel()])
        z = solve_ivp(rhs, (0.0, 2 * math.pi / NS_W), np.concatenate([y0, np.eye(2).ravel()]), method="DOP853",
                      rtol=1e-12, atol=1e-14).y[:, -1]
        return z[:2], z[2:].reshape(2, 2)
    y = np.array(y, dtype=float)
    for _ in range(30):
        y1, m = period(y)
        dy = np.linalg.solve(m - np.eye(2), y - y1)
        y = y + dy
        if np.max(np.abs(dy)) < 1e-12:
            break
    return y, np.linalg.eigvals(period(y)[1])


def scipy_neimark_sacker(amp_lo: float, amp_hi: float, y: np.ndarray) -> float:
    """The forcing amplitude in [amp_lo, amp_hi] where the sliding belt's complex pair has
    modulus 1: brentq (to 1e-13) on scipy's multipliers, each orbit by Newton from y."""
    from scipy.optimize import brentq
    return float(brentq(lambda a: float(np.max(np.abs(scipy_sliding_belt_multipliers(a, y)[1]))) - 1.0,
                        amp_lo, amp_hi, xtol=1e-13))


# ------------------------------------------------------------------------------------------
# Folds at the edges of frequency locking: first-order averaging and Adler's limit
# ------------------------------------------------------------------------------------------
# A weakly self-excited oscillator forced near its natural frequency locks to the forcing when
# the forcing is strong enough; the locked orbit ends in saddle-node folds. With y = x - x_e
# (x_e the sliding equilibrium), the belt is y'' + y + D(y') = F cos(W t), D(v) = mu(v - v_b)
# - mu(-v_b) (unit mass, spring and normal force). For small D, F and sigma = W - 1, the
# first-order averaged equations (Krylov and Bogoliubov; multiple scales as Nayfeh and Mook,
# Nonlinear Oscillations, 1979, treat the forced van der Pol oscillator) of y = a cos(W t + phi)
# are a' = Q(a)/2 - (F/2) sin(phi) and a phi' = -sigma a - (F/2) cos(phi), with Q(a) = (1/pi)
# int_0^2pi D(-a sin t) sin t dt. The free cycle has Q(a0) = 0; locked orbits satisfy F^2 =
# Q(a)^2 + 4 sigma^2 a^2, and its extrema in a are the folds. Near a0 the phase equation is
# Adler's (R. Adler, "A study of locking phenomena in oscillators", Proc. IRE 34, 351-357,
# 1946): a0 phi' = -sigma a0 - (F/2) cos(phi), locked for F >= 2 a0 |sigma|, the edge the
# lower fold tends to as sigma / Q'(a0) -> 0 (F_min = 2 a0 |sigma| / sqrt(1 + 4 sigma^2 /
# Q'(a0)^2) to leading order). The belt speed is at the inflection of g (v_s / sqrt(2),
# delta = 2), so that D has no quadratic term, and c_v sets D'(0) = -2 eps: the growth rate
# eps is the small parameter, with sigma = LK_KAPPA eps and F of order eps^(3/2).
#: the locking belt's speed [m/s] and detuning over growth rate sigma / eps
LK_VB, LK_KAPPA = V_S / math.sqrt(2.0), 0.25


def locking_c_v(eps: float) -> float:
    """The viscous term [s/m] that makes D'(0) = c_v + mu'(-LK_VB) = -2 eps at the belt speed."""
    return float(-_mu_and_slope(-LK_VB)[1] - 2.0 * eps)


def locking_belt(amp: float, eps: float, kappa: float = LK_KAPPA) -> Any:
    """`forced_belt` at LK_VB with D'(0) = -2 eps, forced by amp cos((1 + kappa eps) t)."""
    return forced_belt(1.0 + kappa * eps, amp, locking_c_v(eps), LK_VB)


def averaged_locking(eps: float, sigma: float, n: int = 4096) -> tuple[float, float, float]:
    """The free cycle's amplitude a0 [m] (Q(a0) = 0, brentq to 1e-15) and the folds of the
    averaged equations above at detuning sigma [rad/s]: the local minimum of F(a) = sqrt(Q(a)^2
    + 4 sigma^2 a^2) near a0 (the locking edge) and its local maximum at smaller a (where the
    saddle meets the small-amplitude orbit) [N]. Q by the trapezoidal rule on n points (spectral
    for the periodic integrand), the extrema bracketed on a grid and refined by bounded Brent."""
    from scipy.optimize import brentq, minimize_scalar
    c_v = locking_c_v(eps)
    t = np.linspace(0.0, 2.0 * math.pi, n, endpoint=False)

    def q(a: float) -> float:
        d = _mu_and_slope(-a * np.sin(t) - LK_VB, c_v)[0] - _mu_and_slope(-LK_VB, c_v)[0]
        return float(2.0 * np.mean(d * np.sin(t)))

    def f2(a: float) -> float:
        return q(a) ** 2 + 4.0 * sigma ** 2 * a ** 2
    a0 = brentq(q, 1e-6, 0.99 * LK_VB, xtol=1e-15)
    grid = np.linspace(0.02, 1.5, 300) * a0
    vals = np.array([f2(a) for a in grid])
    i_min = int(np.argmin(vals[grid > 0.5 * a0])) + int(np.sum(grid <= 0.5 * a0))
    i_max = int(np.argmax(vals[:i_min]))
    folds = []
    for i, sign in ((i_min, 1.0), (i_max, -1.0)):
        r = minimize_scalar(lambda a: sign * f2(a), bounds=(grid[i - 1], grid[i + 1]), method="bounded",
                            options={"xatol": 1e-14 * a0})
        folds.append(math.sqrt(f2(r.x)))
    return float(a0), folds[0], folds[1]


# ------------------------------------------------------------------------------------------
# A pitchfork and a period doubling of the forced oscillator with static friction
# ------------------------------------------------------------------------------------------
# Shaw (S. W. Shaw, "On the dynamic response of a system with dry friction", J. Sound Vib.
# 108(2), 305-325, 1986) extended Den Hartog's oscillator to a static coefficient above the
# kinetic one and showed that "the symmetric motions with two stops per period can be unstable
# and that pairs of unsymmetric motions are born at the bifurcation points" (his abstract; his
# values are in figures this project could not read). Both maps below are in closed form
# (derived here; m = k = 1, P0 cos(beta t), P0 = 1, kinetic friction r, static r_s). A slip from
# rest at (t0, x0) under x'' + x = cos(beta t) + s (s = -r up, +r down) is x = A cos(t - t0) +
# B sin(t - t0) + V cos(beta t) + s, V = 1 / (1 - beta^2), A = x0 - V cos(beta t0) - s,
# B = V beta sin(beta t0); it ends where x' = 0, and its end (x_1, t_1) varies with (x0, t0) as
# dx_1 = cos(d) dx0 + (A + B') sin(d) dt0 and dt_1 = (sin(d) dx0 - (A + B') cos(d) dt0) / a_1,
# d = t_1 - t0, B' = V beta^2 cos(beta t0), a_1 the acceleration at the end (x' = 0 there, so the
# end time's variation does not move x_1). Stuck at -X, the mass breaks away up at t_b where
# X + cos(beta t_b) = r_s (sin(beta t_b) < 0), so dt_b / dX = 1 / (beta sin(beta t_b)). A stick
# forgets the velocity, so the motion is the fixed point of a map of the stop position X, and
# the monodromy's multipliers are 0 (the stick) and the map's derivative:
# * the symmetric motion with two stops per period: the half period's map g (slip up from -X,
#   stop at +X' = g(X), mirrored), multipliers 0 and g'(X)^2. Where g' passes -1 the full
#   multiplier passes +1 while the symmetric motion goes on: the pitchfork (a "branch point").
# * beyond it the asymmetric motions lose their second stop (near beta = 0.55 at r = 0.3,
#   r_s = 0.9, the mass turns at the top without sticking): the period's map F (slip up from
#   -X, a reversal, slip down, stop at -X' = -F(X)), multipliers 0 and F'(X); where F' passes
#   -1, a period doubling.
def stop_oscillator(beta: float, r: float = 0.3, r_s: float = 0.9) -> Any:
    """Den Hartog's oscillator (cases.gallery_denhartog) with static friction r_s > r."""
    import stickslip as ss
    model = ss.Model()
    b = model.add_body(1.0)
    model.add_spring(b, None, k=1.0)
    model.add_force(b, ss.signal.sine(1.0, beta / (2 * math.pi), math.pi / 2))
    model.add_contact(b, None, "coulomb", normal_force=r, mu_s=r_s / r, mu_k=1.0)
    return model


def _slip_from_rest(beta: float, t0: float, x0: float, s: float) -> tuple[float, float, np.ndarray]:
    """End time and position of a slip from rest at (t0, x0) (see above) and d(x_1, t_1) /
    d(x0, t0); the end is the first zero of x' after t0 (a scan of 4000 steps over two periods,
    then brentq to 1e-15)."""
    from scipy.optimize import brentq
    v = 1.0 / (1.0 - beta ** 2)
    a, b = x0 - v * math.cos(beta * t0) - s, v * beta * math.sin(beta * t0)
    b1 = v * beta ** 2 * math.cos(beta * t0)

    def vel(t: float) -> float:
        return -a * math.sin(t - t0) + b * math.cos(t - t0) - v * beta * math.sin(beta * t)
    grid = t0 + np.arange(1, 4001) * (4 * math.pi / beta) / 4000
    vals = np.array([vel(t) for t in grid])
    k = int(np.flatnonzero(np.sign(vals[1:]) != np.sign(vals[:-1]))[0])
    t1 = brentq(vel, grid[k], grid[k + 1], xtol=1e-15)
    x1 = a * math.cos(t1 - t0) + b * math.sin(t1 - t0) + v * math.cos(beta * t1) + s
    acc = -x1 + math.cos(beta * t1) + s
    c, sn = math.cos(t1 - t0), math.sin(t1 - t0)
    return t1, x1, np.array([[c, (a + b1) * sn], [sn / acc, -(a + b1) * c / acc]])


def _stop_map(beta: float, r: float, r_s: float, x_stop: float, reversal: bool
              ) -> tuple[float, float, tuple[float, float, float]]:
    """From a stop at -x_stop: the next stop position (mirrored: +X' for the half map, -X' for
    the period's map with a reversal), the map's derivative, and (t_b, the end of the last
    slip, the force check at the reversal or 0)."""
    tb = (2 * math.pi - math.acos(r_s - x_stop)) / beta
    d = np.array([-1.0, 1.0 / (beta * math.sin(beta * tb))])          # d(x0, t_b) / dX
    t1, x1, j = _slip_from_rest(beta, tb, -x_stop, -r)
    turn = 0.0
    if reversal:
        turn = abs(-x1 + math.cos(beta * t1))
        t1, x1, j2 = _slip_from_rest(beta, t1, x1, r)
        j = j2 @ j
        x1, j = -x1, -j
    return x1, float((j @ d)[0]), (tb, t1, turn)


def stop_motion(beta: float, reversal: bool, r: float = 0.3, r_s: float = 0.9) -> tuple[float, float]:
    """The stop position X of the symmetric two-stop motion (reversal False) or of the motion
    with one stop and one reversal (True), the fixed point of its map (brentq in [1.0, r_s +
    0.99] to 1e-15), and the map's derivative there (g'(X); the multiplier is its square, or
    F'(X), the multiplier). ValueError when the motion fails its checks: a reversal where the
    force exceeds r_s, a stop that holds until the next breakaway."""
    from scipy.optimize import brentq
    x_stop = brentq(lambda x: _stop_map(beta, r, r_s, x, reversal)[0] - x, 1.0, r_s + 0.99, xtol=1e-15)
    _, slope, (tb, t_end, turn) = _stop_map(beta, r, r_s, x_stop, reversal)
    # stuck at the stop (at +X, mirrored: -X + cos) until the next breakaway, half a period or a period after t_b
    sign, until = (1.0, tb + 2 * math.pi / beta) if reversal else (-1.0, tb + math.pi / beta)
    t = np.linspace(t_end, until, 2001)
    held = bool(np.all(np.abs(sign * x_stop + np.cos(beta * t)) <= r_s * (1 + 1e-9)))
    if not held or (reversal and not turn > r_s):
        raise ValueError(f"beta = {beta}: not the motion of the closed form (stop held {held}, reversal force {turn})")
    return x_stop, slope


def closed_form_bifurcation(beta_lo: float, beta_hi: float, reversal: bool) -> float:
    """The forcing frequency ratio in [beta_lo, beta_hi] where the map's derivative is -1 (the
    pitchfork of the symmetric motion, or the one-stop motion's period doubling): brentq to 1e-14."""
    from scipy.optimize import brentq
    return float(brentq(lambda b: stop_motion(b, reversal)[1] + 1.0, beta_lo, beta_hi, xtol=1e-14))


def damped_belt(c: float) -> Any:
    """The paper's belt (m = 10 kg, k = 300 N/m, v_b = 1.5 m/s), `proposed` law, a damper c."""
    import stickslip as ss
    m = ss.Model.from_scene("belt", "proposed", v0=1.5)
    m.add_damper(0, None, c)
    return m


# ------------------------------------------------------------------------------------------
# Bilinear hysteresis (Caughey 1960): a mass on a spring and a Jenkins element
# ------------------------------------------------------------------------------------------
#: mass [kg], linear spring k [N/m], the Jenkins element's spring k_t [N/m] and slip force F_s
#: [N], a light damper c [N s/m] and the forcing amplitude P [N] (P < 4 F_s / pi: bounded)
JK_M, JK_K, JK_KT, JK_FS, JK_C, JK_P = 1.0, 0.25, 0.75, 0.75, 0.05, 0.6


def jenkins_oscillator(w: float, ratio: float = 0.999) -> Any:
    """m x'' + c x' + k x + f_J = P cos(w t), f_J the force of a Jenkins element (a spring k_t
    in series with a Coulomb slider of limit F_s): the elastoplastic law with N = 1, sigma0 =
    k_t, mu_s = mu_k = F_s (g constant), sigma1 = sigma2 = 0 and z_ba = `ratio` F_s / k_t; it
    is a Jenkins element except between z_ba and F_s / k_t, where the law's attachment ramps
    the slip in (the limit ratio -> 1)."""
    import stickslip as ss
    model = ss.Model()
    b = model.add_body(JK_M)
    model.add_spring(b, None, k=JK_K)
    model.add_damper(b, None, c=JK_C)
    model.add_force(b, ss.signal.sine(JK_P, w / (2 * math.pi), math.pi / 2))
    model.add_contact(b, None, "elastoplastic", normal_force=1.0, mu_s=JK_FS, mu_k=JK_FS, sigma0=JK_KT,
                      sigma1=0.0, sigma2=0.0, z_ba_ratio=ratio)
    return model


def caughey_residual(a: Any, w: float) -> Any:
    """The one-harmonic balance of `jenkins_oscillator` at amplitude(s) a [m] and frequency w
    [rad/s] (Caughey 1960, J. Appl. Mech. 27(4) 640-643): the Jenkins element's describing
    function under x = a cos(theta), with x_y = F_s / k_t and cos(beta) = 1 - 2 x_y / a, has the
    in-phase part C = k_t a (beta - sin(2 beta) / 2) / pi and the quadrature part S = 4 F_s (1
    - x_y / a) / pi (k_t a and 0 for a <= x_y); the amplitude solves
    (k a + C - m w^2 a)^2 + (S + c w a)^2 = P^2. Returns the left side minus P^2 [N^2]."""
    a = np.asarray(a, dtype=float)
    xy = JK_FS / JK_KT
    beta = np.arccos(np.clip(1.0 - 2.0 * xy / a, -1.0, 1.0))
    c_in = np.where(a > xy, JK_KT * a * (beta - 0.5 * np.sin(2.0 * beta)) / math.pi, JK_KT * a)
    s_q = np.where(a > xy, 4.0 * JK_FS * (1.0 - xy / a) / math.pi, 0.0)
    return (JK_K * a + c_in - JK_M * w * w * a) ** 2 + (s_q + JK_C * w * a) ** 2 - JK_P ** 2


def caughey_amplitudes(w: float, a_max: float = 100.0, n: int = 20001) -> list[float]:
    """Every root a in (0, a_max] of `caughey_residual` at w: sign changes on a geometric grid
    of n amplitudes, each refined by brentq (to 1e-14)."""
    from scipy.optimize import brentq
    a = np.geomspace(1e-4, a_max, n)
    g = caughey_residual(a, w)
    roots = np.nonzero(np.sign(g[1:]) != np.sign(g[:-1]))[0]
    return [float(brentq(lambda x: float(caughey_residual(x, w)), a[i], a[i + 1], xtol=1e-14)) for i in roots]


def _cpu(fn: Callable[[], Any]) -> tuple[Any, float]:
    t0 = time.process_time()
    out = fn()
    return out, time.process_time() - t0


def guide_numbers() -> dict[str, tuple[float, str, str]]:
    """Each (value, unit, what)."""
    import stickslip as ss
    out: dict[str, tuple[float, str, str]] = {}
    br, cpu = _cpu(lambda: ss.continuation(forced_belt, 0.85, 1.65, method="dopri5", step=0.05, max_step=0.1))
    pd = [b for b in br.bifurcations if b["kind"] == "period doubling"]
    out["pd.points"] = (len(br), "", "points of the branch in W from 0.85 to 1.65")
    out["pd.cpu"] = (cpu, "s", "its CPU time, the two period doublings located included")
    for k, b in enumerate(pd, 1):
        i = b["index"]
        exact = scipy_period_doubling(br.p[i - 1], br.p[i], br.orbits[i].y0)
        out[f"pd.w{k}"] = (b["p"], "rad/s", f"period doubling {k}")
        out[f"pd.err{k}"] = (abs(b["p"] / exact - 1), "", "relative distance to scipy's")
    br, cpu = _cpu(lambda: ss.continuation(lambda a: forced_belt(1.0, a), 0.06, 0.02, method="dopri5", step=0.05,
                                           max_step=0.1))
    folds = [b for b in br.bifurcations if b["kind"] == "fold"]
    out["fold.points"] = (len(br), "", "points of the branch in F from 0.06 to 0.02")
    out["fold.cpu"] = (cpu, "s", "its CPU time, the two folds located included")
    for k, b in enumerate(folds, 1):
        out[f"fold.f{k}"] = (b["p"], "", f"fold {k}: the forcing amplitude")
    i = folds[0]["index"]
    exact = scipy_fold(float(br.orbits[i - 1].x0[0]), float(br.orbits[i + 1].x0[0]), float(br.orbits[i].v0[0]),
                       float(br.p[i]))
    out["fold.err1"] = (abs(folds[0]["p"] / exact - 1), "", "relative distance of fold 1 to scipy's")
    out.update(_closed_form_numbers())
    out.update(_jenkins_numbers())
    out.update(_locking_numbers())
    rough = ss.continuation(lambda a: forced_belt(1.0, a), 0.06, 0.02, method="dopri5", step=0.05, max_step=0.1,
                            locate_bifurcations=False)
    out["fold.rough_err1"] = (abs(rough.bifurcations[0]["p"] / exact - 1), "", "the same, at the turning point")
    # the Hopf point of steady sliding, as equilibria in c
    eq, cpu = _cpu(lambda: ss.continuation(damped_belt, 0.5, 1.5, kind="equilibrium", step=0.1))
    slope = float(np.diff(ss.friction_coefficient("proposed", np.array([1.5 - 1e-6, 1.5 + 1e-6])))[0] / 2e-6)
    c_hopf = -10.0 * 9.81 * slope
    out["eq.cpu"] = (cpu, "s", "CPU time of 11 equilibria and the Hopf point located")
    out["eq.hopf"] = (eq.bifurcations[0]["p"], "N s/m", "Hopf point of the equilibria")
    out["eq.err"] = (abs(eq.bifurcations[0]["p"] / c_hopf - 1), "", "relative distance to -N mu'(v_b)")
    # LuGre
    lugre = ss.Model.from_scene("belt", "lugre", v_b=0.1)
    orb, cpu = _cpu(lambda: ss.periodic_orbit(lugre, method="radau5"))
    out["lugre.cpu"] = (cpu, "s", "CPU time of the LuGre cycle")
    out["lugre.period"] = (orb.period, "s", "its period")
    out["lugre.z0"] = (float(orb.z0[0]), "m", "the bristle deflection at the section")
    out["lugre.multiplier"] = (float(np.abs(orb.nontrivial).max()), "", "largest nontrivial multiplier")
    return out


def _closed_form_numbers() -> dict[str, tuple[float, str, str]]:
    """The Neimark-Sacker point of the sliding belt and the stop oscillator's pitchfork and
    period doubling, each (value, unit, what), against their independent computations."""
    import stickslip as ss
    out: dict[str, tuple[float, str, str]] = {}
    br, cpu = _cpu(lambda: ss.continuation(sliding_belt, 0.06, 0.02, method="dopri5", step=0.05, max_step=0.1))
    b = br.bifurcations[0]
    i = b["index"]
    exact = scipy_neimark_sacker(br.p[i], br.p[i - 1], br.orbits[i].y0)
    out["ns.points"] = (len(br), "", "points of the sliding belt's branch in F from 0.06 to 0.02")
    out["ns.cpu"] = (cpu, "s", "its CPU time, the Neimark-Sacker point located included")
    out["ns.f"] = (b["p"], "N", "the Neimark-Sacker point")
    out["ns.err"] = (abs(b["p"] / exact - 1), "", "relative distance to scipy's")
    out["ns.angle"] = (float(np.max(np.angle(br.multipliers[i]))), "rad", "the pair's angle there")
    for key, lo, hi, reversal, kind in (("bp", 0.3, 0.48, False, "branch point"),
                                         ("pd_stop", 0.56, 0.68, True, "period doubling")):
        br, cpu = _cpu(lambda: ss.continuation(stop_oscillator, lo, hi, step=0.05, max_step=0.1))
        b = br.bifurcations[0]
        i = b["index"]
        exact = closed_form_bifurcation(br.p[i - 1], br.p[i], reversal)
        worst = 0.0
        for p, o in zip(br.p, br.orbits):
            slope = stop_motion(p, reversal)[1]
            found = o.multipliers[np.argmax(np.abs(o.multipliers))].real
            worst = max(worst, float(abs(found - (slope if reversal else slope ** 2))))
        out[f"{key}.points"] = (len(br), "", f"points of the stop oscillator's branch in beta from {lo} to {hi}")
        out[f"{key}.cpu"] = (cpu, "s", f"its CPU time, the {kind} located included")
        out[f"{key}.beta"] = (b["p"], "", f"the {kind}")
        out[f"{key}.err"] = (abs(b["p"] / exact - 1), "", "relative distance to the closed form's")
        out[f"{key}.mult_err"] = (worst, "", "largest distance of a multiplier to the closed form's")
    return out


def _jenkins_numbers() -> dict[str, tuple[float, str, str]]:
    """The response curve of `jenkins_oscillator` by shooting against Caughey's one-harmonic
    closed form, each (value, unit, what)."""
    import stickslip as ss
    out: dict[str, tuple[float, str, str]] = {}
    ws = np.linspace(0.3, 1.6, 27)
    br, cpu = _cpu(lambda: ss.frequency_response(lambda f: jenkins_oscillator(2 * math.pi * f), ws / (2 * math.pi),
                                                  method="radau5"))
    one = np.array([caughey_amplitudes(float(w)) for w in ws], dtype=object)
    roots = [len(r) for r in one]
    a1 = np.array([r[0] for r in one], dtype=float)
    gap = br.amplitude / a1 - 1.0
    yielding = a1 > JK_FS / JK_KT
    out["jk.points"] = (len(br.curve), "", "points of the continued curve from 0.3 to 1.6 rad/s")
    out["jk.cpu"] = (cpu, "s", "CPU time of the response at 27 frequencies")
    out["jk.folds"] = (sum(b["kind"] == "fold" for b in br.curve.bifurcations), "", "folds on the continued curve")
    out["jk.roots_max"] = (max(roots), "", "most one-harmonic amplitudes at one frequency")
    out["jk.elastic_err"] = (float(np.max(np.abs(gap[~yielding]))), "", "largest relative gap, elastic motions")
    k = int(np.argmax(np.abs(gap)))
    out["jk.gap_max"] = (float(abs(gap[k])), "", "largest relative gap of the exact amplitude to the one-harmonic")
    out["jk.gap_w"] = (float(ws[k]), "rad/s", "where")
    far = yielding & (ws >= 0.8)
    out["jk.gap_far"] = (float(np.max(np.abs(gap[far]))), "", "largest relative gap from 0.8 rad/s on")
    a = [ss.periodic_orbit(jenkins_oscillator(0.8, r), method="radau5").amplitude[0] for r in (0.999, 0.9999)]
    out["jk.limit"] = (float(abs(a[0] / a[1] - 1.0)), "", "amplitude at 0.8 rad/s, z_ba_ratio 0.999 against 0.9999")
    from stickslip.harmonic import harmonic_balance
    for n_t in (256, 2048):
        hb, cpu = _cpu(lambda: [harmonic_balance(jenkins_oscillator(w, 0.9999), 1, n_samples=n_t) for w in (0.9, 1.2)])
        err = float(max(abs(h.amplitude[0] / caughey_amplitudes(w)[0] - 1.0) for h, w in zip(hb, (0.9, 1.2))))
        out[f"jk.hb{n_t}_err"] = (err, "", f"one harmonic, {n_t} instants: largest relative gap to Caughey's")
        out[f"jk.hb{n_t}_cpu"] = (cpu / 2, "s", "its CPU time per frequency")
    return out


def _locking_numbers() -> dict[str, tuple[float, str, str]]:
    """The folds of `locking_belt` continued down in F, against the first-order averaged
    equations' (`averaged_locking`) as eps halves, the first against scipy's at eps = 0.01, the
    free cycle's own frequency (second order in eps, what the lower fold's gap mostly is), and
    the averaged lower fold against Adler's edge 2 a0 |sigma| as sigma / eps shrinks; each
    (value, unit, what)."""
    import stickslip as ss
    out: dict[str, tuple[float, str, str]] = {}
    for k, eps in enumerate((0.04, 0.02, 0.01, 0.005)):
        a0, f_min, f_max = averaged_locking(eps, LK_KAPPA * eps)
        br, cpu = _cpu(lambda: ss.continuation(lambda f: locking_belt(f, eps), 2.5 * f_min, 0.5 * f_min,
                                               method="dopri5", step=0.05, max_step=0.1))
        folds = [b for b in br.bifurcations if b["kind"] == "fold"]
        out[f"lock.e{k}"] = (eps, "1/s", f"growth rate {k}")
        out[f"lock.a0_e{k}"] = (a0, "m", "the free cycle's first-order amplitude")
        out[f"lock.fmin_e{k}"] = (f_min, "N", "the averaged equations' lower fold (locking edge)")
        out[f"lock.f1_e{k}"] = (folds[0]["p"], "N", "the continuation's first fold")
        out[f"lock.gap1_e{k}"] = (folds[0]["p"] / f_min - 1, "", "its relative gap to the averaged one")
        out[f"lock.gap2_e{k}"] = (folds[1]["p"] / f_max - 1, "", "the second fold's to the averaged upper fold")
        out[f"lock.folds_e{k}"] = (len(folds), "", "folds found")
        x_e = -float(_mu_and_slope(-LK_VB, locking_c_v(eps))[0])
        free = ss.periodic_orbit(forced_belt(1.0, None, locking_c_v(eps), LK_VB), guess=[x_e + a0, 0.0, 2 * math.pi],
                                 method="dopri5")
        shift = 2 * math.pi / free.period - 1.0
        out[f"lock.omega_e{k}"] = (shift, "rad/s", "the free cycle's frequency minus 1 (periodic_orbit, unforced)")
        out[f"lock.detune_e{k}"] = (-shift / (LK_KAPPA * eps), "", "W - that frequency, over sigma, minus 1")
        if k:
            for j in (1, 2):
                out[f"lock.rate{j}_e{k}"] = (out[f"lock.gap{j}_e{k}"][0] / out[f"lock.gap{j}_e{k - 1}"][0], "",
                                             f"fold {j}: the gap over the last one's (first order: 1/2)")
        if eps == 0.01:
            out["lock.points"] = (len(br), "", "points of the branch at eps = 0.01")
            out["lock.cpu"] = (cpu, "s", "its CPU time, the two folds located included")
            i = folds[0]["index"]
            exact = scipy_fold(float(br.orbits[i - 1].x0[0]), float(br.orbits[i + 1].x0[0]),
                               float(br.orbits[i].v0[0]), float(br.p[i]), 1.0 + LK_KAPPA * eps, locking_c_v(eps),
                               LK_VB)
            out["lock.scipy_err"] = (abs(folds[0]["p"] / exact - 1), "", "first fold: relative distance to scipy's")
    for k, kappa in enumerate((0.2, 0.1, 0.05)):
        a0, f_min, _ = averaged_locking(0.01, kappa * 0.01)
        out[f"lock.adler_k{k}"] = (kappa, "", "sigma / eps")
        out[f"lock.adler_gap_k{k}"] = (f_min / (2 * a0 * kappa * 0.01) - 1, "",
                                       "averaged lower fold against Adler's 2 a0 sigma, eps = 0.01")
    return out


def main(argv: Sequence[str] | None = None) -> dict[str, tuple[float, str, str]]:
    p = argparse.ArgumentParser(prog="python -m benchmarks.steady_bifurcations", description=__doc__.split("\n\n")[0])
    p.add_argument("--outdir", help="write the numbers into OUTDIR/steady_bifurcations.json (with its provenance)")
    p.add_argument("--only", choices=("locking",), help="compute and print only this entry (no --outdir)")
    args = p.parse_args(argv)
    if args.only and args.outdir:
        p.error(f"--only {args.only}: prints only; the results file is written by the whole run")
    numbers = _locking_numbers() if args.only == "locking" else guide_numbers()
    if args.outdir:
        import sys
        from pathlib import Path
        root = Path(__file__).resolve().parent.parent
        if str(root) not in sys.path:
            sys.path.insert(0, str(root))
        from harness.files import write_text
        from harness.provenance import write_provenance
        from tools.docnumbers import numbers_json
        path = write_text(Path(args.outdir) / "steady_bifurcations.json", numbers_json(numbers))
        write_provenance(args.outdir, "benchmarks.steady_bifurcations", [path], argv)
        print(path)
    else:
        for key, (value, unit, what) in numbers.items():
            print(f"{key:20s} {value:.10g} {unit:6s} {what}")
    return numbers


if __name__ == "__main__":
    main()
