"""An event-driven solver for bodies on one axis coupled by set-valued Coulomb contacts with time-
varying normal forces, written with numpy and scipy only (no stickslip code): the independent
reference and the competitor of `python -m cases.gallery_clutches` (Modelica's CoupledClutches)
and of the gallery's tests (tests/cases/test_gallery_*.py).

The bodies have masses (inertias) m and forces f(t, x) (external ones and springs); contact i
acts between bodies a_i and b_i (b_i = None: the ground) with the slip w_i = v_a - v_b - s_i
(s_i: the constant speed of a surface under a, a belt; 0 by default) and the normal force N_i(t)
(open where N_i <= 0). In a mode (each contact open, stuck, or slipping forwards or backwards) a
slipping contact pushes -mode mu N on a and the opposite on b (mu = mu_k, or a given function of
the slip's size, a Stribeck curve); the stuck contacts' forces keep their slips' accelerations
at zero (a linear solve with the Delassus matrix H M^-1 H^T, least squares where contacts are
redundant). scipy's solve_ivp integrates the mode (DOP853 by default) with events for w_i = 0
(slipping) and |r_i| = mu_s N_i (stuck), up to the next breakpoint of the signals (a step's
time, where a normal force crosses zero). At each event or breakpoint the new mode is found by
exhaustive search over the 3^k modes of the closed contacts at w = 0, keeping a consistent one
with the most stuck contacts; among those, the one where only the contacts that reached their
limits slip (a stuck contact below its limit stays stuck). A contact that an event brings to w =
0 has its bodies' velocities projected onto w = 0, conserving momentum.
"""
from __future__ import annotations

import itertools
from dataclasses import dataclass, field
from typing import Any, Callable, Sequence

import numpy as np
from scipy.integrate import solve_ivp


#: A normal force at or below this is open [N] (a cosine's zero is 1e-15 N off in floating point).
OPEN_BELOW: float = 1e-9


@dataclass
class ScipyContacts:
    """The system: masses, forces f(t, x) -> array of the bodies' forces but friction, contacts
    (a, b, N(t)) or (a, b, N(t), surface speed), mu_s, mu_k (one each per contact or shared)
    and the breakpoints of the signals [s]."""

    m: Sequence[float]
    force: Callable[[float, np.ndarray], np.ndarray]
    contacts: Sequence[tuple[Any, ...]]
    mu_s: float | Sequence[float]
    mu_k: float | Sequence[float]
    breakpoints: Sequence[float] = ()
    #: The kinetic coefficient as a function of abs(slip) (a Stribeck curve); mu_k when None.
    mu_slip: Callable[[float], float] | None = None
    h: np.ndarray = field(init=False)

    def __post_init__(self) -> None:
        self.m = np.asarray(self.m, float)
        nc = len(self.contacts)
        self.h = np.zeros((nc, self.m.size))
        self.s = np.zeros(nc)
        for i, (a, b, *rest) in enumerate(self.contacts):
            self.h[i, a] = 1.0
            if b is not None:
                self.h[i, b] = -1.0
            if len(rest) > 1:
                self.s[i] = float(rest[1])
        self.mu_s = np.broadcast_to(np.asarray(self.mu_s, float), (nc,)).copy()
        self.mu_k = np.broadcast_to(np.asarray(self.mu_k, float), (nc,)).copy()
        self.minv_ht = self.h.T / self.m[:, None]
        self.delassus = self.h @ self.minv_ht
        self.nfev = 0

    def normal(self, t: float) -> np.ndarray:
        """The normal forces at t [N] (0 where open)."""
        return np.array([max(0.0, float(cn[2](t))) for cn in self.contacts])

    def forces(self, t: float, x: np.ndarray, u: np.ndarray, mode: np.ndarray) -> np.ndarray:
        """Contact forces of the mode (2 open, 0 stuck, +-1 slipping) at t, x, u."""
        n = self.normal(t)
        mu = self.mu_k
        if self.mu_slip is not None:
            w = np.abs(self.h @ u - self.s)
            mu = np.array([self.mu_slip(float(wi)) for wi in w])
        r = np.where((mode == 1) | (mode == -1), -mode * mu * n, 0.0)
        stuck = np.flatnonzero(mode == 0)
        if stuck.size:
            free_acc = self.h @ ((self.force(t, x) + self.h.T @ r) / self.m)
            # least squares: for redundant contacts (a body on two feet) the smallest forces,
            # which share the load equally between equal contacts
            r[stuck] = np.linalg.lstsq(self.delassus[np.ix_(stuck, stuck)], -free_acc[stuck], rcond=1e-12)[0]
        return r

    def accel(self, t: float, x: np.ndarray, u: np.ndarray, mode: np.ndarray) -> np.ndarray:
        """The bodies' accelerations in the mode at t, x, u."""
        self.nfev += 1
        return (self.force(t, x) + self.h.T @ self.forces(t, x, u, mode)) / self.m

    def decide(self, t: float, x: np.ndarray, u: np.ndarray, mode: np.ndarray, at_limit: set[int]) -> np.ndarray:
        """The mode after an event or breakpoint at t: open where N <= 0; slipping with sign(w)
        where |w| is not zero; for the closed contacts at w = 0, a consistent mode with the
        most stuck contacts (stuck: |r| <= mu_s N, below it for those whose limit was just
        reached; slipping: the slip accelerates the way it points)."""
        n = self.normal(t)
        w = self.h @ u - self.s
        new = mode.copy()
        cands = []
        for i in range(n.size):
            if n[i] <= OPEN_BELOW:
                new[i] = 2
            elif mode[i] == 0 or abs(w[i]) <= 1e-9 * (1.0 + np.abs(u).max()):
                cands.append(i)
            else:
                new[i] = int(np.sign(w[i]))
        # the mode where only the contacts at their limits change: they slip against their
        # forces, every other candidate holds (preferred among equally stuck modes: a stuck
        # contact below its limit stays stuck; with mu_s > mu_k another contact's slip can be
        # consistent too)
        guess = new.copy()
        guess[cands] = 0
        held = self.forces(t, x, u, guess)
        for i in at_limit:
            guess[i] = -int(np.sign(held[i]))
        best, best_key = None, None
        for choice in itertools.product((0, 1, -1), repeat=len(cands)):
            trial = new.copy()
            trial[cands] = choice
            r = self.forces(t, x, u, trial)
            acc = self.h @ ((self.force(t, x) + self.h.T @ r) / self.m)
            ok = True
            for i, ci in zip(cands, choice):
                if ci == 0:
                    lim = self.mu_s[i] * n[i] * (1 - 1e-9 if i in at_limit else 1 + 1e-9)
                    ok &= abs(r[i]) <= lim
                elif i in at_limit and ci == guess[i]:
                    # a break-away against the force: with a Stribeck curve (mu(0) = mu_s) the
                    # slip starts with zero acceleration, so rounding may give either sign
                    ok &= ci * acc[i] > -1e-9 * (1.0 + np.abs(self.force(t, x) / self.m).max())
                else:
                    ok &= ci * acc[i] > 0
            if ok:
                key = (-list(choice).count(0), 0 if np.array_equal(trial, guess) else 1,
                       sum(abs(acc[i]) for i, ci in zip(cands, choice) if ci))
                if best_key is None or key < best_key:
                    best, best_key = trial, key
        if best is None:
            raise RuntimeError(f"no consistent mode at t = {t}")
        return best

    def run(self, v0: Sequence[float], t_end: float, t_eval: np.ndarray, *, x0: Sequence[float] | None = None,
            rtol: float = 1e-10, atol: float = 1e-12, method: str = "DOP853"
            ) -> tuple[np.ndarray, np.ndarray, list[tuple[float, int, int]]]:
        """Integrate from t = 0 to t_end; (x, v) at t_eval (shape (n_bodies, n_t)) and the
        transitions (t, contact, new mode)."""
        nb = self.m.size
        x = np.zeros(nb) if x0 is None else np.asarray(x0, float).copy()
        u = np.asarray(v0, float).copy()
        t = 0.0
        mode = np.zeros(len(self.contacts), int)
        mode = self.decide(t, x, u, np.full_like(mode, 2), set())
        out = np.full((2 * nb, t_eval.size), np.nan)
        events: list[tuple[float, int, int]] = []
        stops = sorted(b for b in self.breakpoints if 0.0 < b < t_end) + [t_end]
        while t < t_end:
            t_stop = next(b for b in stops if b > t)

            def rhs(tt: float, y: np.ndarray, mode: np.ndarray = mode) -> np.ndarray:
                return np.concatenate([y[nb:], self.accel(tt, y[:nb], y[nb:], mode)])

            funcs = []
            for i in range(mode.size):
                if mode[i] == 0:
                    def f(tt: float, y: np.ndarray, i: int = i, mode: np.ndarray = mode) -> float:
                        return self.mu_s[i] * self.normal(tt)[i] - abs(self.forces(tt, y[:nb], y[nb:], mode)[i])
                    f.direction = -1
                elif mode[i] in (1, -1):
                    def f(tt: float, y: np.ndarray, i: int = i) -> float:
                        return float(self.h[i] @ y[nb:] - self.s[i])
                    f.direction = -mode[i]
                else:
                    continue
                f.terminal = True
                f.contact = i
                funcs.append(f)
            sol = solve_ivp(rhs, (t, t_stop), np.concatenate([x, u]), method=method, rtol=rtol, atol=atol,
                            events=funcs or None, dense_output=True)
            if sol.status == -1:
                raise RuntimeError(f"solve_ivp failed at t = {sol.t[-1]}: {sol.message}")
            t_new = float(sol.t[-1])
            sel = (t_eval >= t) & (t_eval <= t_new)
            if sel.any() and t_new > t:
                out[:, sel] = sol.sol(t_eval[sel])
            y = sol.y[:, -1]
            x, u, t = y[:nb].copy(), y[nb:].copy(), t_new
            hit = [funcs[j].contact for j, te in enumerate(sol.t_events or []) if te.size] if sol.status == 1 else []
            for i in hit:
                if mode[i] in (1, -1):         # exact stick: project onto w_i = 0
                    u -= self.minv_ht[:, i] * (self.h[i] @ u - self.s[i]) / self.delassus[i, i]
            new = self.decide(t, x, u, mode, {i for i in hit if mode[i] == 0})
            for i in range(mode.size):
                if new[i] != mode[i]:
                    events.append((t, i, int(new[i])))
            mode = new
        return out[:nb], out[nb:], events
