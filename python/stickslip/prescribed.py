"""Prescribed motion: the friction force of a law along a given displacement record, its
internal states integrated by the Fortran core in one call per record
(stickslip_prescribed.f90; docs/guide/prescribed-motion.md).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from . import _stickslip as _ext
from .core import LAWS, REGISTRY, _check_code, _choice, _finite, _keys, _physical, _states

__all__ = ["PrescribedResult", "prescribed_motion", "law_n_states", "law_state_labels"]


@dataclass
class PrescribedResult:
    """The friction along a prescribed motion, at the sample times.

    Attributes
    ----------
    law : str
        The friction law.
    params : dict
        The law's parameters as given (the others at their defaults).
    t : numpy.ndarray
        Sample times [s].
    force : numpy.ndarray
        Friction force mu N [N], with the sign of the velocity in steady sliding (the force that
        drives the motion against friction; the force on the sliding body is -force).
    mu : numpy.ndarray
        Friction coefficient [-] (asymmetry applied).
    z : numpy.ndarray
        Internal states, shape (n_states, len(t)), named in `state_labels`.
    x_contact : numpy.ndarray
        Displacement of the contact after the backlash [m].
    v_contact : numpy.ndarray
        Velocity of the contact [m/s] (0 inside the backlash band).
    state_labels : tuple of str
        Names and units of the states.
    stats : dict
        ``n_advance`` (substeps of the state integration, both halves of every step-doubling
        test), ``n_unconverged`` (sample intervals kept at the substep limit without meeting
        rtol; 0 normally), ``max_substeps`` (largest substep count of one monotone piece).
    """

    law: str
    params: dict[str, float]
    t: np.ndarray
    force: np.ndarray
    mu: np.ndarray
    z: np.ndarray
    x_contact: np.ndarray
    v_contact: np.ndarray
    state_labels: tuple[str, ...] = ()
    stats: dict[str, int] = field(default_factory=dict)


def _law_params(law: str, params: dict[str, Any]) -> tuple[tuple[str, float], ...]:
    """The given parameters of `law`, names known to the law and values real numbers."""
    _choice("law", law, LAWS)
    accepted = REGISTRY["law"][law]["params"]
    unknown = [k for k in params if k not in accepted]
    if unknown:
        raise ValueError(f"unknown parameter(s) {', '.join(sorted(unknown))} of law {law!r} "
                         f"(accepted: {', '.join(accepted)})")
    return tuple(_physical(params).items())


def law_n_states(law: str, **params: float) -> int:
    """Number of internal states of `law` with these parameters (0 for a static law; for the
    generalized Maxwell-slip model its ``n_elements``).

    Parameters
    ----------
    law : str
        A name of LAWS.
    **params : float
        The law's parameters (DEFAULTS for those not given); only ``n_elements`` changes the
        count.

    Returns
    -------
    int
        The number of internal states, >= 0.

    Raises
    ------
    ValueError
        For an unknown law, or a parameter unknown to it or out of its range.
    """
    return _states(law, _law_params(law, params))[0]


def law_state_labels(law: str, **params: float) -> tuple[str, ...]:
    """Names and units of the internal states of `law` with these parameters.

    Parameters
    ----------
    law : str
        A name of LAWS.
    **params : float
        The law's parameters, as for `law_n_states`.

    Returns
    -------
    tuple of str
        One label a state, e.g. ``('z [m]',)`` for LuGre, ``()`` for a static law.

    Raises
    ------
    ValueError
        For an unknown law, or a parameter unknown to it or out of its range.
    """
    return _states(law, _law_params(law, params))[1]


def _samples(name: str, value: Any, n: int | None, unit: str) -> np.ndarray:
    try:
        a = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"{name}: must be real numbers [{unit}], got {type(value).__name__}") from None
    if a.ndim != 1 or (n is not None and a.size != n):
        want = "a 1-d array" if n is None else f"{n} values, one per sample of t"
        raise ValueError(f"{name}: must be {want} [{unit}], got shape {a.shape}")
    if not np.isfinite(a).all():
        i = int(np.flatnonzero(~np.isfinite(a))[0])
        raise ValueError(f"{name}: must be finite [{unit}], got {a[i]!r} at sample {i}")
    return np.ascontiguousarray(a)


def prescribed_motion(law: str, t: Any, x: Any, v: Any = None, *, normal_force: Any = 1.0, z0: Any = None,
                      backlash: float = 0.0, asymmetry: float = 1.0, rtol: float = 1e-8,
                      **params: float) -> PrescribedResult:
    """The friction force of `law` along a prescribed motion x(t) of the sliding body relative
    to its support.

    Parameters
    ----------
    law : str
        A friction law of `stickslip.LAWS`.
    t : array_like
        Sample times [s], strictly increasing.
    x : array_like
        Displacement at t [m].
    v : array_like, optional
        Velocity at t [m/s]. When omitted it is derived from x as the derivative at each sample
        of the parabola through it and its two neighbours (`numpy.gradient(x, t,
        edge_order=2)`; one neighbour for a two-sample record). Between samples the motion is
        the cubic Hermite interpolant of (x, v).
    normal_force : float or array_like
        Normal force N [N], >= 0: a scalar or one value per sample.
    z0 : array_like, optional
        Initial internal states (``law_n_states(law, **params)`` values; default 0).
    backlash : float
        Total width of a play between the body and the contact [m], >= 0: after a reversal the
        contact stays put until x has travelled `backlash` (it starts centred in the band).
    asymmetry : float
        Ratio of the negative-direction sliding level to the positive one, > 0: a negative
        friction coefficient is multiplied by it.
    rtol : float
        Relative tolerance of the state integration's step-doubling test per sample interval
        (0 or in [2.2e-14, 1)).
    **params : float
        The law's parameters (`stickslip.REGISTRY["law"][law]["params"]`; the others at their
        defaults, `stickslip.DEFAULTS`).

    Returns
    -------
    PrescribedResult
        t, force [N], mu [-], z (n_states, len(t)), x_contact [m], v_contact [m/s].

    Raises
    ------
    ValueError
        For bad input, naming it and its accepted range: an unknown law or parameter, a
        parameter out of range, NaN or infinite samples, mismatched lengths, t not strictly
        increasing, backlash < 0, asymmetry <= 0, a negative normal force, z0 of the wrong size.

    Examples
    --------
    >>> import numpy as np, stickslip
    >>> t = np.linspace(0.0, 2.0, 2001)
    >>> res = stickslip.prescribed_motion("lugre", t, 1e-3 * np.sin(np.pi * t), normal_force=100.0)
    >>> res.force.shape, res.z.shape
    ((2001,), (1, 2001))
    """
    given = _law_params(law, params)
    code = REGISTRY["law"][law]["code"]
    tt = _samples("t", t, None, "s")
    n = tt.size
    if n < 1:
        raise ValueError("t: must hold at least one sample time [s]")
    bad = np.flatnonzero(~(np.diff(tt) > 0.0))
    if bad.size:
        i = int(bad[0])
        raise ValueError(f"t: must be strictly increasing [s], got t[{i}] = {tt[i]!r} and t[{i + 1}] = {tt[i + 1]!r}")
    xx = _samples("x", x, n, "m")
    if v is None:
        vv = np.gradient(xx, tt, edge_order=2 if n > 2 else 1) if n > 1 else np.zeros(1)
    else:
        vv = _samples("v", v, n, "m/s")
    if np.ndim(normal_force) == 0:
        nf = np.array([_finite("normal_force", normal_force, ">= 0, a scalar or one value per sample [N]")])
    else:
        nf = _samples("normal_force", normal_force, n, "N")
    if (nf < 0.0).any():
        raise ValueError(f"normal_force: must be >= 0 [N], got {nf[nf < 0.0][0]!r}")
    backlash = _finite("backlash", backlash, ">= 0 [m]")
    if backlash < 0.0:
        raise ValueError(f"backlash: must be >= 0 [m], got {backlash!r}")
    asymmetry = _finite("asymmetry", asymmetry, "> 0 [-]")
    if asymmetry <= 0.0:
        raise ValueError(f"asymmetry: must be > 0 (negative-direction level / positive one) [-], got {asymmetry!r}")
    rtol = _finite("rtol", rtol, "0 or in [2.2e-14, 1)")
    nz, labels = _states(law, given)
    if z0 is None:
        zz = np.zeros(nz)
    else:
        zz = np.atleast_1d(np.asarray(z0, dtype=np.float64))
        if zz.shape != (nz,) or not np.isfinite(zz).all():
            raise ValueError(f"z0: must be {nz} finite value(s), the initial internal states of {law!r} "
                             f"({', '.join(labels) or 'none'})")
    force, mu, z, xc, vc, counters, _ = _run(code, given, tt, xx, vv, nf, zz, backlash, asymmetry, rtol)
    stats = dict(zip(("n_advance", "n_unconverged", "max_substeps"), (int(c) for c in counters)))
    return PrescribedResult(law=law, params=dict(given), t=tt, force=force, mu=mu, z=np.asarray(z).reshape(nz, n),
                            x_contact=xc, v_contact=vc, state_labels=labels, stats=stats)


_ADAPTIVE = np.zeros(0, dtype=np.int32)


def _run(code: int, given: tuple[tuple[str, float], ...], t: np.ndarray, x: np.ndarray, v: np.ndarray,
         nf: np.ndarray, z0: np.ndarray, backlash: float, asymmetry: float, rtol: float,
         substeps: np.ndarray | None = None) -> tuple[np.ndarray, ...]:
    """The Fortran call on checked samples: force, mu, z, x_c, v_c, counters and the substeps
    per monotone piece that each sample interval used. `substeps` (n - 1 values >= 1) freezes
    the mesh instead of the step-doubling choice (for finite differences in the parameters:
    the force is then a smooth function of them). Raises ValueError for a bad parameter,
    RuntimeError for a failed state integration."""
    keys, vals = _keys(dict(given))
    msub = _ADAPTIVE if substeps is None else np.ascontiguousarray(substeps, dtype=np.int32)
    if msub.size and (msub.size != t.size - 1 or msub.min() < 1 or msub.max() > 65536):
        raise ValueError(f"substeps: must be {t.size - 1} integers in [1, 65536] (one per sample interval), "
                         f"got {msub.size} in [{msub.min()}, {msub.max()}]")
    force, mu, z, xc, vc, counters, used, status = _ext.prescribed(
        code, keys, vals, t, x, v, nf, z0, backlash, asymmetry, rtol, msub)
    if int(status) != 0:
        _check_code(int(status), dict(given))
        raise RuntimeError(f"prescribed_motion: the state integration failed (status {int(status)})")
    return force, mu, z, xc, vc, counters, used[:max(t.size - 1, 0)]


def _force_on(law: str, params: dict[str, float], t: np.ndarray, x: np.ndarray, v: np.ndarray, nf: np.ndarray,
              backlash: float, asymmetry: float, rtol: float,
              substeps: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The force of `law` (states from 0) on samples already checked (identification's
    inner loop), and the substeps per piece of each sample interval; `substeps` freezes them
    (see `_run`). Parameters are checked by the library (ValueError naming the bad one)."""
    given = _law_params(law, params)
    nz = _states(law, given)[0]
    code = REGISTRY["law"][law]["code"]
    out = _run(code, given, t, x, v, nf, np.zeros(nz), backlash, asymmetry, rtol, substeps)
    return out[0], out[6]
