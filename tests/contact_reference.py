"""An independent event-driven reference for small linear systems with set-valued Coulomb
friction, written with numpy and scipy only (no stickslip code): M u' = -K q + H^T r,
w = H u + b, constant normal forces.

In a mode (each contact stuck, or slipping in a direction) the stuck contacts' forces keep
their relative accelerations at zero (least squares with the weights 1 / (mu_s N), which for
redundant contacts spreads the load in proportion to capacity); scipy's solve_ivp integrates
the mode (DOP853) with events for w_i = 0 (slipping) and |r_i| = mu_s N_i (stuck). At each
event the new mode is found by exhaustive search over every mode of the contacts at w = 0
(3^k of them), keeping a consistent one with the most stuck contacts.
"""
from __future__ import annotations

import itertools

import numpy as np
from scipy.integrate import solve_ivp


class Reference:
    def __init__(self, m, k, h, b, n, mu_s, mu_k):
        self.m = np.asarray(m, float)
        self.k = np.atleast_2d(np.asarray(k, float))
        self.h = np.atleast_2d(np.asarray(h, float))
        self.b = np.asarray(b, float)
        self.n = np.asarray(n, float)
        self.mu_s = np.asarray(mu_s, float)
        self.mu_k = np.asarray(mu_k, float)
        self.minv = np.diag(1.0 / self.m)
        self.a = self.h @ self.minv @ self.h.T          # Delassus matrix

    def forces(self, q, u, mode):
        """Contact forces of the mode (0 stuck, +-1 slip direction) at (q, u)."""
        r = np.where(mode != 0, -mode * self.mu_k * self.n, 0.0)
        stuck = np.flatnonzero(mode == 0)
        if stuck.size:
            af = self.h @ (self.minv @ (-self.k @ q + self.h.T @ r))
            wts = np.sqrt(self.mu_s[stuck] * self.n[stuck])
            a = self.a[np.ix_(stuck, stuck)] * np.outer(wts, wts)
            y = np.linalg.lstsq(a, -af[stuck] * wts, rcond=1e-12)[0]
            r[stuck] = wts * y
        return r

    def accel(self, q, u, mode):
        return self.minv @ (-self.k @ q + self.h.T @ self.forces(q, u, mode))

    def decide(self, q, u, cands, mode, at_limit=()):
        """The mode of the candidate contacts (at w = 0): a consistent one with the most stuck
        contacts; among those, every candidate held if that is consistent, else the candidates
        held beyond their limits slipping against their forces and the others held, else the
        one with the smallest sum of |relative accelerations| (the library's stated choice).
        Stuck contacts whose event located their limit (at_limit) count as beyond it."""
        held = mode.copy()
        held[cands] = 0
        r = self.forces(q, u, held)
        guess = held.copy()
        over = [i for i in cands if abs(r[i]) > self.mu_s[i] * self.n[i] * (1 + 1e-12) or i in at_limit]
        for i in over:
            guess[i] = -int(np.sign(r[i]))
        best, best_key = None, None
        for choice in itertools.product((0, 1, -1), repeat=len(cands)):
            trial = mode.copy()
            trial[cands] = choice
            r = self.forces(q, u, trial)
            acc = self.h @ self.accel(q, u, trial)
            ok = True
            for i, c in zip(cands, choice):
                if c == 0:
                    lim = self.mu_s[i] * self.n[i] * (1 - 1e-9 if i in at_limit else 1 + 1e-9)
                    ok &= abs(r[i]) <= lim and abs(acc[i]) < 1e-8
                else:
                    ok &= c * acc[i] > 0
            if not ok:
                continue
            key = (-choice.count(0), 0 if np.array_equal(trial, held) else 1 if np.array_equal(trial, guess) else 2,
                   sum(abs(acc[i]) for i, c in zip(cands, choice) if c != 0))
            if best_key is None or key < best_key:
                best, best_key = trial, key
        if best is None:
            raise RuntimeError("no consistent mode")
        return best

    def run(self, q0, u0, t_end, t_eval, rtol=1e-11, atol=1e-13):
        nd = self.m.size
        q, u, t = np.array(q0, float), np.array(u0, float), 0.0
        w = self.h @ u + self.b
        mode = np.sign(w).astype(int)
        at_zero = np.flatnonzero(w == 0)
        if at_zero.size:
            mode = self.decide(q, u, at_zero, mode)
        out = np.full((2 * nd, t_eval.size), np.nan)
        events = []
        while t < t_end:
            def rhs(_t, y, mode=mode):
                return np.concatenate([y[nd:], self.accel(y[:nd], y[nd:], mode)])

            funcs = []
            for i in range(self.n.size):
                if mode[i] == 0:
                    def f(_t, y, i=i, mode=mode):
                        return self.mu_s[i] * self.n[i] - abs(self.forces(y[:nd], y[nd:], mode)[i])
                    f.direction = -1
                else:
                    def f(_t, y, i=i):
                        return float(self.h[i] @ y[nd:] + self.b[i])
                    f.direction = -mode[i]       # towards w = 0 only (a release starts at 0)
                f.terminal = True
                funcs.append(f)
            sol = solve_ivp(rhs, (t, t_end), np.concatenate([q, u]), method="DOP853", rtol=rtol, atol=atol,
                            events=funcs, dense_output=True)
            t_stop = sol.t[-1]
            sel = (t_eval >= t) & (t_eval <= t_stop)
            if sel.any() and t_stop > t:
                out[:, sel] = sol.sol(t_eval[sel])
            y = sol.y[:, -1]
            q, u, t = y[:nd].copy(), y[nd:].copy(), t_stop
            if sol.status != 1:
                break
            hit = [i for i, te in enumerate(sol.t_events) if te.size]
            for i in hit:
                if mode[i] != 0 and np.count_nonzero(self.h[i]) == 1:      # exact stick
                    j = np.flatnonzero(self.h[i])[0]
                    u[j] = -self.b[i] / self.h[i, j]
            cands = sorted(set(hit) | set(np.flatnonzero(mode == 0)))
            new = self.decide(q, u, np.array(cands), mode, at_limit={i for i in hit if mode[i] == 0})
            for i in cands:
                if new[i] != mode[i]:
                    events.append((t, i, new[i]))
            mode = new
        return out, events
