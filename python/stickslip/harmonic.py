"""Harmonic balance with alternating frequency-time (AFT), as NLvib does, beside shooting.

The forced periodic motion of a `Model` with regularised friction laws is written as a truncated Fourier series, x_i(t) = a_i0 + sum_k (a_ik cos(k w t) + b_ik
sin(k w t)), k = 1 .. n_harmonics. The equations of motion, M x'' = F(x, x', t), are sampled
at `n_samples` instants of the period (the forces and the friction law evaluated in time),
and their residual is projected back on the same harmonics; Newton's method
(stickslip.steady's, forward-difference Jacobian) zeroes the projected residual. A law with
internal states (a bristle, a Jenkins element's presliding) is evaluated along the series'
motion by `prescribed_motion` over three periods from zero states, the last one used (the
hysteresis loop settled; a contact whose states still move from the second period to the
third, by more than 1e-9 of the friction coefficient, is a named failure). Laws that
jump at zero slip (coulomb, karnopp) are refused: the friction force is evaluated as the law's
curve mu(s) N, which jumps there; use `periodic_orbit` for exact stick.

Examples
--------
>>> import stickslip as ss
>>> from stickslip.harmonic import harmonic_balance
>>> m = ss.Model()
>>> b = m.add_body(1.0)
>>> m.add_spring(b, None, k=4.0)
>>> m.add_damper(b, None, c=0.2)
>>> m.add_force(b, ss.signal.sine(1.0, 0.3))
>>> hb = harmonic_balance(m, n_harmonics=1)
>>> round(float(hb.amplitude[0]), 6)
1.710264
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .model import _JUMP_LAWS, Model
from .prescribed import prescribed_motion
from .steady import GuessShapeError, LawStatesUnsupported, NoConvergence, Orbit, _check_model, _newton, _signal, \
    _System, forcing_period

__all__ = ["HarmonicSolution", "harmonic_balance"]


@dataclass
class HarmonicSolution:
    """A periodic motion by harmonic balance (returned by `harmonic_balance`).

    Attributes
    ----------
    period : float
        The forcing period [s].
    n_harmonics : int
    coefficients : numpy.ndarray, shape (n_bodies, 2 n_harmonics + 1)
        Per body: a_0, then a_k (cos) and b_k (sin) for k = 1 .. n_harmonics [m].
    x0, v0 : numpy.ndarray, shape (n_bodies,)
        The state at t = 0 [m], [m/s] (to compare with `Orbit.x0`, `Orbit.v0`).
    amplitude : numpy.ndarray, shape (n_bodies,)
        Half the peak-to-peak displacement, from the series on 4096 instants [m].
    residual : float
        Infinity norm of the projected residual [N].
    iterations : int
    """

    period: float
    n_harmonics: int
    coefficients: np.ndarray
    x0: np.ndarray
    v0: np.ndarray
    amplitude: np.ndarray
    residual: float
    iterations: int

    def motion(self, t: Any) -> tuple[np.ndarray, np.ndarray]:
        """x and v of every body at times t [s] (shape (n_bodies, n_t))."""
        basis, dbasis, _ = _basis(self.n_harmonics, 2 * math.pi / self.period, np.atleast_1d(np.asarray(t, float)))
        return self.coefficients @ basis, self.coefficients @ dbasis


def _basis(h: int, w: float, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The series' basis (1, cos k w t, sin k w t) at t and its first two time derivatives,
    shape (2 h + 1, n_t)."""
    k = np.arange(1, h + 1)[:, None]
    c, s = np.cos(k * w * t), np.sin(k * w * t)
    one = np.ones((1, t.size))
    zero = np.zeros((1, t.size))
    basis = np.vstack([one, np.stack([c, s], 1).reshape(2 * h, -1)])
    d1 = np.vstack([zero, np.stack([-k * w * s, k * w * c], 1).reshape(2 * h, -1)])
    d2 = np.vstack([zero, np.stack([-(k * w) ** 2 * c, -(k * w) ** 2 * s], 1).reshape(2 * h, -1)])
    return basis, d1, d2


def harmonic_balance(model: Model, n_harmonics: int = 5, period: float | None = None, guess: Any = None, *,
                     n_samples: int | None = None, tol: float = 1e-10, max_iter: int = 40) -> HarmonicSolution:
    """The forced periodic motion of `model` by harmonic balance (AFT).

    Parameters
    ----------
    model : Model
        A forced model whose contacts all have laws whose curve is continuous at zero slip
        (not coulomb or karnopp); a law with internal states needs a contact without surface
        velocity.
    n_harmonics : int, optional
        Harmonics of the series (default 5), >= 1.
    period : float, optional
        The forcing period [s] (default: that of the model's sines).
    guess : HarmonicSolution or Orbit, optional
        A start: a solution with any number of harmonics, or a shooting Orbit (projected on
        the harmonics). Default: the linear response without friction (zero when that is
        singular).
    n_samples : int, optional
        Instants per period of the time-domain evaluation (default 4 (n_harmonics + 1) + 1, at
        least 64): aliasing of the friction force's higher harmonics is below the truncation
        error when it is large enough.
    tol : float, optional
        Tolerance on the projected residual [N] (default 1e-10).
    max_iter : int, optional
        Newton iterations at most.

    Returns
    -------
    HarmonicSolution

    Raises
    ------
    ValueError
        A law that jumps at zero slip, a law with states on a moving surface, an autonomous
        model, or bad arguments.
    stickslip.NoConvergence
        Newton's method did not converge, or a law's states are not periodic after three
        periods of the solution.
    """
    model = _check_model(model, allow_states=True)
    stated = [i for i in range(len(model.contacts)) if model._law_states(i)[0]]
    for i in stated:
        if model.contacts[i].surface_velocity is not None:
            raise LawStatesUnsupported(f"{model.contact_label(i)}: law {model.contacts[i].law!r} has internal states; "
                                       "harmonic balance evaluates them along the motion of a contact without "
                                       "surface velocity only (periodic_orbit for a moving surface)")
    for i, c in enumerate(model.contacts):
        if c.law in _JUMP_LAWS:
            raise ValueError(f"{model.contact_label(i)}: law {c.law!r} jumps at zero slip; harmonic balance needs "
                             "a continuous friction curve (a regularised law; periodic_orbit for exact stick)")
    if isinstance(n_harmonics, bool) or not isinstance(n_harmonics, (int, np.integer)) or n_harmonics < 1:
        raise ValueError(f"n_harmonics: must be an integer >= 1, got {n_harmonics!r}")
    period = forcing_period(model, period)
    if period is None:
        raise ValueError("model: nothing is forced (every signal is constant); harmonic_balance solves forced "
                         "motion only (autonomous cycles: periodic_orbit)")
    h = int(n_harmonics)
    n_t = max(64, 4 * (h + 1) + 1) if n_samples is None else int(n_samples)
    if n_t < 2 * h + 1:
        raise ValueError(f"n_samples: must be >= 2 n_harmonics + 1 = {2 * h + 1}, got {n_samples!r}")
    w = 2 * math.pi / period
    t = np.arange(n_t) * (period / n_t)
    basis, d1, d2 = _basis(h, w, t)
    project = np.linalg.pinv(basis)                     # samples -> coefficients (least squares)
    sys_ = _System(model)
    n = sys_.n
    coef0 = _start(guess, sys_, h, w, period)

    run = np.arange(3 * n_t) * (period / n_t)          # three periods for the laws' states
    b3, db3, _ = _basis(h, w, run)

    def states_mu(c: np.ndarray) -> tuple[dict[int, np.ndarray], float]:
        """The stated contacts' mu over the last period, and their largest change from the
        second period to the third."""
        mus, drift = {}, 0.0
        for i in stated:
            con = model.contacts[i]
            pr = prescribed_motion(con.law, run, sys_.G[i] @ (c @ b3), sys_.G[i] @ (c @ db3), rtol=1e-12,
                                   normal_force=np.maximum(_signal(con.normal_force, run)[0], 0.0) + 0.0 * run,
                                   **con.params)
            mus[i] = pr.mu[2 * n_t:]
            drift = max(drift, float(np.max(np.abs(pr.mu[2 * n_t:] - pr.mu[n_t:2 * n_t]))))
        return mus, drift

    def residual(u: np.ndarray) -> np.ndarray:
        c = u.reshape(n, 2 * h + 1)
        y = np.vstack([c @ basis, c @ d1])
        r = sys_.mass[:, None] * (c @ d2) - sys_._free(y, t, None, states_mu(c)[0] if stated else None)
        return (r @ project).ravel()

    scale = np.full(coef0.size, max(float(np.max(np.abs(coef0))), 1e-3))
    u, norm, it, _ = _newton(residual, coef0.ravel(), scale, tol, max_iter, "harmonic_balance")
    coef = u.reshape(n, 2 * h + 1)
    if stated:
        drift = states_mu(coef)[1]
        if drift > 1e-9:
            raise NoConvergence(f"harmonic_balance: the laws' states are not periodic: their friction coefficient "
                                f"changes by {drift:.3g} from the second period to the third (a contact that never "
                                "slips keeps its initial states; periodic_orbit solves for them)", norm, it)
    b0, db0, _ = _basis(h, w, np.zeros(1))
    return HarmonicSolution(period=period, n_harmonics=h, coefficients=coef, x0=(coef @ b0)[:, 0],
                            v0=(coef @ db0)[:, 0], amplitude=_amplitude(coef, h, w, period), residual=norm,
                            iterations=it)


def _amplitude(coef: np.ndarray, h: int, w: float, period: float) -> np.ndarray:
    """Half the peak-to-peak of each body's series: its extremes on 4096 instants, each
    refined by Newton steps on x'(t) = 0."""
    fine = np.linspace(0.0, period, 4096, endpoint=False)
    xs = coef @ _basis(h, w, fine)[0]
    out = np.empty(coef.shape[0])
    for b in range(coef.shape[0]):
        ext = []
        for i in (int(np.argmax(xs[b])), int(np.argmin(xs[b]))):
            t = np.array([fine[i]])
            for _ in range(4):
                _, d1, d2 = _basis(h, w, t)
                a = float(coef[b] @ d2[:, 0])
                if a == 0.0:
                    break
                t = t - float(coef[b] @ d1[:, 0]) / a
            ext.append(float(coef[b] @ _basis(h, w, t)[0][:, 0]))
        out[b] = 0.5 * (max(ext[0], float(xs[b].max())) - min(ext[1], float(xs[b].min())))
    return out


def _start(guess: Any, sys_: _System, h: int, w: float, period: float) -> np.ndarray:
    """Start coefficients (n_bodies, 2 h + 1) from a guess, or the frictionless linear response."""
    n = sys_.n
    if isinstance(guess, HarmonicSolution):
        out = np.zeros((n, 2 * h + 1))
        m = min(h, guess.n_harmonics)
        out[:, :2 * m + 1] = guess.coefficients[:, :2 * m + 1]
        return out
    if isinstance(guess, Orbit):
        t = guess.result.t[:-1]
        b = _basis(h, w, t)[0]
        return guess.result.x[:, :-1] @ np.linalg.pinv(b)
    if guess is not None:
        raise GuessShapeError(f"guess: must be a HarmonicSolution or an Orbit, got {type(guess).__name__}")
    # the frictionless linear response to the forces' harmonics, harmonic by harmonic
    t = np.arange(4 * h + 4) * (period / (4 * h + 4))
    basis = _basis(h, w, t)[0]
    f = np.zeros((n, t.size))
    for body, s in sys_.forces:
        f[body] += _signal(s, t)[0]
    fc = f @ np.linalg.pinv(basis)
    out = np.zeros((n, 2 * h + 1))
    try:
        out[:, 0] = np.linalg.solve(sys_.K, fc[:, 0] + sys_.f0) if np.linalg.matrix_rank(sys_.K) == n else 0.0
        for k in range(1, h + 1):
            kw = k * w
            dyn = np.block([[sys_.K - kw**2 * np.diag(sys_.mass), kw * sys_.C],
                            [-kw * sys_.C, sys_.K - kw**2 * np.diag(sys_.mass)]])
            ab = np.linalg.solve(dyn, np.concatenate([fc[:, 2 * k - 1], fc[:, 2 * k]]))
            out[:, 2 * k - 1], out[:, 2 * k] = ab[:n], ab[n:]
    except np.linalg.LinAlgError:
        out[:] = 0.0
    return out
