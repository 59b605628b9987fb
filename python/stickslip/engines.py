"""Friction in physics engines, as laws stickslip can state exactly.

Five engine models regularise Coulomb friction by a law of the slip speed alone, and the steady
creep of the paper's slope box (10 kg, 10 degrees, mu_s = 0.35, mu_k = 0.30, which truly never
moves) in each follows from the balance of that law on the slope, mu(v*) N = m g sin(theta).
Four of these laws are registered laws of the library, written once in Fortran
(fortran/laws/stickslip_law_<name>.f90, each with its source): ``drake_continuous``,
``drake_tamsi``, ``capped_viscous`` (Newton; MuJoCo's elliptic cone) and ``mujoco_pyramidal``;
`stickslip.simulate` takes them like any law, and this module evaluates them through
`stickslip.friction_coefficient` with the parameters the engine's settings give
(`engine_contacts`). The engines:

- ``drake_continuous``: Drake's MultibodyPlant in continuous mode (point contact), its
  StribeckModel: mu_s step5(v / v_s) below the stiction tolerance v_s, a quintic step down to
  mu_d on [v_s, 3 v_s], mu_d beyond; step5(x) = 10 x^3 - 15 x^4 + 6 x^5 (the paper's haversine
  family: a C2 step instead of a half cosine); the law ``drake_continuous`` with v_s the
  stiction tolerance. Source: drake, multibody/plant/multibody_plant.cc,
  ``StribeckModel::ComputeFrictionCoefficient`` and ``step5`` (drake 1.x; the law is unchanged
  since 2019).
- ``drake_tamsi``: Drake's discrete MultibodyPlant with the TAMSI solver: mu s (2 - s) for
  s = v / v_s < 1, mu beyond, with mu the dynamic coefficient (discrete Drake ignores the static
  one); the law ``drake_tamsi``. Source: drake, ``StribeckModel::ModifiedStribeck`` (multibody_plant.cc, drake 1.x);
  checked against drake 1.51.1's own runs.
- ``drake_lagged``: Drake's default discrete model (the "lagged" convex approximation of
  compliant contact): friction regularised by the stiction tolerance (Drake's
  ``DiscreteContactApproximation`` documentation, drake 1.51; Castro, Han and Masterjohn 2023),
  of the form mu_d s / sqrt(1 + s^2), s = v / v_s. The form is identified from Drake's own runs,
  not read from its source: their creep is proportional to v_s and v* / v_s = 0.7265, the root
  of mu_d s / sqrt(1 + s^2) = tan(theta) (python -m cases.engines); on slopes of 5 and 15
  degrees the same form predicts Drake's creep to 1e-7 (tests/test_engines.py). Not a
  registered law (it is not published): `drake_lagged_mu`.
- ``mujoco``: MuJoCo's soft contact. Inside the friction cone each frictional constraint row
  gives the force D (a_ref - a) with D = 1 / R and a_ref = -B v (K = 0 in friction rows), so at a
  steady slip (a = 0) the contact acts as a viscous damper of coefficient B / R_friction:
  B = 2 / (d_max t_c) (t_c = max(solref[0], 2 timestep), or -solref[1] / d_max in the direct
  format); R_0 = (1 - d) / d * A with d the impedance at the contact's penetration (solimp) and A
  the body's translational inverse weight (1 / m for a free box); elliptic cone: R_friction =
  R_0 / impratio; pyramidal cone: each of the four edge rows n +- mu t has A = (1 + mu^2) / m and
  R = 2 (mu^2 / impratio) R_0, and an edge whose force would be negative drops out: the laws
  ``capped_viscous`` (elliptic) and ``mujoco_pyramidal``, each contact with its v_s
  (`mujoco_v_s`). Source:
  mujoco, src/engine/engine_core_constraint.c (``mj_diagApprox``, ``mj_makeImpedance``,
  ``getimpedance``; mujoco 3.x); checked against mujoco 4.0.0's own runs (``cases.engines``).
- ``newton_semi_implicit``: Newton's (and warp.sim's) semi-implicit Euler rigid contact:
  min(k_f |v_t|, mu f_n) per contact point, k_f the mean of the two shapes' (default 1000
  N s/m, ``ModelBuilder.ShapeConfig.kf``): the law ``capped_viscous`` with v_s = mu f_n / k_f
  per contact. Source: newton 1.8,
  newton/_src/solvers/semi_implicit/kernels_contact.py (``eval_body_contact``), and warp.sim's
  ``eval_rigid_contacts``.

Bullet's sequential-impulse solver and Drake's SAP solver (whose regularisation Drake sets
from the numerics alone) have no smooth law of this kind: they solve a velocity-level cone
problem each step, and what creep they show is measured by ``python -m cases.engines``, not
predicted here (`NO_LAW`).

`engine_creep` returns the creep speed, `advise_engine` the setting for a creep budget,
`engine_mu` the equivalent friction coefficient of the whole box at a slip speed.
"""
from __future__ import annotations

import math
import numbers
import warnings
from typing import Any, Callable

import numpy as np

from .core import friction_coefficient

#: The engines with an equivalent law, each with its settings and their defaults (the engine's
#: own defaults; mu None: the scene's mu_k).
ENGINE_SETTINGS: dict[str, dict[str, Any]] = {
    "drake_continuous": {"stiction_tolerance": 1e-4},
    "drake_tamsi": {"stiction_tolerance": 1e-4},
    "drake_lagged": {"stiction_tolerance": 1e-4},
    "mujoco": {"cone": "pyramidal", "impratio": 1.0, "solref": (0.02, 1.0),
               "solimp": (0.9, 0.95, 0.001, 0.5, 2.0), "timestep": 0.002, "n_contacts": 4,
               "mu": None, "noslip_iterations": 0},
    "newton_semi_implicit": {"k_f": 1000.0, "n_contacts": 4, "mu": None},
}
#: The engines with an equivalent law (engine_creep, advise_engine and engine_mu take them).
ENGINES: tuple[str, ...] = tuple(ENGINE_SETTINGS)
#: Engines without a smooth law, and why.
NO_LAW: dict[str, str] = {
    "bullet": "Bullet solves a velocity-level friction cone by sequential impulses each step: no "
              "smooth law; its creep is measured (python -m cases.engines)",
    "drake_sap": "Drake's SAP solver solves a convex velocity-level cone problem each step: no "
                 "smooth law; its creep is measured",
}
#: The slope's parameters (the paper's) and the engines' box: aspect = height of the centre of
#: mass above the contact plane over the half-length of the footprint along the slope (0.5: a
#: 0.2 x 0.2 x 0.1 m box); it sets how the normal load splits between the front and back
#: contacts of a 4-contact box.
SCENE_DEFAULTS: dict[str, float] = {"theta_deg": 10.0, "m": 10.0, "g": 9.81, "mu_s": 0.35,
                                    "mu_k": 0.30, "aspect": 0.5}
CONES: tuple[str, ...] = ("pyramidal", "elliptic")
#: solimp's last two numbers where fewer than five are given (MuJoCo's own defaults: midpoint
#: 0.5, power 2).
SOLIMP_TAIL: tuple[float, float] = (0.5, 2.0)

#: MuJoCo's damping ratio (solref's second number, or B / (2 sqrt(K)) in the direct format)
#: below which the slope box rocks on its contacts in MuJoCo's own runs: the number of active
#: contacts drops from 4 to 2 or 0 and the box creeps faster than the steady law predicts
#: (pyramidal: 1.9 to 3.7 times at dampratio 0.3-0.7 with the defaults otherwise). Measured with
#: mujoco 4.0.0 by bisection on 10 s runs of the paper's box (``python -m cases.engines
#: --rocking``, engines_rocking.csv), over timestep 0.5-5 ms, solref timeconst 0.01-0.1 s and
#: impratio 1-100; each entry is the largest threshold found at that impratio (pyramidal) or at
#: any (elliptic), rounded up to 0.01. Between the impratios listed the larger neighbour's
#: threshold applies; beyond 100, the last.
ROCKING_DAMPRATIO: dict[str, tuple[tuple[float, float], ...]] = {
    "pyramidal": ((1.0, 0.72), (3.0, 0.77), (10.0, 0.81), (30.0, 0.83), (100.0, 0.85)),
    "elliptic": ((math.inf, 0.51),),
}


class EngineDomainWarning(UserWarning):
    """A prediction outside the domain where the engine's equivalent law describes its runs
    (the engine's own motion differs: it rocks, or it slides past a creep that exists only for
    small disturbances)."""


def _real(key: str, value: Any) -> float:
    """value as a float (Python or numpy real numbers, not bool); ValueError naming key."""
    if isinstance(value, bool) or not isinstance(value, (numbers.Real, np.floating, np.integer)):
        raise ValueError(f"{key} must be a real number, got {value!r}")
    return float(value)


def _names(seq: Any) -> str:
    return ", ".join(seq)


def _split(engine: str, settings: dict[str, Any]) -> tuple[dict[str, float], dict[str, Any]]:
    """Check the engine and its settings; return (scene, engine settings) with defaults."""
    if engine in NO_LAW:
        raise ValueError(f"{engine}: {NO_LAW[engine]}; engines with a law: {_names(ENGINES)}")
    if engine not in ENGINE_SETTINGS:
        raise ValueError(f"unknown engine {engine!r}; accepted: {_names(ENGINES)}")
    scene, own = dict(SCENE_DEFAULTS), dict(ENGINE_SETTINGS[engine])
    for key, value in settings.items():
        if key in SCENE_DEFAULTS:
            scene[key] = _real(key, value)
        elif key in own:
            own[key] = value
        else:
            raise ValueError(f"{engine} has no setting {key!r}; accepted: "
                             f"{_names(list(own) + list(SCENE_DEFAULTS))}")
    for key in ("m", "g", "mu_s", "mu_k"):
        if not scene[key] > 0:
            raise ValueError(f"{key} must be > 0, got {scene[key]}")
    if not 0 < scene["theta_deg"] < 90:
        raise ValueError(f"theta_deg must be in (0, 90), got {scene['theta_deg']}")
    if not scene["aspect"] >= 0:
        raise ValueError(f"aspect must be >= 0, got {scene['aspect']}")
    for key, value in own.items():
        if value is None and key != "mu":
            raise ValueError(f"{engine} needs the setting {key!r} (no default)")
    if "mu" in own and own["mu"] is None:
        own["mu"] = scene["mu_k"]        # one coefficient: the kinetic one
    for key in ("stiction_tolerance", "impratio", "timestep", "k_f", "mu"):
        if key in own:
            own[key] = _real(key, own[key])
            if not (own[key] > 0 and math.isfinite(own[key])):
                raise ValueError(f"{key} must be a finite number > 0, got {own[key]:g}")
    if "noslip_iterations" in own:
        n = own["noslip_iterations"]
        if isinstance(n, bool) or not isinstance(n, (numbers.Integral, np.integer)) or n < 0:
            raise ValueError(f"noslip_iterations must be an integer >= 0, got {n!r}")
        own["noslip_iterations"] = int(n)
    if "n_contacts" in own:
        n = own["n_contacts"]
        if isinstance(n, bool) or not isinstance(n, (numbers.Real, np.number)) or int(n) != n or n < 1:
            raise ValueError(f"n_contacts must be an integer >= 1, got {n!r}")
        own["n_contacts"] = int(n)
    if "cone" in own and own["cone"] not in CONES:
        raise ValueError(f"unknown cone {own['cone']!r}; accepted: {_names(CONES)}")
    if "solref" in own:
        ref = tuple(float(x) for x in own["solref"])
        if len(ref) != 2 or (ref[0] > 0) != (ref[1] > 0) or 0 in ref:
            raise ValueError(f"solref must be (timeconst > 0, dampratio > 0) or (-stiffness, "
                             f"-damping), got {own['solref']}")
        own["solref"] = ref
    if "solimp" in own:
        imp = tuple(_real("solimp", x) for x in own["solimp"])
        if 3 <= len(imp) < 5:           # MuJoCo takes 3 to 5 numbers: the rest its defaults
            imp = imp + SOLIMP_TAIL[len(imp) - 3:]
        if len(imp) != 5 or not (0 < imp[0] < 1 and 0 < imp[1] < 1 and imp[2] >= 0
                                 and 0 < imp[3] < 1 and imp[4] >= 1):
            raise ValueError(f"solimp must be 3 to 5 numbers (dmin, dmax in (0, 1), width >= 0"
                             f"[, midpoint in (0, 1)[, power >= 1]]), got {own['solimp']!r}")
        own["solimp"] = imp
    if own.get("cone") == "elliptic" and own.get("noslip_iterations", 0) > 0:
        raise ValueError("mujoco: noslip_iterations > 0 with the elliptic cone has no "
                         "equivalent law: MuJoCo's noslip pass then removes the soft cone's slip "
                         "after each solve (mujoco 4.0.0's runs of the paper's box: 5.2e-6 m/s "
                         "after 1 iteration, 5.9e-8 m/s after 3 or more, against 4.4e-4 m/s "
                         "without), a creep set by the pass, not by a law; measure it with the "
                         "engine (python -m cases.engines). With the pyramidal cone the pass "
                         "changed nothing in those runs, and engine_creep takes it")
    return scene, own


# ------------------------------------------------------------------------------------------
# The laws: each engine's contacts as registered laws of the library (one implementation, in
# Fortran: fortran/laws/stickslip_law_<name>.f90), with the parameters the engine's settings give
# ------------------------------------------------------------------------------------------
#: The registered law of each engine with one (`stickslip.LAWS`); drake_lagged has none (its
#: form is identified from Drake's runs, not published: `drake_lagged_mu`).
ENGINE_LAWS: dict[str, str] = {"drake_continuous": "drake_continuous", "drake_tamsi": "drake_tamsi",
                               "newton_semi_implicit": "capped_viscous"}
MUJOCO_LAWS: dict[str, str] = {"elliptic": "capped_viscous", "pyramidal": "mujoco_pyramidal"}


def drake_lagged_mu(v: Any, stiction_tolerance: float, mu: float) -> np.ndarray:
    """Drake's lagged approximation's regularised coefficient mu s / sqrt(1 + s^2), s = |v| / v_s
    (identified from Drake's runs, so not a law of the registry; see the module's
    documentation)."""
    s = np.abs(np.asarray(v, dtype=float)) / stiction_tolerance
    return mu * s / np.sqrt(1.0 + s * s)


def mujoco_impedance(solimp: tuple[float, ...], depth: float) -> float:
    """MuJoCo's impedance d at a penetration depth [m] (>= 0; zero margin), from solimp."""
    dmin, dmax, width, mid, power = solimp
    if dmin == dmax or width <= 1e-15:
        return 0.5 * (dmin + dmax)
    x = depth / width
    if x >= 1 or x <= 0:
        return dmax if x >= 1 else dmin
    if power == 1:
        y = x
    elif x <= mid:
        y = x ** power / mid ** (power - 1)
    else:
        y = 1 - (1 - x) ** power / (1 - mid) ** (power - 1)
    return dmin + y * (dmax - dmin)


def _mujoco_kb(own: dict[str, Any]) -> tuple[float, float]:
    """MuJoCo's K [1/s^2] and B [1/s] of solref (refsafe: timeconst >= 2 timestep)."""
    ref, dmax = own["solref"], own["solimp"][1]
    if ref[0] > 0:
        tc = max(ref[0], 2 * float(own["timestep"]))
        return 1 / (dmax ** 2 * tc ** 2 * ref[1] ** 2), 2 / (dmax * tc)
    return -ref[0] / dmax ** 2, -ref[1] / dmax


def mujoco_dampratio(own: dict[str, Any]) -> float:
    """MuJoCo's damping ratio of solref: its second number (timeconst, dampratio), or
    B / (2 sqrt(K)) in the direct format (-stiffness, -damping)."""
    K, B = _mujoco_kb(own)
    return B / (2.0 * math.sqrt(K))


def rocking_dampratio(cone: str, impratio: float) -> float:
    """The damping ratio below which the slope box rocks in MuJoCo (`ROCKING_DAMPRATIO`)."""
    for upto, zeta in ROCKING_DAMPRATIO[cone]:
        if impratio <= upto:
            return zeta
    return ROCKING_DAMPRATIO[cone][-1][1]


def _check_rocking(own: dict[str, Any]) -> None:
    """EngineDomainWarning where solref's damping ratio is below MuJoCo's rocking threshold."""
    zeta, limit = mujoco_dampratio(own), rocking_dampratio(own["cone"], own["impratio"])
    if zeta < limit:
        warnings.warn(EngineDomainWarning(
            f"mujoco: solref's damping ratio {zeta:.3g} is below {limit:g}, where the box rocks "
            f"on its contacts in MuJoCo's runs ({own['cone']} cone, impratio "
            f"{own['impratio']:g}) and creeps faster than this steady law predicts (the "
            f"pyramidal cone 1.9-3.7 times at damping ratios 0.3-0.7); measure it with the "
            f"engine (python -m cases.engines)"), stacklevel=3)


def mujoco_v_s(own: dict[str, Any], inv_weight: float, load: float) -> float:
    """The v_s [m/s] of one MuJoCo contact carrying the normal load [N] (the parameter of the
    registered law of its cone, `MUJOCO_LAWS`): the slip speed at which its viscous force,
    B/R times the speed, would reach mu times the load, with B of solref and R of the friction
    rows at the impedance d of the contact's penetration at rest (solimp; the penetration from
    the normal balance, by bisection: the normal force grows with it).

    Elliptic cone: v_s = mu load (1 - d) A / (d B impratio). Pyramidal cone (four edge rows
    n +- mu t, each with R = 2 (mu^2/impratio) (1 - d)/d (1 + mu^2) A, all four pushing at rest):
    v_s = mu load (1 - d) (1 + mu^2) A / (d B impratio). A = inv_weight, the body's
    translational inverse weight [1/kg]."""
    K, B = _mujoco_kb(own)
    mu, ir, pyramidal = float(own["mu"]), float(own["impratio"]), own["cone"] == "pyramidal"
    edge = 2 * (mu * mu / ir) * (1 + mu * mu) if pyramidal else 1.0   # R_row / ((1 - d)/d A)

    def normal(depth: float) -> float:        # the normal force at rest at this penetration [N]
        d = mujoco_impedance(own["solimp"], depth)
        return (4 if pyramidal else 1) * K * d * depth / (edge * (1 - d) / d * inv_weight)

    lo, hi = 0.0, 1e-6
    while normal(hi) < load:
        lo, hi = hi, hi * 2
        if hi > 1e3:
            raise ValueError("MuJoCo contact: no penetration carries the load")
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if normal(mid) < load else (lo, mid)
    d = mujoco_impedance(own["solimp"], hi)
    return mu * load * (1 - d) / d * inv_weight * (1 + mu * mu if pyramidal else 1.0) / (B * ir)


def _loads(scene: dict[str, float], n: int) -> list[float]:
    """Normal load [N] on each of n contacts: a 4-contact box's front and back pairs share the
    overturning moment of the friction (aspect), other counts share equally."""
    th = math.radians(scene["theta_deg"])
    total = scene["m"] * scene["g"] * math.cos(th)
    if n != 4:
        return [total / n] * n
    e = scene["aspect"] * math.tan(th)
    if e >= 1:
        raise ValueError(f"aspect {scene['aspect']} tips the box over on this slope")
    return [total / 4 * (1 + e)] * 2 + [total / 4 * (1 - e)] * 2


def engine_contacts(engine: str, **settings: Any) -> list[tuple[str, dict[str, float], float]]:
    """The slope box's contacts in an engine as laws of the registry: a list of (law, its
    parameters, normal load [N] times the number of contacts alike), whose friction forces
    add up to the box's, ``sum(load * ss.friction_coefficient(law, v, **params))``.

    Drake's laws act on the whole normal load m g cos(theta) (their coefficient does not
    depend on the load); Newton's and MuJoCo's act per contact point, each with its own v_s:
    Newton's capped_viscous with v_s = mu f_n / k_f, MuJoCo's law of its cone with
    `mujoco_v_s`. Contacts with the same law and parameters are merged (the front pair and
    the back pair of a four-contact box).

    Parameters
    ----------
    engine : str
        One of `ENGINES` but drake_lagged (no registered law: `drake_lagged_mu`).
    **settings
        As for `engine_creep`.

    Returns
    -------
    list of (str, dict, float)
        (law, parameters, load [N]).

    Raises
    ------
    ValueError
        As `engine_creep`, and for drake_lagged.
    """
    scene, own = _split(engine, settings)
    N = scene["m"] * scene["g"] * math.cos(math.radians(scene["theta_deg"]))
    if engine == "drake_lagged":
        raise ValueError("drake_lagged has no registered law (its form is identified from "
                         "Drake's runs): use stickslip.engines.drake_lagged_mu")
    if engine == "drake_continuous":
        return [("drake_continuous", {"mu_s": scene["mu_s"], "mu_k": scene["mu_k"],
                                      "v_s": float(own["stiction_tolerance"])}, N)]
    if engine == "drake_tamsi":
        return [("drake_tamsi", {"mu_k": scene["mu_k"], "v_s": float(own["stiction_tolerance"])}, N)]
    merged: dict[tuple[str, float], float] = {}
    for f in _loads(scene, own["n_contacts"]):
        if engine == "newton_semi_implicit":
            key = ("capped_viscous", float(own["mu"]) * f / float(own["k_f"]))
        else:           # a free body's translational inverse weight is 1/m (body_invweight0)
            key = (MUJOCO_LAWS[own["cone"]], mujoco_v_s(own, 1.0 / scene["m"], f))
        merged[key] = merged.get(key, 0.0) + f
    return [(law, {"mu_k": float(own["mu"]), "v_s": vs}, load) for (law, vs), load in merged.items()]


def _force(engine: str, settings: dict[str, Any]) -> Callable[[np.ndarray], np.ndarray]:
    """Total friction force [N] on the box at slip speeds v [m/s] (an array), by the engine's
    law."""
    if engine == "drake_lagged":
        scene, own = _split(engine, settings)
        N = scene["m"] * scene["g"] * math.cos(math.radians(scene["theta_deg"]))
        return lambda v: drake_lagged_mu(v, own["stiction_tolerance"], scene["mu_k"]) * N
    contacts = engine_contacts(engine, **settings)
    return lambda v: sum(load * friction_coefficient(law, v, **params)
                         for law, params, load in contacts)


def engine_mu(engine: str, v: Any, **settings: Any) -> np.ndarray:
    """The engine's equivalent friction coefficient of the slope box at slip speed v [m/s]:
    its total friction force over the total normal load m g cos(theta), each contact's force
    from its registered law (`engine_contacts`; drake_lagged from `drake_lagged_mu`).

    Parameters
    ----------
    engine : str
        One of `ENGINES`.
    v : float or array
        Slip speed [m/s] (>= 0).
    **settings
        The engine's settings (`ENGINE_SETTINGS`) and the scene's (`SCENE_DEFAULTS`).

    Returns
    -------
    numpy.ndarray
        mu(v) [-], the shape of v.

    Examples
    --------
    >>> import stickslip as ss
    >>> round(float(ss.engine_mu("drake_tamsi", 5e-5, stiction_tolerance=1e-4)), 12)   # 0.3 s (2 - s)
    0.225
    """
    scene, _ = _split(engine, settings)
    N = scene["m"] * scene["g"] * math.cos(math.radians(scene["theta_deg"]))
    v = np.asarray(v, dtype=float)
    if np.any(~(v >= 0)):
        raise ValueError("v must be >= 0 (a slip speed)")
    return np.asarray(_force(engine, settings)(v) / N, dtype=float).reshape(v.shape)


def engine_creep(engine: str, **settings: Any) -> float:
    """Steady creep speed [m/s] of the paper's slope box in a physics engine.

    The speed v* where the engine's friction law balances the slope, F(v*) = m g sin(theta),
    F being the total friction force of the box's contacts (`engine_contacts`): in closed form
    for Drake's TAMSI and lagged laws and for Newton below its caps, else by k-section on F
    evaluated by the registered laws. math.inf when the law cannot hold the box at any speed
    (the box accelerates).

    Parameters
    ----------
    engine : str
        "drake_continuous", "drake_tamsi", "drake_lagged", "mujoco" or "newton_semi_implicit".
    **settings
        The engine's settings: stiction_tolerance [m/s] (Drake); cone ("pyramidal" or
        "elliptic"), impratio, solref, solimp, timestep [s], n_contacts, mu (MuJoCo); k_f
        [N s/m], n_contacts, mu (Newton); and the scene's: theta_deg, m [kg], g [m/s^2], mu_s,
        mu_k, aspect. Engines with one friction coefficient take mu = mu_k unless given.

    Returns
    -------
    float
        v* [m/s].

    Raises
    ------
    ValueError
        An unknown engine or setting, a setting the engine does not have, or a bad value.

    Examples
    --------
    >>> import stickslip as ss
    >>> round(ss.engine_creep("drake_tamsi", stiction_tolerance=1e-4) * 20 * 1e3, 3)  # mm in 20 s
    0.716
    """
    scene, own = _split(engine, settings)
    th = math.radians(scene["theta_deg"])
    pull = scene["m"] * scene["g"] * math.sin(th)
    t = math.tan(th)
    cap = {"drake_continuous": scene["mu_s"], "drake_tamsi": scene["mu_k"],
           "drake_lagged": scene["mu_k"]}.get(engine, own.get("mu"))
    if t >= cap:
        return math.inf
    if engine == "drake_continuous" and t > min(scene["mu_k"], scene["mu_s"]):
        warnings.warn(EngineDomainWarning(
            f"drake_continuous: tan(theta) = {t:.4g} lies between mu_d = {scene['mu_k']:g} and "
            f"mu_s = {scene['mu_s']:g}: the law has a creep below the stiction tolerance, but "
            f"past it the coefficient falls to mu_d, which cannot hold the box, so any excursion "
            f"(Drake's own runs from rest) slides away: math.inf"), stacklevel=2)
        return math.inf
    if engine == "mujoco":
        _check_rocking(own)
    if engine == "drake_tamsi":
        return (1 - math.sqrt(1 - t / scene["mu_k"])) * own["stiction_tolerance"]
    if engine == "drake_lagged":
        return t / math.sqrt(scene["mu_k"] ** 2 - t * t) * own["stiction_tolerance"]
    if engine == "newton_semi_implicit":
        # below every cap F = n k_f v
        v = pull / (own["n_contacts"] * own["k_f"])
        if all(own["k_f"] * v <= own["mu"] * f for f in _loads(scene, own["n_contacts"])):
            return v
    # F rises to its cap (the whole load times the cap coefficient) by 3 v_s at the latest
    hi = 3.0 * max(params["v_s"] for _, params, _ in engine_contacts(engine, **settings))
    return _solve_increasing(_force(engine, settings), pull, hi)


def _solve_increasing(f: Callable[[np.ndarray], np.ndarray], target: float, hi: float,
                     points: int = 64) -> float:
    """The x in [0, hi] where the nondecreasing f (evaluated on arrays) first reaches target,
    by k-section: f on `points` points of the bracket, the bracket narrowed to the interval
    where f crosses the target, until it is a few ulps wide (f(0) < target <= f(hi))."""
    lo = 0.0
    while hi - lo > 4 * np.spacing(hi):
        x = np.linspace(lo, hi, points)
        reached = np.asarray(f(x)) >= target
        k = int(np.argmax(reached)) if reached.any() else points     # first x with f >= target
        if k == 0:
            return lo
        if k == points:
            return math.inf
        lo, hi = float(x[k - 1]), float(x[k])
    return 0.5 * (lo + hi)


#: The box's footprint half-length along the slope [m] in `mujoco_slope_xml` (its height is
#: 2 aspect times it; 0.2 x 0.2 x 0.1 m at the default aspect 0.5).
BOX_HALF_LENGTH: float = 0.1


def mujoco_slope_xml(**settings: Any) -> str:
    """MuJoCo's model (MJCF) of the paper's slope box with the given engine and scene settings
    (as for `engine_creep`): a free box of mass m resting on a plane under gravity tilted by
    theta_deg, friction mu on both geoms (MuJoCo takes the larger), the contact's solref and
    solimp on both, and the options timestep, cone, impratio and noslip_iterations."""
    scene, own = _split("mujoco", settings)
    th = math.radians(scene["theta_deg"])
    gravity = f'{scene["g"] * math.sin(th)!r} 0 {-scene["g"] * math.cos(th)!r}'
    half = (BOX_HALF_LENGTH, BOX_HALF_LENGTH, scene["aspect"] * BOX_HALF_LENGTH)
    contact = (f'friction="{own["mu"]!r} 0.005 0.0001" '
               f'solref="{own["solref"][0]!r} {own["solref"][1]!r}" '
               f'solimp="{" ".join(repr(x) for x in own["solimp"])}"')
    return (f'<mujoco><option timestep="{own["timestep"]!r}" cone="{own["cone"]}" '
            f'impratio="{own["impratio"]!r}" noslip_iterations="{own["noslip_iterations"]}" '
            f'gravity="{gravity}"/><worldbody>'
            f'<geom type="plane" size="100 5 0.1" {contact}/>'
            f'<body pos="0 0 {half[2]!r}"><freejoint/>'
            f'<geom type="box" size="{half[0]!r} {half[1]!r} {half[2]!r}" mass="{scene["m"]!r}" '
            f'{contact}/></body></worldbody></mujoco>')


def mujoco_settle(t_end: float = 1.0, **settings: Any) -> float:
    """The slip [m] of the slope box from rest in MuJoCo itself beyond its steady creep:
    x(t_end) - v* t_end, v* = `engine_creep` (the slip while the contact forces build up, which
    the steady law does not describe). Needs the mujoco package."""
    import mujoco
    model = mujoco.MjModel.from_xml_string(mujoco_slope_xml(**settings))
    data = mujoco.MjData(model)
    for _ in range(int(round(t_end / model.opt.timestep))):
        mujoco.mj_step(model, data)
    return float(data.qpos[0]) - engine_creep("mujoco", **settings) * float(data.time)


#: The setting advise_engine chooses per engine.
ADVISED_SETTING: dict[str, str] = {"drake_continuous": "stiction_tolerance",
                                   "drake_tamsi": "stiction_tolerance",
                                   "drake_lagged": "stiction_tolerance", "mujoco": "impratio",
                                   "newton_semi_implicit": "k_f"}


def advise_engine(engine: str, max_creep: float, t_end: float, *, margin: float = 0.0,
                  settle: float | None = None, **settings: Any) -> dict[str, Any]:
    """Settings that keep the slope box's slip from rest over t_end within max_creep.

    The slip from rest is the settling slip (while the engine's contact forces build up, before
    the steady creep: `settle`) plus the steady creep v* t_end. The advised setting
    (`ADVISED_SETTING`: Drake's stiction tolerance, MuJoCo's impratio for the given cone,
    Newton's k_f) is the loosest whose creep meets max_creep / (1 + margin) - settle, rounded to
    3 significant digits toward the strict side: never more than 2x stricter than needed.
    With MuJoCo installed and settle not given, the settling slip is MuJoCo's own
    (`mujoco_settle`, measured at the advised setting, the advice then made again with it until
    the total meets the budget).

    Parameters
    ----------
    engine : str
        One of `ENGINES`.
    max_creep : float
        Largest distance the box may creep [m] (> 0).
    t_end : float
        Duration [s] (> 0).
    margin : float, optional
        Relative reserve kept free of the budget (>= 0; 0.1: advise for max_creep / 1.1).
    settle : float, optional
        The engine's settling slip from rest [m] (>= 0), as measured with the engine
        (``python -m cases.engines`` reports each run's). Not given: MuJoCo's is measured with
        MuJoCo where it is installed; for the other engines (or without MuJoCo) it is not
        budgeted, "settle" is None in the result and a UserWarning says so.
    **settings
        The engine's other settings and the scene's, as for `engine_creep` (not the advised
        one).

    Returns
    -------
    dict
        The advised setting by name, "creep" (v* t_end [m] at it), "v_star" [m/s], "settle"
        (the settling slip budgeted [m], None where it is not), "total" (creep + settle [m]),
        "budget" (max_creep / (1 + margin) [m]), and where
        it is known the cost: "timestep" [s] and "steps_per_second" [1/s] (MuJoCo: its
        timestep; Drake continuous and Newton: the largest explicit (forward or semi-implicit
        Euler) step that is stable on the law's steepest slope dF/dv in the box's stiffest
        mode, its yaw on four corner contacts, 2 m / (3 dF/dv)); None where no cost is known
        (TAMSI, lagged).

    Raises
    ------
    ValueError
        An unknown engine or setting, the advised setting given, max_creep or t_end <= 0.
    """
    if engine in ENGINE_SETTINGS and ADVISED_SETTING[engine] in settings:
        raise ValueError(f"advise_engine chooses {ADVISED_SETTING[engine]} for {engine}; "
                         f"do not pass it")
    for key, value in (("max_creep", max_creep), ("t_end", t_end)):
        if not (_real(key, value) > 0 and math.isfinite(float(value))):
            raise ValueError(f"{key} must be a finite number > 0, got {value!r}")
    if not (_real("margin", margin) >= 0 and math.isfinite(float(margin))):
        raise ValueError(f"margin must be a finite number >= 0, got {margin!r}")
    if settle is not None and not (_real("settle", settle) >= 0 and math.isfinite(float(settle))):
        raise ValueError(f"settle must be a finite number >= 0 [m], got {settle!r}")
    max_creep, t_end = float(max_creep), float(t_end)
    budget = max_creep / (1.0 + float(margin))
    _split(engine, settings)
    name = ADVISED_SETTING[engine]
    measure = settle is None and engine == "mujoco" and _have_mujoco()
    amount = 0.0 if settle is None else float(settle)
    for _ in range(4):                      # MuJoCo's settling slip depends on the setting
        if amount >= budget:
            raise ValueError(f"{engine}: the settling slip {amount:.3g} m alone exceeds the "
                             f"budget {budget:.3g} m")
        out = _advise_steady(engine, (budget - amount) / t_end, t_end, settings)
        if not measure:
            break
        amount = max(mujoco_settle(**settings, **{name: out[name]}), 0.0)
        if out["creep"] + amount <= budget:
            break
    out["settle"] = amount if (measure or settle is not None) else None
    if out["settle"] is None:
        warnings.warn(f"advise_engine: {engine}'s settling slip from rest is not budgeted (pass "
                      f"settle=, measured with the engine: python -m cases.engines)",
                      UserWarning, stacklevel=2)
    out["total"] = out["creep"] + amount
    out["budget"] = budget
    return out


def _have_mujoco() -> bool:
    try:
        import mujoco  # noqa: F401
    except ImportError:
        return False
    return True


def _advise_steady(engine: str, target: float, t_end: float,
                   settings: dict[str, Any]) -> dict[str, Any]:
    """advise_engine's choice for a steady creep speed target [m/s] (its rounding and cost)."""
    scene, _ = _split(engine, settings)
    name = ADVISED_SETTING[engine]

    def creep(x: float) -> float:
        return engine_creep(engine, **settings, **{name: x})

    if engine.startswith("drake"):                            # v* proportional to v_s
        if not math.isfinite(creep(1.0)):
            raise ValueError(f"{engine} cannot hold the box on this slope at any {name}")
        value = target / creep(1.0)
    else:
        # creep decreases with impratio / k_f, nearly as 1 / x: start from that guess, then
        # bisection in log space on a bracket around it
        if not math.isfinite(creep(1e12)):
            raise ValueError(f"{engine} cannot hold the box on this slope at any {name}")
        guess = creep(1.0) / target
        lo, hi = guess / 1.5, guess * 1.5
        while creep(lo) <= target and lo > 1e-15:
            lo /= 2
        while creep(hi) > target:
            lo, hi = hi, hi * 2
            if hi > 1e15:
                raise ValueError(f"{engine}: no {name} up to 1e15 meets the budget")
        for _ in range(30):
            mid = math.sqrt(lo * hi)
            lo, hi = (mid, hi) if creep(mid) > target else (lo, mid)
        value = hi
    # 3 significant digits, rounded toward the strict side
    digits = 10 ** (math.floor(math.log10(value)) - 2)
    steps = math.floor(value / digits) if engine.startswith("drake") else math.ceil(value / digits)
    value = float(f"{steps * digits:.3g}")
    v_star = creep(value)
    out: dict[str, Any] = {name: value, "creep": v_star * t_end, "v_star": v_star,
                           "timestep": None, "steps_per_second": None}
    _, own = _split(engine, {**settings, name: value})
    m = scene["m"]
    N = m * scene["g"] * math.cos(math.radians(scene["theta_deg"]))
    # the stiffest mode of friction on a box with four corner contacts is its yaw: a uniform box
    # (I_z = m (hx^2 + hy^2) / 3) feels 3 dF/dv / m there, three times the translation's
    yaw = 3.0
    if engine == "mujoco":
        out["timestep"] = float(own["timestep"])
    elif engine == "drake_continuous":
        slope = scene["mu_s"] * 1.875 * N / value          # max of step5' is 15/8 at x = 1/2
        out["timestep"] = 2 * m / (yaw * slope)
    elif engine == "newton_semi_implicit":
        factor = yaw if own["n_contacts"] == 4 else 1.0
        out["timestep"] = 2 * m / (factor * own["n_contacts"] * value)
    if out["timestep"] is not None:
        out["steps_per_second"] = 1.0 / out["timestep"]
    return out
