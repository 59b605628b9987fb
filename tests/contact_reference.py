"""An independent event-driven reference for small linear systems with set-valued Coulomb
friction, written with numpy and scipy only (no stickslip code): M u' = -K q + H^T r,
w = H u + b, normal forces constant or given as tables (linear between their points, held
outside them, clipped at 0: a contact whose table is <= 0 is open and carries no force).

In a mode (each contact stuck, or slipping in a direction) the stuck contacts' forces keep
their relative accelerations at zero (least squares with the weights 1 / (mu_s N), which for
redundant contacts spreads the load in proportion to capacity); scipy's solve_ivp integrates
the mode (DOP853) with events for w_i = 0 (slipping, closed), |r_i| = mu_s N_i (stuck) and
N_i = 0 (a table crossing zero, either way), and stops at the tables' points. At each event
the new mode is found by exhaustive search over the modes of the contacts at w = 0, by
increasing number of slipping contacts (all 3^k of them where none holds), keeping a
consistent one with the most stuck contacts (contacts on the same row up to sign, which have
the same w, counted once); a contact that closes slips the way it moves (at w = 0 to rounding
it is decided with the others). A slipping contact's return to w = 0 inside one step, which
solve_ivp's events (at the steps' ends) miss, is found on the dense output. Where several modes with that many stuck contacts are consistent (a tie), the
time is kept in `ties`: another rule may pick another of them.
"""
from __future__ import annotations

import itertools

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq


#: A slip acceleration this small against its direction [m/s^2] is zero to rounding: such a mode
#: is not chosen, but where it holds at least as many stuck contacts as the chosen one the
#: instant is a tie (which is right depends on the derivatives, which neither side looks at).
ROUNDING_ACC = 1e-12


class Reference:
    def __init__(self, m, k, h, b, n, mu_s, mu_k, normal_tables=None):
        self.m = np.asarray(m, float)
        self.k = np.atleast_2d(np.asarray(k, float))
        self.h = np.atleast_2d(np.asarray(h, float))
        self.b = np.asarray(b, float)
        self.n = np.asarray(n, float)
        self.mu_s = np.asarray(mu_s, float)
        self.mu_k = np.asarray(mu_k, float)
        self.minv = np.diag(1.0 / self.m)
        self.a = self.h @ self.minv @ self.h.T          # Delassus matrix
        tables = normal_tables if normal_tables is not None else [None] * self.n.size
        self.tables = [None if tb is None else (np.asarray(tb[0], float), np.asarray(tb[1], float))
                       for tb in tables]
        self.ties: list[float] = []

    def normal_raw(self, t):
        """The normal forces before clipping at 0 [N] at time t."""
        out = self.n.copy()
        for i, tb in enumerate(self.tables):
            if tb is not None:
                out[i] = np.interp(t, tb[0], tb[1])
        return out

    def normal(self, t):
        return np.maximum(self.normal_raw(t), 0.0)

    def corners(self):
        """Every table point [s], sorted."""
        pts = set()
        for tb in self.tables:
            if tb is not None:
                pts.update(float(x) for x in tb[0])
        return sorted(pts)

    def forces(self, q, u, mode, t=0.0):
        """Contact forces of the mode (0 stuck, +-1 slip direction) at (t, q, u)."""
        nn = self.normal(t)
        r = np.where(mode != 0, -mode * self.mu_k * nn, 0.0)
        stuck = np.flatnonzero(mode == 0)
        if stuck.size:
            af = self.h @ (self.minv @ (-self.k @ q + self.h.T @ r))
            wts = np.sqrt(np.maximum(self.mu_s[stuck] * nn[stuck], 1e-300))
            a = self.a[np.ix_(stuck, stuck)] * np.outer(wts, wts)
            y = np.linalg.lstsq(a, -af[stuck] * wts, rcond=1e-12)[0]
            r[stuck] = wts * y
        return r

    def accel(self, q, u, mode, t=0.0):
        return self.minv @ (-self.k @ q + self.h.T @ self.forces(q, u, mode, t))

    def decide(self, q, u, cands, mode, at_limit=(), t=0.0):
        """The mode of the candidate contacts (at w = 0): a consistent one with the most stuck
        contacts; among those, every candidate held if that is consistent, else the candidates
        held beyond their limits slipping against their forces and the others held, else the
        one with the smallest sum of |relative accelerations| (the library's stated choice).
        Stuck contacts whose event located their limit (at_limit) count as beyond it. A tie
        (several consistent modes with the most stuck contacts) is recorded in `ties`."""
        nn = self.normal(t)
        held = mode.copy()
        held[cands] = 0
        r = self.forces(q, u, held, t)
        guess = held.copy()
        over = [i for i in cands if abs(r[i]) > self.mu_s[i] * nn[i] * (1 + 1e-12) or i in at_limit]
        for i in over:
            guess[i] = -int(np.sign(r[i]))
        cands = list(cands)
        for slack in (0.0, 1e-9):      # slipping away from w = 0 (then to rounding: at mu_s = mu_k)
            best, n_best = self._search(q, u, cands, mode, at_limit, t, nn, held, guess, slack)
            if best is not None:
                break
        if best is None:
            raise RuntimeError("no consistent mode")
        if n_best > 1 and any(self.mu_s[i] > self.mu_k[i] for i in cands):
            self.ties.append(t)
        return best

    def _row_key(self, i):
        """Contact i's row (H_i, b_i) up to sign: contacts with the same key have the same w."""
        row = np.append(self.h[i], self.b[i])
        lead = row[np.flatnonzero(row)[0]]
        return tuple(row * np.sign(lead))

    def _search(self, q, u, cands, mode, at_limit, t, nn, held, guess, slack):
        """The best consistent mode of the candidates (see `decide`), searched by increasing
        number of slipping ones, and how many consistent modes hold that many stuck contacts
        (None, 0: none). Contacts on the same row up to sign (the same w: a contact split in
        halves) count as one stuck contact, as issue 41 states the rule: the search goes on
        while a count of fewer slipping contacts could still hold as many distinct rows."""
        best, best_key, counts, round_max = None, None, {}, -1
        cap_max = float(np.max(self.mu_s * nn, initial=0.0))
        keys = [self._row_key(i) for i in cands]
        for n_slip in range(len(cands) + 1):
            if best is not None and len(cands) - n_slip < -best_key[0]:
                break
            for slipping in itertools.combinations(range(len(cands)), n_slip):
                for signs in itertools.product((1, -1), repeat=n_slip):
                    choice = [0] * len(cands)
                    for j, sg in zip(slipping, signs):
                        choice[j] = sg
                    trial = mode.copy()
                    trial[cands] = choice
                    r = self.forces(q, u, trial, t)
                    acc = self.h @ self.accel(q, u, trial, t)
                    ok, rounding = True, False
                    for i, c in zip(cands, choice):
                        if c == 0:
                            lim = self.mu_s[i] * nn[i] * (1 - 1e-9 if i in at_limit else 1 + 1e-9)
                            lim += 1e-12 * cap_max      # a contact closing (N = 0) on a held row
                            ok &= abs(r[i]) <= lim and abs(acc[i]) < 1e-8
                        elif c * acc[i] <= -slack:
                            ok &= c * acc[i] > -ROUNDING_ACC      # slips away only to rounding
                            rounding = True
                    if not ok:
                        continue
                    n_stuck = len({k for k, c in zip(keys, choice) if c == 0})
                    if rounding:        # consistent to rounding only: not chosen, but another solution
                        round_max = max(round_max, n_stuck)
                        continue
                    counts[n_stuck] = counts.get(n_stuck, 0) + 1
                    key = (-n_stuck, 0 if np.array_equal(trial, held) else 1 if np.array_equal(trial, guess) else 2,
                           sum(abs(acc[i]) for i, c in zip(cands, choice) if c != 0))
                    if best_key is None or key < best_key:
                        best, best_key = trial, key
        if best is None:
            return None, 0
        return best, counts[-best_key[0]] + (1 if round_max >= -best_key[0] else 0)

    def _closed(self, t):
        """Which contacts carry a normal force just after t (a table at 0 there: by its slope)."""
        return self.normal_raw(t + 1e-9) > 0.0

    def _missed_return(self, sol, mode, closed, per_step=64):
        """The earliest return of a slipping contact's s w (s its direction) to 0 that
        solve_ivp's events miss: they look at the steps' ends only, so an excursion that
        starts at w = 0 to rounding with the wrong sign (after a reversal) and comes back
        within one step goes unseen. Found on the dense output, `per_step` points a step,
        as a fall of s w from above 0 to <= 0; (time, contact) or None."""
        nd = self.m.size
        slipping = [i for i in range(self.n.size) if mode[i] != 0 and closed[i]]
        if not slipping or sol.t.size < 2:
            return None
        tt = np.concatenate([np.linspace(a, b, per_step, endpoint=False) for a, b in zip(sol.t[:-1], sol.t[1:])]
                            + [sol.t[-1:]])
        sw = (mode[slipping, None] * (self.h[slipping] @ sol.sol(tt)[nd:]
                                      + self.b[slipping, None]))
        best = None
        for row, i in enumerate(slipping):
            s = sw[row]
            above = np.maximum.accumulate(s > 0.0)
            falls = np.flatnonzero((s[1:] <= 0.0) & above[:-1])
            if not falls.size:
                continue
            k = falls[0]
            g = lambda x, i=i: float(mode[i] * (self.h[i] @ sol.sol(x)[nd:] + self.b[i]))
            tc = brentq(g, tt[k], tt[k + 1], xtol=1e-15, rtol=8.9e-16) if g(tt[k + 1]) < 0.0 else tt[k + 1]
            if best is None or tc < best[0]:
                best = (tc, i)
        return best

    def run(self, q0, u0, t_end, t_eval, rtol=1e-11, atol=1e-13, max_segments=100000):
        nd = self.m.size
        nc = self.n.size
        q, u, t = np.array(q0, float), np.array(u0, float), 0.0
        w = self.h @ u + self.b
        mode = np.sign(w).astype(int)
        at_zero = np.flatnonzero(w == 0)
        if at_zero.size:
            mode = self.decide(q, u, at_zero, mode, t=t)
        out = np.full((2 * nd, t_eval.size), np.nan)
        events = []
        corners = [c for c in self.corners() if c > 0.0]
        stalled = 0
        for _ in range(max_segments):
            if t >= t_end:
                break
            if stalled > 50:
                raise RuntimeError(f"reference: no progress at t = {t}")
            t_stop_at = min([c for c in corners if c > t] + [t_end])
            closed = self._closed(t)

            def rhs(_t, y, mode=mode):
                return np.concatenate([y[nd:], self.accel(y[:nd], y[nd:], mode, _t)])

            funcs, kinds = [], []
            for i in range(nc):
                if mode[i] == 0:
                    slack = 0.0 if closed[i] else 1e-9     # held while open: only a force that appears
                    def f(_t, y, i=i, mode=mode, slack=slack):
                        return self.mu_s[i] * self.normal(_t)[i] + slack - abs(self.forces(y[:nd], y[nd:], mode, _t)[i])
                    f.direction = -1
                    f.terminal = True
                    funcs.append(f)
                    kinds.append(("limit", i))
                elif closed[i]:
                    def f(_t, y, i=i):
                        return float(self.h[i] @ y[nd:] + self.b[i])
                    f.direction = -mode[i]       # towards w = 0 only (a release starts at 0)
                    f.terminal = True
                    funcs.append(f)
                    kinds.append(("w", i))
                if self.tables[i] is not None:
                    def f(_t, y, i=i):
                        return float(self.normal_raw(_t)[i])
                    f.direction = -1 if closed[i] else 1
                    f.terminal = True
                    funcs.append(f)
                    kinds.append(("normal", i))
            sol = solve_ivp(rhs, (t, t_stop_at), np.concatenate([q, u]), method="DOP853", rtol=rtol, atol=atol,
                            events=funcs, dense_output=True)
            t_stop = sol.t[-1]
            y = sol.y[:, -1]
            missed = self._missed_return(sol, mode, closed)
            if missed is not None and missed[0] < t_stop:
                t_stop, y = missed[0], sol.sol(missed[0])
                sol.status, sol.t_events = 1, [np.array([]) for _ in funcs]
                sol.t_events[kinds.index(("w", missed[1]))] = np.array([t_stop])
            sel = (t_eval >= t) & (t_eval <= t_stop)
            if sel.any() and t_stop > t:
                out[:, sel] = sol.sol(t_eval[sel])
            stalled = stalled + 1 if t_stop == t else 0
            q, u, t = y[:nd].copy(), y[nd:].copy(), t_stop
            if sol.status == -1 or (sol.status == 0 and t >= t_end):
                break
            hit = [kinds[j] for j, te in enumerate(sol.t_events) if te.size] if sol.status == 1 else []
            w_hit = [i for kind, i in hit if kind == "w"]
            if w_hit:      # every closed slipping contact at w = 0 with them (the same row: redundant)
                w = self.h @ u + self.b
                w_hit = sorted(set(w_hit) | {i for i in range(nc) if mode[i] != 0 and closed[i]
                                             and abs(w[i]) <= 1e-10 * (1.0 + np.abs(u).max())})
            for i in w_hit:
                if np.count_nonzero(self.h[i]) == 1:      # exact stick
                    j = np.flatnonzero(self.h[i])[0]
                    u[j] = -self.b[i] / self.h[i, j]
            now_closed = self._closed(t)     # every table that crossed with them (the same table: halves)
            closing = [i for i in range(nc) if now_closed[i] and not closed[i]] if hit else []
            w = self.h @ u + self.b
            # a closing contact slips the way it moves; at w = 0 to rounding (a body held by
            # other contacts) it is decided with the others, not slipped on the sign of noise
            w_zero = 1e-10 * (1.0 + np.abs(u).max())
            at_w0 = [i for i in closing if abs(w[i]) <= w_zero]
            new_mode = mode.copy()
            for i in closing:
                if mode[i] != 0 and i not in at_w0:
                    new_mode[i] = int(np.sign(w[i]))
            cands = sorted(set(w_hit) | set(at_w0) | set(np.flatnonzero(mode == 0)))
            limit = {i for kind, i in hit if kind == "limit"}
            if limit:      # every stuck contact at its limit with them (the same row: redundant)
                r = self.forces(q, u, mode, t)
                lim = self.mu_s * self.normal(t)
                limit |= {i for i in range(nc) if mode[i] == 0 and lim[i] > 0 and abs(r[i]) >= lim[i] * (1 - 1e-7)}
            cands = sorted(set(cands) | limit)
            new = self.decide(q, u, np.array(cands, int), new_mode, at_limit=limit, t=t) if cands else new_mode
            for i in range(nc):
                if new[i] != mode[i]:
                    events.append((t, i, new[i]))
            mode = new
        return out, events
